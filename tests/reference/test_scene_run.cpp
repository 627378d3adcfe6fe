// Scenes run by the reference solver (reference/run/scene_run): the scene turned into a world,
// stepped, and its outputs written in the shared format (solver/io) and read back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "reference/run/scene_run.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/scene_loader.hpp"

namespace talus::reference {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the system's temporary directory, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "talus_scene_run_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "mkdtemp failed";
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

Scene scene_from(const std::string& yaml) {
  return parse_scene(yaml, "test.yaml", ".");
}

const char* const kMaterials = R"(
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
)";

// BLAZE-DEM §5.1 through the whole path (validation/free_fall_drag/scene.yaml): a sphere falls
// from rest under gravity and quadratic drag; every trajectory frame must follow
// x(t) = (v_t^2/g) ln cosh(g t / v_t) and every probe row's kinetic energy m v(t)^2 / 2 with
// v(t) = v_t tanh(g t / v_t), within `bound` relative (the paper's error bounds: 0.1% at
// dt = 1e-3 s, 0.01% at 1e-4 s).
void check_free_fall(double time_step, double bound) {
  Scene scene = load_scene(TALUS_SOURCE_DIR "/validation/free_fall_drag/scene.yaml");
  const long long frame_every = std::llround(0.1 / time_step);  // a frame every 0.1 s
  scene.time_step = time_step;
  scene.outputs.trajectories->every = frame_every;
  scene.outputs.probes->every = frame_every / 10;
  TempDir dir;
  SceneRunSettings settings;
  settings.output_root = dir.path();
  const SceneRunReport report = run_scene(scene, settings);
  EXPECT_EQ(report.steps, std::llround(2.0 / time_step));
  // The world's time is a sum of dt: 1e-13 s of rounding at most over 2e4 steps.
  EXPECT_NEAR(report.simulated_time, 2.0, 1e-12);
  EXPECT_EQ(report.particles, 1u);

  const double g = 9.81, alpha = 0.5, radius = 0.05, density = 2000;
  const double mass = density * 4.0 / 3.0 * M_PI * radius * radius * radius;
  const double vt = std::sqrt(mass * g / alpha);
  const std::vector<TrajectoryFrame> frames =
      read_trajectory(dir.path() + "/free_fall_drag/frames");
  ASSERT_EQ(frames.size(), 21u);  // 0, 0.1, ..., 2 s
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames[k].step, static_cast<long long>(k) * frame_every);
    ASSERT_EQ(frames[k].rows.size(), 1u);
    const double t = frames[k].step * time_step;
    const double fallen = vt * vt / g * std::log(std::cosh(g * t / vt));
    // + 1e-15 m for t = 0, where both are 0.
    EXPECT_NEAR(-frames[k].rows[0].position.z, fallen, bound * fallen + 1e-15) << "t " << t;
    EXPECT_EQ(frames[k].rows[0].id, 0);
    EXPECT_EQ(frames[k].rows[0].template_index, 0);
  }
  const ProbeTable probes = read_probe_file(dir.path() + "/free_fall_drag/probes.csv");
  ASSERT_EQ(probes.header.size(), 3u);
  EXPECT_EQ(probes.header[2], "kinetic_energy");
  ASSERT_EQ(probes.rows.size(), 201u);  // every 0.01 s
  for (const std::vector<double>& row : probes.rows) {
    const double v = vt * std::tanh(g * row[0] / vt);
    const double energy = 0.5 * mass * v * v;
    // v within `bound` gives the energy within 2 bound; + 1e-15 J for t = 0.
    EXPECT_NEAR(row[2], energy, 2 * bound * energy + 1e-15) << "t " << row[0];
  }
  EXPECT_TRUE(fs::exists(dir.path() + "/free_fall_drag/frames/run.json"));
}

TEST(ReferenceSceneRun, FreeFallWithDragWithinPointOnePercentAtDt1e3) {
  check_free_fall(1e-3, 1e-3);
}

TEST(ReferenceSceneRun, FreeFallWithDragWithinPointZeroOnePercentAtDt1e4) {
  check_free_fall(1e-4, 1e-4);
}

// The world a scene makes: the initial particles in order with ids 0..n-1, the walls' triangles,
// the effects.
TEST(ReferenceSceneRun, WorldSetupFollowsTheScene) {
  const std::string yaml =
      std::string("time: {step: 1.0e-5, end: 1.0e-4}\nseed: 3\n") + kMaterials + R"(
templates:
  grain: {shape: "cube:0.01", material: glass}
particles:
  - lattice:
      template: grain
      region: {box: {min: [-0.03, -0.03, 0.01], max: [0.03, 0.03, 0.035]}}
      spacing: 0.02
      random_orientation: true
walls:
  - box: {min: [-0.05, -0.05, 0], max: [0.05, 0.05, 0.1], open_top: true, material: glass}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)";
  const Scene scene = scene_from(yaml);
  std::vector<int> template_of_body;
  const RefWorldSetup setup = world_setup(scene, template_of_body);
  const std::vector<ParticleState> particles = initial_particles(scene);
  ASSERT_EQ(particles.size(), 3u * 3u * 1u);  // floor(0.06 / 0.02) x 3 x floor(0.025 / 0.02)
  ASSERT_EQ(setup.bodies.size(), particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    EXPECT_EQ(setup.bodies[i].id, static_cast<long long>(i));
    EXPECT_EQ(setup.bodies[i].position.x(), particles[i].position.x);
    EXPECT_EQ(setup.bodies[i].position.z(), particles[i].position.z);
    EXPECT_EQ(template_of_body[i], 0);
  }
  ASSERT_EQ(setup.walls.size(), 1u);
  EXPECT_EQ(setup.walls[0].triangles.size(), 10u);  // an open-top box: 5 faces of 2 triangles
  ASSERT_TRUE(setup.effects.gravity.has_value());
  EXPECT_EQ(setup.effects.gravity->z(), -9.81);
  EXPECT_TRUE(setup.effects.contacts);
  EXPECT_EQ(setup.effects.contact, ContactModel::volume);
  EXPECT_TRUE(setup.effects.friction);
  EXPECT_EQ(setup.time_step, 1e-5);
}

// The three contact models pass to the world as they are, each volume law with its own damping
// (effects.damping unset); the energy probe, whose ledger only production keeps, is refused.
TEST(ReferenceSceneRun, ContactModelsAndTheEnergyProbe) {
  const std::string yaml = std::string("time: {step: 1.0e-5, end: 1.0e-4}\n") + kMaterials + R"(
templates:
  grain: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.1]}
effects:
  contact: CONTACT
outputs:
  probes: {every: 1, quantities: [kinetic_energy]}
)";
  for (const auto& [name, model] : {std::pair{"volume", ContactModel::volume},
                                    std::pair{"volume_paper", ContactModel::volume_paper}}) {
    std::string text = yaml;
    text.replace(text.find("CONTACT"), 7, name);
    Scene scene = scene_from(text);
    std::vector<int> template_of_body;
    const RefWorldSetup setup = world_setup(scene, template_of_body);
    EXPECT_EQ(setup.effects.contact, model);
    EXPECT_FALSE(setup.effects.damping.has_value());
    scene.outputs.probes->quantities.push_back(Probe::energy);
    EXPECT_THROW(world_setup(scene, template_of_body), std::runtime_error);
  }
}

// A feed inserts floor(rate (t - start)) particles by time t, with ids after the initial ones.
TEST(ReferenceSceneRun, FeedInsertsAtItsRate) {
  const std::string yaml = std::string("time: {step: 1.0e-3, end: 0.05}\n") + kMaterials + R"(
templates:
  ball: {sphere: 0.002, material: glass}
particles:
  - explicit:
      - {template: ball, position: [0, 0, -1]}
  - feed:
      template: ball
      region: {box: {min: [-0.05, -0.05, 0], max: [0.05, 0.05, 0.05]}}
      rate: 200
      start: 0.01
      stop: 0.04
effects:
  gravity: [0, 0, -9.81]
)";
  const Scene scene = scene_from(yaml);
  SceneRunner runner(scene, {});
  std::size_t seen_at_0025 = 0;
  while (!runner.done()) {
    runner.advance();
    // The step that starts at t inserts what is due at t: after the step ending at 0.025 s the
    // feed has run at t = 0.024 s, floor(200 * 0.014) = 2 particles.
    if (runner.step() == 25) seen_at_0025 = runner.world().bodies().size();
  }
  EXPECT_EQ(seen_at_0025, 1u + 2u);
  // At the last step (t = 0.049 s) the feed had stopped at 0.04 s: floor(200 * 0.03) = 6.
  ASSERT_EQ(runner.world().bodies().size(), 1u + 6u);
  for (std::size_t i = 0; i < runner.world().bodies().size(); ++i) {
    EXPECT_EQ(runner.world().bodies()[i].id, static_cast<long long>(i));
  }
}

// A hopper's closed outlet plate is there until outlet_opens_at, then gone.
TEST(ReferenceSceneRun, ClosedOutletOpensOnTime) {
  const std::string yaml = std::string("time: {step: 1.0e-3, end: 0.01}\n") + kMaterials + R"(
templates:
  grain: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.5]}
walls:
  - hopper: {base: [0, 0, 0], bottom_radius: 0.02, top_radius: 0.1, height: 0.1,
             outlet: closed, outlet_opens_at: 0.005, segments: 16, material: glass}
effects:
  contact: volume
)";
  const Scene scene = scene_from(yaml);
  SceneRunner runner(scene, {});
  const std::size_t closed = runner.world().wall_triangles(0).size();
  EXPECT_EQ(closed, 2u * 16u + 16u);  // the frustum's sides and a 16-triangle fan over the outlet
  while (!runner.done()) {
    const double t = runner.world().time();
    runner.advance();
    const std::size_t now = runner.world().wall_triangles(0).size();
    // The plate goes in the step that starts at or after 0.005 s (times carry ~1e-18 s rounding).
    EXPECT_EQ(now, t < 0.005 - 1e-9 ? closed : closed - 16u) << "t " << t;
  }
}

// bed_height: the highest vertex of a polyhedron along -g.
TEST(ReferenceSceneRun, BedHeightIsTheHighestVertexAgainstGravity) {
  const std::string yaml = std::string("time: {step: 1.0e-3, end: 0.01}\n") + kMaterials + R"(
templates:
  grain: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.1]}
      - template: grain
        position: [0.1, 0, 0.1]
        orientation: {axis: [1, 0, 0], degrees: 45}
effects:
  gravity: [0, 0, -9.81]
)";
  const Scene scene = scene_from(yaml);
  SceneRunner runner(scene, {});
  const double side = 0.01 / std::sqrt(3.0);  // cube:D is the circumscribed diameter
  // The first cube's top face is at 0.1 + side/2; the second, turned 45 degrees about x, reaches
  // higher, 0.1 + side/sqrt(2) (its edge). Rounding of the vertices: ~1e-17 m.
  EXPECT_NEAR(bed_height(runner.world(), Eigen::Vector3d(0, 0, -9.81)), 0.1 + side / std::sqrt(2.0),
              1e-15);
  // Measured along -g: with gravity along -x the highest point is the second cube's +x face.
  EXPECT_NEAR(bed_height(runner.world(), Eigen::Vector3d(-9.81, 0, 0)), 0.1 + side / 2, 1e-15);
}

}  // namespace
}  // namespace talus::reference
