// The production solver (solver/step, host backend) against the reference solver (reference/)
// on the same scenes: the same touching pairs at every step and the same positions within 1e-8
// relative over the stated horizon. The two share the scene loader and the output files only:
// geometry, force laws and integration are independent implementations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "reference/run/scene_run.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/step/step_test_util.hpp"
#include "tests/support/feed_scenes.hpp"

namespace talus::reference {
namespace {

struct Agreement {
  long long steps = 0;
  long long contact_steps = 0;       // steps with at least one contact (pair or wall)
  long long contact_mismatches = 0;  // steps whose pair or wall contact counts differ
  double position_error = 0;         // max over steps and particles, relative (see below)
  double orientation_error = 0;      // max |q_p - q_r| (sign-fixed), unitless
  double velocity_error = 0;         // max |v_p - v_r| / (|v_r| + speed scale)
};

std::size_t reference_contacts(const RefWorld& world, bool walls) {
  std::size_t n = 0;
  for (const RefContact& c : world.contacts()) n += (c.wall >= 0) == walls ? 1 : 0;
  return n;
}

// Both solvers stepped side by side over the whole scene. Position error of a particle:
// |x_p - x_r| / max(|x_r|, length), `length` the scene's particle size, so that a particle near
// the origin is measured against its size rather than against 0.
Agreement compare_solvers(const Scene& scene, double length, double speed) {
  SceneRunner reference(scene, SceneRunSettings{});
  ProductionRunner production(scene, ProductionSettings{});
  Agreement a;
  while (!reference.done()) {
    reference.advance();
    production.advance();
    ++a.steps;
    const std::size_t ref_pairs = reference_contacts(reference.world(), false);
    const std::size_t ref_walls = reference_contacts(reference.world(), true);
    a.contact_steps += ref_pairs + ref_walls > 0 ? 1 : 0;
    a.contact_mismatches +=
        ref_pairs != production.pair_contacts() || ref_walls != production.wall_contacts() ? 1 : 0;
    const std::vector<TrajectoryRow> rows = production.rows();
    const std::vector<RefBody>& bodies = reference.world().bodies();
    EXPECT_EQ(rows.size(), bodies.size());
    for (std::size_t i = 0; i < std::min(rows.size(), bodies.size()); ++i) {
      const RigidBody& r = bodies[i].state;
      const Vec3d xr(r.position.x(), r.position.y(), r.position.z());
      const Vec3d vr(r.velocity.x(), r.velocity.y(), r.velocity.z());
      a.position_error =
          std::max(a.position_error, norm(rows[i].position - xr) / std::max(norm(xr), length));
      a.velocity_error =
          std::max(a.velocity_error, norm(rows[i].velocity - vr) / (norm(vr) + speed));
      const Eigen::Quaterniond& q = r.orientation;
      const Quatd& p = rows[i].orientation;
      const double s = p.w * q.w() + p.x * q.x() + p.y * q.y() + p.z * q.z() < 0 ? -1 : 1;
      a.orientation_error =
          std::max(a.orientation_error,
                   std::sqrt(std::pow(s * p.w - q.w(), 2) + std::pow(s * p.x - q.x(), 2) +
                             std::pow(s * p.y - q.y(), 2) + std::pow(s * p.z - q.z(), 2)));
    }
  }
  return a;
}

Scene scene_from(const std::string& yaml) {
  return parse_scene(yaml, "test.yaml", ".");
}

const char* const kGlass = R"(
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
)";

// The tolerance of every comparison: the brief's 1e-8 relative. The two solvers round
// differently (Eigen vs hand-written arithmetic, exact CGAL overlap vs the dual-space overlap in
// double, whose volume and centroid carry ~1e-13 relative round-off), and a contact amplifies
// such differences by a factor that stays far below 1e5 over these short horizons.
constexpr double kTolerance = 1e-8;

void expect_agreement(const Agreement& a, long long min_contact_steps) {
  EXPECT_EQ(a.contact_mismatches, 0);
  EXPECT_GE(a.contact_steps, min_contact_steps);  // the horizon really covers a contact
  EXPECT_LT(a.position_error, kTolerance);
  EXPECT_LT(a.orientation_error, kTolerance);
  EXPECT_LT(a.velocity_error, 1e-6);  // velocities: the contact's stiff force, 100x looser
  std::printf("steps %lld  contact steps %lld  position %.3g  orientation %.3g  velocity %.3g\n",
              a.steps, a.contact_steps, a.position_error, a.orientation_error, a.velocity_error);
}

// Free fall with drag (validation/free_fall_drag): no contacts, the integrator and body forces.
TEST(ProductionVsReference, FreeFallWithDragAgrees) {
  Scene scene = load_scene(TALUS_SOURCE_DIR "/validation/free_fall_drag/scene.yaml");
  scene.outputs = Outputs{};
  const Agreement a = compare_solvers(scene, 0.05, 1.0);
  EXPECT_EQ(a.steps, 2000);
  // No contact at all: the same arithmetic up to the order of operations, 1e-14.
  EXPECT_LT(a.position_error, 1e-13);
  EXPECT_LT(a.velocity_error, 1e-13);
}

// Two spheres, linear model, an oblique impact with friction and rotation: 2 ms, the whole
// contact (about 1 ms) and the separation.
TEST(ProductionVsReference, TwoSpheresLinearObliqueWithFrictionAndRotation) {
  const Scene scene = scene_from(std::string("time: {step: 1.0e-6, end: 2.0e-3}\n") + kGlass + R"(
templates:
  ball: {sphere: 0.005, material: glass}
particles:
  - explicit:
      - {template: ball, position: [-0.0052, 0.002, 0], velocity: [1.0, 0, 0],
         angular_velocity: [0, 0, 30]}
      - {template: ball, position: [0.0052, -0.002, 0], velocity: [-1.0, 0.1, 0]}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.005, 1.0), 100);
}

// Two spheres, a volume law (the lens), oblique, friction (the tangential spring with history),
// rotation, restitution 0.5: Eq. 15's damping on the default law's k_n (`volume`), the
// calibrated damping (`volume_paper`).
Scene two_spheres_volume(const std::string& model) {
  return scene_from(std::string("time: {step: 1.0e-6, end: 2.0e-3}\n") + kGlass + R"(
templates:
  ball: {sphere: 0.005, material: glass}
  small: {sphere: 0.003, material: glass}
particles:
  - explicit:
      - {template: ball, position: [-0.0051, 0.001, 0], velocity: [1.0, 0, 0],
         angular_velocity: [0, 10, 30]}
      - {template: small, position: [0.0032, -0.001, 0], velocity: [-1.0, 0.2, 0]}
effects:
  contact: )" + model +
                    R"(
  friction: true
  rotation: true
)");
}

TEST(ProductionVsReference, TwoSpheresVolumeObliqueWithFrictionAndRotation) {
  expect_agreement(compare_solvers(two_spheres_volume("volume"), 0.005, 1.0), 100);
}

TEST(ProductionVsReference, TwoSpheresVolumePaperObliqueWithFrictionAndRotation) {
  expect_agreement(compare_solvers(two_spheres_volume("volume_paper"), 0.005, 1.0), 100);
}

// A cube and an octahedron, a volume law (the dual-space overlap against the reference's exact
// CGAL overlap), corner-first oblique impact with friction and rotation: 3 ms.
Scene two_polyhedra_volume(const std::string& model) {
  return scene_from(std::string("time: {step: 1.0e-6, end: 3.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
  octa: {shape: "octahedron:0.012", material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.0062, 0.001, 0.0005], velocity: [1.0, 0, 0],
         orientation: {axis: [1, 1, 0], degrees: 30}, angular_velocity: [0, 5, 20]}
      - {template: octa, position: [0.0062, -0.001, 0], velocity: [-1.0, 0.2, 0],
         orientation: {axis: [0, 1, 1], degrees: 20}}
effects:
  contact: )" + model +
                    R"(
  friction: true
  rotation: true
)");
}

TEST(ProductionVsReference, TwoCubesVolumeObliqueWithFrictionAndRotation) {
  expect_agreement(compare_solvers(two_polyhedra_volume("volume"), 0.01, 1.0), 100);
}

TEST(ProductionVsReference, TwoCubesVolumePaperObliqueWithFrictionAndRotation) {
  expect_agreement(compare_solvers(two_polyhedra_volume("volume_paper"), 0.01, 1.0), 100);
}

// A sphere against a cube, linear model, friction and rotation (BLAZE-DEM's simple contact: the
// closest point on the cube for both solvers).
TEST(ProductionVsReference, SphereAndCubeLinearWithFrictionAndRotation) {
  const Scene scene = scene_from(std::string("time: {step: 1.0e-6, end: 2.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
  ball: {sphere: 0.004, material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.0052, 0.001, 0.0005], velocity: [1.0, 0, 0],
         orientation: {axis: [1, 1, 0], degrees: 30}, angular_velocity: [0, 5, 20]}
      - {template: ball, position: [0.0052, -0.001, 0], velocity: [-1.0, 0.2, 0]}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.01, 1.0), 100);
}

// A cloud of `n` particles of the given templates, jittered on a lattice of spacing `spacing`
// and thrown towards the centre with speed about `speed`: many simultaneous contacts.
std::string cloud(int n, double spacing, double speed, const std::vector<std::string>& templates,
                  std::uint64_t seed, int side = 3) {
  std::mt19937_64 random(seed);
  const auto uniform = [&] { return double(random() >> 11) * 0x1.0p-53 - 0.5; };
  std::ostringstream out;
  out.precision(17);
  out << "particles:\n  - explicit:\n";
  for (int k = 0; k < n; ++k) {
    const double mid = 0.5 * (side - 1);
    const double x = spacing * (k % side - mid + 0.1 * uniform());
    const double y = spacing * ((k / side) % side - mid + 0.1 * uniform());
    const double z = spacing * (k / (side * side) - mid + 0.1 * uniform());
    out << "      - {template: " << templates[k % templates.size()] << ", position: [" << x << ", "
        << y << ", " << z << "], velocity: [" << -speed * x / spacing + speed * uniform() << ", "
        << -speed * y / spacing << ", " << -speed * z / spacing << "], orientation: {axis: ["
        << uniform() << ", 1, " << uniform() << "], degrees: " << 90 * uniform()
        << "}, angular_velocity: [" << 10 * uniform() << ", " << 10 * uniform() << ", "
        << 10 * uniform() << "]}\n";
  }
  return out.str();
}

// 20 particles, linear model, spheres and cubes of two sizes mixed, friction and rotation: 4 ms.
TEST(ProductionVsReference, TwentyMixedParticlesLinear) {
  const Scene scene = scene_from(std::string("time: {step: 1.0e-6, end: 4.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  ball: {sphere: 0.005, material: glass}
  small: {sphere: 0.004, material: glass}
)" + cloud(20, 0.012, 1.0, {"cube", "ball", "small"}, 7) +
                                 R"(
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.01, 1.0), 100);
}

// 20 polyhedra, volume model, cubes and octahedra, friction and rotation: 3 ms at dt = 2e-6 s
// (short, since the reference's exact overlap is slow for every touching pair and step:
// benchmarks/history/README.md).
TEST(ProductionVsReference, TwentyPolyhedraVolume) {
  const Scene scene = scene_from(std::string("time: {step: 2.0e-6, end: 3.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  octa: {shape: "octahedron:0.011", material: glass}
)" + cloud(20, 0.011, 1.0, {"cube", "octa"}, 11) +
                                 R"(
effects:
  contact: volume
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.01, 1.0), 100);
}

// A tilted cube dropped on a plane wall, a volume law, friction and rotation: it lands on an edge,
// rocks and slides (the area-weighted wall contact with its history keyed by {id, wall}); 15 ms.
Scene cube_dropped_on_a_plane(const std::string& model) {
  return scene_from(std::string("time: {step: 5.0e-6, end: 1.5e-2}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: cube, position: [0, 0, 0.0075], velocity: [0.2, 0, -0.5],
         orientation: {axis: [1, 0.3, 0], degrees: 25}}
walls:
  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.1, material: glass}
effects:
  gravity: [0, 0, -9.81]
  contact: )" + model +
                    R"(
  friction: true
  rotation: true
)");
}

TEST(ProductionVsReference, CubeDroppedOnAPlaneVolume) {
  expect_agreement(compare_solvers(cube_dropped_on_a_plane("volume"), 0.01, 0.5), 100);
}

TEST(ProductionVsReference, CubeDroppedOnAPlaneVolumePaper) {
  expect_agreement(compare_solvers(cube_dropped_on_a_plane("volume_paper"), 0.01, 0.5), 100);
}

// Two cubes and a sphere in a box that moves by `motion`, linear model, gravity, friction and
// rotation, until `end` (s).
Scene particles_in_a_moving_box(const std::string& motion, const std::string& end) {
  return scene_from("time: {step: 2.0e-6, end: " + end + "}\n" + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
  ball: {sphere: 0.005, material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.006, 0.001, 0.0065], velocity: [-0.3, 0, -0.2],
         orientation: {axis: [1, 0.3, 0], degrees: 25}}
      - {template: cube, position: [0.007, -0.002, 0.007], velocity: [0.1, 0.2, -0.3],
         orientation: {axis: [0, 1, 1], degrees: 40}}
      - {template: ball, position: [0.0, 0.01, 0.0055], velocity: [0.2, 0.3, 0]}
walls:
  - box:
      min: [-0.015, -0.015, 0]
      max: [0.015, 0.015, 0.03]
      open_top: true
      material: glass
      motion: )" + motion +
                    R"(
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
}

// The box's walls translate: several facets per wall, particles across facet edges, the moving
// walls' velocity at the contact point; 20 ms.
TEST(ProductionVsReference, ParticlesInAMovingBoxLinear) {
  const Scene scene =
      particles_in_a_moving_box("{translation: {velocity: [0.05, 0.02, 0]}}", "2.0e-2");
  expect_agreement(compare_solvers(scene, 0.01, 0.5), 100);
}

// The box shaken (an oscillation along a tilted direction: 1 mm, 50 Hz, one cycle from 2 ms, a
// peak acceleration of 10 g): the wall's velocity at the contact point is the oscillation's at
// the step's time (each solver its own formula); 30 ms.
TEST(ProductionVsReference, ParticlesInAShakenBoxLinear) {
  const Scene scene = particles_in_a_moving_box(
      "{oscillation: {direction: [0, 0.6, 0.8], amplitude: 0.001, frequency: 50, start: 0.002, "
      "cycles: 1}}",
      "3.0e-2");
  expect_agreement(compare_solvers(scene, 0.01, 0.5), 100);
}

// A cube resting on a plane that is tapped once (0.2 mm, 60 Hz from 1 ms: 2.9 g), a volume law
// with friction and rotation: thrown up at about 0.07 m/s, it lands again on the plane back at
// its place after some 15 ms and rocks; 50 ms.
TEST(ProductionVsReference, CubeOnATappedPlaneVolume) {
  const Scene scene = scene_from(std::string("time: {step: 5.0e-6, end: 5.0e-2}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: cube, position: [0, 0, 0.00502], velocity: [0.05, 0, 0],
         orientation: {axis: [0, 0, 1], degrees: 10}}
walls:
  - plane:
      point: [0, 0, 0]
      normal: [0, 0, 1]
      size: 0.1
      material: glass
      motion:
        oscillation: {direction: [0, 0, 1], amplitude: 0.0002, frequency: 60, start: 0.001,
                      cycles: 1}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.01, 0.5), 100);
}

// 20 particles (two cubes in opposite corners, spheres of two sizes) thrown together inside a
// box, linear model, gravity, friction and rotation: pair and wall contacts at once; 6 ms. The
// cubes never touch each other: for two polyhedra the linear model's contact point differs by
// design between the solvers (the reference takes the exact overlap's centroid, production the
// supporting-feature rule of geometry/simple_contact.hpp; reference/contact/contact_geometry.hpp
// says why), so their torques, and then their trajectories, agree only to about |F| times the
// patch size, not to 1e-8.
TEST(ProductionVsReference, TwentyMixedParticlesInABoxLinear) {
  std::vector<std::string> names;
  for (int k = 0; k < 20; ++k)
    names.push_back(k == 0 || k == 19 ? "cube" : k % 2 ? "ball" : "small");
  const Scene scene = scene_from(std::string("time: {step: 2.0e-6, end: 6.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  ball: {sphere: 0.005, material: glass}
  small: {sphere: 0.004, material: glass}
walls:
  - box: {min: [-0.019, -0.019, -0.019], max: [0.019, 0.019, 0.019], material: glass}
)" + cloud(20, 0.012, 1.0, names, 5) +
                                 R"(
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.01, 1.0), 100);
}

// A feed (scene/feeder.hpp) into a box: one initial ball, then 2000 balls per second for 10 ms
// (20 balls) placed at random in a region above the floor and thrown down at 0.5 m/s onto it,
// linear model, gravity, friction and rotation, 30 ms (6000 steps). Both solvers ask their own
// Feeder at the start of every step with their own positions: the same particles at the same
// steps (the same count after every step, ids after the initial ball), and positions within
// kTolerance over the whole horizon, through the wall and pair contacts of the landing.
TEST(ProductionVsReference, FeedIntoABoxLinear) {
  const Scene scene = scene_from(std::string("time: {step: 5.0e-6, end: 0.03}\n") + kGlass +
                                 testing::kBallFeedScene);
  // The count after each step: the initial ball and what the feed had due at the step's start.
  {
    const Feeder feeder(scene, 0);
    ProductionRunner production(scene, ProductionSettings{});
    SceneRunner reference(scene, SceneRunSettings{});
    long long mismatches = 0;
    while (!production.done()) {
      const double start = reference.world().time();
      production.advance();
      reference.advance();
      const std::size_t n = production.rows().size();
      EXPECT_EQ(n, reference.world().bodies().size());
      mismatches += n != 1u + static_cast<std::size_t>(feeder.due(start)) ? 1 : 0;
    }
    EXPECT_EQ(mismatches, 0);
    const std::vector<TrajectoryRow> rows = production.rows();
    ASSERT_EQ(rows.size(), 21u);  // floor(2000 * 0.01) = 20 fed
    for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i].id, (long long)i);
  }
  expect_agreement(compare_solvers(scene, 0.003, 0.5), 100);
}

// A domain box (docs/scenes.md): two balls bounce in a box while four beside it, thrown down,
// leave the box's floor behind and then the domain; both solvers remove them at the same step
// (the counts agree after every step) and go on alike with the two left.
TEST(ProductionVsReference, BallsLeavingTheDomainAreRemovedLinear) {
  const Scene scene = scene_from(std::string("time: {step: 5.0e-6, end: 0.02}\n") + kGlass + R"(
templates:
  ball: {sphere: 0.003, material: glass}
walls:
  - box: {min: [-0.01, -0.01, 0], max: [0.01, 0.01, 0.03], material: glass, open_top: true}
particles:
  - explicit:
      - {template: ball, position: [0, 0, 0.0031]}
      - {template: ball, position: [0.001, 0.0005, 0.01], velocity: [0, 0, -0.5]}
  - lattice:
      template: ball
      region: {box: {min: [0.02, 0, 0], max: [0.032, 0.006, 0.006]}}
      spacing: 0.006
      velocity: [0, 0, -1]
domain: {min: [-0.02, -0.02, -0.004], max: [0.05, 0.02, 0.05]}
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  {
    ProductionRunner production(scene, ProductionSettings{});
    SceneRunner reference(scene, SceneRunSettings{});
    ASSERT_EQ(reference.world().bodies().size(), 4u);
    while (!production.done()) {
      production.advance();
      reference.advance();
      ASSERT_EQ(production.rows().size(), reference.world().bodies().size())
          << "step " << reference.step();
    }
    // The lattice's two balls (ids 2, 3; 3 mm up at 1 m/s) pass z = -4 mm within 7 ms.
    ASSERT_EQ(production.rows().size(), 2u);
    EXPECT_EQ(production.rows()[1].id, 1);
  }
  expect_agreement(compare_solvers(scene, 0.003, 1.0), 100);
}

// The files: both solvers write trajectory frames and probes (kinetic energy, pair contacts, bed
// height, wall forces) for two cubes on a plane, volume model; the production files must match
// the reference's: the same frames and rows, positions within 1e-8 relative, probe values within
// 1e-6 relative to the largest of their column (wall forces carry the contact's stiff force).
TEST(ProductionVsReference, OutputFilesAgree) {
  const Scene scene = scene_from(std::string("time: {step: 5.0e-6, end: 1.0e-2}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: cube, position: [0, 0, 0.0055], velocity: [0.1, 0, -0.3],
         orientation: {axis: [1, 0.3, 0], degrees: 10}}
      - {template: cube, position: [0.0105, 0.002, 0.006], velocity: [-0.2, 0, -0.2],
         orientation: {axis: [0, 1, 0.2], degrees: 15}}
walls:
  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.1, material: glass}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
outputs:
  trajectories: {every: 200, directory: frames}
  probes: {every: 100, file: probes.csv,
           quantities: [kinetic_energy, contact_count, bed_height, wall_forces]}
)");
  talus_test::StepTempDir ref_dir, prod_dir;
  SceneRunSettings ref_settings;
  ref_settings.output_root = ref_dir.path();
  run_scene(scene, ref_settings);
  ProductionSettings prod_settings;
  prod_settings.output_root = prod_dir.path();
  run_production(scene, prod_settings);

  const std::vector<TrajectoryFrame> ref = read_trajectory(ref_dir.path() + "/frames");
  const std::vector<TrajectoryFrame> prod = read_trajectory(prod_dir.path() + "/frames");
  ASSERT_EQ(ref.size(), 11u);  // steps 0, 200, ..., 2000
  ASSERT_EQ(prod.size(), ref.size());
  for (std::size_t f = 0; f < ref.size(); ++f) {
    EXPECT_EQ(prod[f].step, ref[f].step);
    ASSERT_EQ(prod[f].rows.size(), ref[f].rows.size());
    for (std::size_t i = 0; i < ref[f].rows.size(); ++i) {
      const TrajectoryRow& r = ref[f].rows[i];
      const TrajectoryRow& p = prod[f].rows[i];
      EXPECT_EQ(p.id, r.id);
      EXPECT_EQ(p.template_index, r.template_index);
      EXPECT_LT(norm(p.position - r.position) / std::max(norm(r.position), 0.01), kTolerance);
      EXPECT_LT(norm(p.angular_velocity - r.angular_velocity),
                1e-6 * (1 + norm(r.angular_velocity)));
    }
  }
  const ProbeTable ref_probes = read_probe_file(ref_dir.path() + "/probes.csv");
  const ProbeTable prod_probes = read_probe_file(prod_dir.path() + "/probes.csv");
  EXPECT_EQ(prod_probes.header, ref_probes.header);
  ASSERT_EQ(prod_probes.rows.size(), ref_probes.rows.size());
  ASSERT_EQ(ref_probes.header.size(), 2u + 3u + 6u);
  double wall_fz_max = 0;
  for (std::size_t c = 2; c < ref_probes.header.size(); ++c) {
    double scale = 0;
    for (const auto& row : ref_probes.rows) scale = std::max(scale, std::abs(row[c]));
    if (ref_probes.header[c] == "wall_plane_0_fz") wall_fz_max = scale;
    for (std::size_t k = 0; k < ref_probes.rows.size(); ++k) {
      EXPECT_NEAR(prod_probes.rows[k][c], ref_probes.rows[k][c], 1e-6 * scale + 1e-15)
          << ref_probes.header[c] << " row " << k;
    }
  }
  EXPECT_GT(wall_fz_max, 0.0);  // the plane really carried the cubes
}

// 200 spheres of two sizes thrown together inside a box under gravity, linear model, friction
// and rotation (the broad phase's grid against the reference's brute force, many simultaneous
// pair and wall contacts): 4 ms.
TEST(ProductionVsReference, TwoHundredSpheresInABoxLinear) {
  const Scene scene = scene_from(std::string("time: {step: 2.0e-6, end: 4.0e-3}\n") + kGlass + R"(
templates:
  ball: {sphere: 0.005, material: glass}
  small: {sphere: 0.004, material: glass}
walls:
  - box: {min: [-0.036, -0.036, -0.036], max: [0.036, 0.036, 0.036], material: glass}
)" + cloud(200, 0.0115, 1.0, {"ball", "small"}, 3, 6) +
                                 R"(
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  expect_agreement(compare_solvers(scene, 0.01, 1.0), 100);
}

}  // namespace
}  // namespace talus::reference
