// Initial states that are not physical (solver/scene/initial_state_checks.hpp): particles through
// each other or through a wall are errors or warnings naming the ids and the scene entries, and
// states that are fine (the example scene, touching particles, particles above an open box) give
// nothing.
#include <algorithm>
#include <cmath>

#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

// Spheres of radius 5 mm and cubes of circumscribed diameter 10 mm (sides a = 10 / sqrt(3) mm,
// inscribed radius a / 2 = 2.887 mm), linear contact, no gravity. Particles and walls appended.
const std::string kPreamble = R"(time: {step: 1.0e-5, end: 0.01}
materials:
  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3, friction: 0.3, restitution: 0.9}
templates:
  ball: {sphere: 0.005, material: steel}
  cube: {shape: cube:0.01, material: steel}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 1.0}
)";

Scene load(const std::string& rest) {
  return parse_scene(kPreamble + rest, "state.yaml", scene_data_dir());
}

std::vector<std::string> warnings_of(const Scene& scene) {
  return check_initial_state(scene, initial_particles(scene));
}

std::vector<std::string> warnings_of(const std::string& rest) {
  return warnings_of(load(rest));
}

// The one warning of the check ("" and a test failure when there is not exactly one).
std::string only_warning(const std::string& rest) {
  const std::vector<std::string> w = warnings_of(rest);
  EXPECT_EQ(w.size(), 1u) << rest;
  return w.size() == 1 ? w[0] : "";
}

// The SceneError of the check (the scene itself loads).
SceneError state_error(const std::string& rest) {
  const Scene scene = load(rest);
  try {
    check_initial_state(scene, initial_particles(scene));
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "no SceneError for:\n" << rest;
  return SceneError("", 0, 0, "", "<no error>");
}

// Two explicit particles of `shape`, the second at `second` (the first at the origin).
std::string two(const std::string& shape, const std::string& second,
                const std::string& orientation = "[1, 0, 0, 0]") {
  return "particles:\n  - explicit:\n      - {template: " + shape +
         ", position: [0, 0, 0], orientation: " + orientation + "}\n      - {template: " + shape +
         ", position: " + second + "}\n";
}

TEST(InitialState, IdenticalPosesAreAnErrorNamingBothParticlesAndLines) {
  const SceneError e = state_error(two("cube", "[0, 0, 0]"));
  EXPECT_STREQ(e.what(),
               "state.yaml:11:9: particles[0].explicit[0]: particles 0 and 1 (the second of "
               "state.yaml:12:9: particles[0].explicit[1]) start with the centroid of one inside "
               "the other: centres 0 m apart (identical positions), inscribed radii 0.00289 m "
               "and 0.00289 m; the contact law cannot separate such a pair (identical poses feel "
               "no force at all, slightly shifted ones are thrown apart at hundreds of m/s); move "
               "them apart (1 such pair in all)");
  // Shifted by 1 nm: the same error, with the distance.
  EXPECT_NE(state_error(two("cube", "[1.0e-9, 0, 0]")).message().find("centres 1e-09 m apart, "),
            std::string::npos);
}

TEST(InitialState, TheErrorThresholdIsTheCentroidInsideTheOther) {
  // Spheres of radius 5 mm: the centroid of one is inside the other below 5 mm (error), the two
  // overlap below 10 mm (warning), and touch or part at 10 mm and beyond (nothing). 1 um either
  // side of each boundary, far above round-off (1e-18 m) and far below the radii.
  EXPECT_EQ(state_error(two("ball", "[0.004999, 0, 0]")).key(), "particles[0].explicit[0]");
  EXPECT_EQ(only_warning(two("ball", "[0.005001, 0, 0]")),
            "state.yaml:11:9: particles[0].explicit[0]: warning: 1 pair of particles overlaps at "
            "the start with particles of state.yaml:12:9: particles[0].explicit[1]; the contact "
            "law pushes them apart at the first step, turning the overlap's elastic energy into "
            "speed (id pairs: 0-1)");
  EXPECT_EQ(warnings_of(two("ball", "[0.009999, 0, 0]")).size(), 1u);
  EXPECT_TRUE(warnings_of(two("ball", "[0.010001, 0, 0]")).empty());
}

TEST(InitialState, PolyhedraOverlapOnlyWhereTheirBodiesDo) {
  // Face to face, cubes of side 5.774 mm: through each other at 5.0 mm (inscribed spheres meet),
  // apart at 5.9 mm although their bounding spheres (radius 5 mm) overlap.
  EXPECT_EQ(warnings_of(two("cube", "[0.005, 0, 0]")).size(), 1u);
  EXPECT_TRUE(warnings_of(two("cube", "[0.0059, 0, 0]")).empty());
  // The first turned 45 degrees about z reaches a / sqrt(2) = 4.082 mm along x, the second
  // 2.887 mm back from 6.5 mm: 0.47 mm into each other, with the centres 6.52 mm apart (beyond
  // the inscribed spheres' 5.77 mm); a corner of the first (z = 2.887 mm) lies inside the second
  // (raised by 0.5 mm, so that the corner is not on its top face).
  const std::string turned = "{axis: [0, 0, 1], degrees: 45}";
  EXPECT_EQ(warnings_of(two("cube", "[0.0065, 0, 0.0005]", turned)).size(), 1u);
  EXPECT_TRUE(warnings_of(two("cube", "[0.0075, 0, 0.0005]", turned)).empty());
}

TEST(InitialState, OverlapsAreGroupedByEntryWithTheFirstIds) {
  // Two rows of 7 spheres (spacing 10 mm), the second 7 mm beside the first along y: sphere i of
  // one overlaps sphere i of the other (centres 7 mm apart: overlapping, not inside each other),
  // and no other (12.2 mm). Seven pairs, one line, the first five listed.
  const std::string row =
      "  - lattice: {template: ball, region: {box: {min: [0, Y0, 0], max: "
      "[0.07, Y1, 0.01]}}, spacing: 0.01}\n";
  const std::string a = replaced(replaced(row, "Y0", "0"), "Y1", "0.01");
  const std::string b = replaced(replaced(row, "Y0", "0.007"), "Y1", "0.017");
  EXPECT_EQ(only_warning("particles:\n" + a + b),
            "state.yaml:10:14: particles[0].lattice: warning: 7 pairs of particles overlap at "
            "the start with particles of state.yaml:11:14: particles[1].lattice; the contact law "
            "pushes them apart at the first step, turning the overlap's elastic energy into "
            "speed (id pairs: 0-7, 1-8, 2-9, 3-10, 4-11 and 2 more)");
}

TEST(InitialState, AnExplicitParticleOnALatticePointNamesBothEntries) {
  const SceneError e = state_error(
      "particles:\n  - explicit:\n      - {template: ball, position: [0.005, 0.005, 0.005]}\n"
      "  - lattice: {template: ball, region: {box: {min: [0, 0, 0], max: [0.02, 0.01, 0.01]}}, "
      "spacing: 0.01}\n");
  EXPECT_EQ(e.key(), "particles[0].explicit[0]");
  EXPECT_NE(e.message().find("particles 0 and 1 (the second of state.yaml:12:14: "
                             "particles[1].lattice) start with the centroid of one inside the "
                             "other: centres 0 m apart (identical positions)"),
            std::string::npos)
      << e.what();
}

const std::string kBox =
    "walls:\n  - box: {min: [-0.05, -0.05, 0], max: [0.05, 0.05, 0.1], material: steel}\n";

std::string one_ball(const std::string& position) {
  return "particles:\n  - explicit:\n      - {template: ball, position: " + position + "}\n";
}

TEST(InitialState, AParticleThroughAWallFromTheInsideIsAWarning) {
  EXPECT_EQ(only_warning(kBox + one_ball("[0, 0, 0.003]")),
            "state.yaml:13:9: particles[0].explicit[0]: warning: 1 particle crosses wall "
            "'box_0' (state.yaml:10:10: walls[0].box) at the start, its centroid on the "
            "particles' side; the wall pushes it out at the first step (ids: 0)");
  // 5 mm up it touches the floor: nothing. A cube 4 mm up, turned 45 degrees about x, reaches
  // a / sqrt(2) = 4.082 mm down: its lower edge is 0.08 mm through the floor, farther from the
  // centroid than its inscribed radius (2.887 mm); the rays to that edge's corners find it.
  EXPECT_TRUE(warnings_of(kBox + one_ball("[0, 0, 0.005]")).empty());
  EXPECT_EQ(
      warnings_of(kBox + "particles:\n  - explicit:\n      - {template: cube, position: [0, 0, "
                         "0.004], orientation: {axis: [1, 0, 0], degrees: 45}}\n")
          .size(),
      1u);
}

TEST(InitialState, AParticleThroughAWallFromBehindIsAnError) {
  const SceneError e = state_error(kBox + one_ball("[0, 0, -0.003]"));
  EXPECT_STREQ(e.what(),
               "state.yaml:13:9: particles[0].explicit[0]: particle 0 crosses wall 'box_0' "
               "(state.yaml:10:10: walls[0].box) with its centroid 0.003 m behind it, on the side "
               "away from the particles: the wall's contact pushes it along the wall's normal, "
               "through the wall; place it on the particles' side (1 such particle in all)");
}

TEST(InitialState, ParticlesOutsideAClosedContainerAreAWarningOpenOnesAreNot) {
  EXPECT_EQ(only_warning(kBox + one_ball("[0, 0, -0.02]")),
            "state.yaml:13:9: particles[0].explicit[0]: warning: 1 particle lies outside the "
            "closed container 'box_0' (state.yaml:10:10: walls[0].box), which it can never enter "
            "(ids: 0)");
  // Above an open box: it may fall in. Nothing.
  EXPECT_TRUE(warnings_of(replaced(kBox, "material: steel", "open_top: true, material: steel") +
                          one_ball("[0, 0, 0.2]"))
                  .empty());
}

TEST(InitialState, ARandomFillOverlappingTheContainerWallPlacesSomeOutsideAndSaysSo) {
  // Placement keeps bounding spheres inside the fill's region and off the walls' triangles, so a
  // region across the box's side puts particles on both sides of it; those outside are named.
  const Scene scene = load(kBox +
                           "particles:\n  - random: {template: ball, region: {box: {min: [0.03, "
                           "-0.05, 0], max: [0.08, 0.05, 0.1]}}, count: 40, seed: 5}\n");
  const std::vector<ParticleState> particles = initial_particles(scene);
  const long long outside =
      std::count_if(particles.begin(), particles.end(),
                    [](const ParticleState& p) { return p.position.x > 0.05; });
  ASSERT_GT(outside, 0);  // the region is 3/5 outside the box: some land there
  const std::vector<std::string> w = check_initial_state(scene, particles);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(
      w[0].rfind("state.yaml:12:13: particles[0].random: warning: " + std::to_string(outside) +
                     " particles lie outside the closed container 'box_0'",
                 0),
      0u)
      << w[0];
}

TEST(InitialState, TouchingNeighboursOfALatticeAreNotOverlaps) {
  // Spacing = diameter: neighbours touch, their centre distances within round-off (1e-18 m) of
  // 10 mm, some of them below it; the check's tolerance (1e-8 of the radius) takes them as
  // touching. Spheres and cubes alike (a cube's bounding diameter is its space diagonal, so
  // cubes at that spacing stand apart).
  for (const std::string shape : {"ball", "cube"})
    EXPECT_TRUE(warnings_of("particles:\n  - lattice: {template: " + shape +
                            ", region: {box: {min: [0, 0, 0], max: [0.05, 0.05, 0.05]}}, "
                            "spacing: 0.01}\n")
                    .empty())
        << shape;
}

TEST(InitialState, TheExampleSceneAndTheBuiltInSceneAreClean) {
  const Scene example = load_scene(scene_data_dir() + "/example.yaml");
  EXPECT_TRUE(warnings_of(example).empty());
  const Scene builtin =
      load_scene(std::string(TALUS_SOURCE_DIR) + "/validation/dodecahedron_packing/scene.yaml");
  EXPECT_TRUE(warnings_of(builtin).empty());
}

}  // namespace
}  // namespace talus
