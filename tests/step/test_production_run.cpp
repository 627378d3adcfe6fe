// Scenes run by the production solver's host step (solver/run/production_run): the free fall
// with drag of BLAZE-DEM §5.1 against its closed form, in double and float, and the outputs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "solver/io/probes.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

using talus_test::StepTempDir;

// validation/free_fall_drag/scene.yaml at time step dt: every trajectory frame must follow
// x(t) = (v_t^2/g) ln cosh(g t / v_t) and every probe's kinetic energy m v(t)^2 / 2 with
// v(t) = v_t tanh(g t / v_t), within `bound` relative: the paper's bounds, 0.1% at dt = 1e-3 s
// and 0.01% at 1e-4 s (velocity Verlet with the drag at the predicted velocity is second order,
// so both hold with a wide margin; float adds ~1e-7 relative per step, 2e4 steps at most).
void check_free_fall(double time_step, double bound, Precision precision) {
  Scene scene = load_scene(TALUS_SOURCE_DIR "/validation/free_fall_drag/scene.yaml");
  const long long frame_every = std::llround(0.1 / time_step);
  scene.time_step = time_step;
  scene.precision = precision;
  scene.outputs.trajectories->every = frame_every;
  scene.outputs.probes->every = frame_every / 10;
  StepTempDir dir;
  ProductionSettings settings;
  settings.output_root = dir.path();
  const ProductionReport report = run_production(scene, settings);
  EXPECT_EQ(report.steps, std::llround(2.0 / time_step));
  EXPECT_NEAR(report.simulated_time, 2.0, 1e-12);  // a sum of 2e4 dt: 1e-13 s of rounding
  EXPECT_EQ(report.particles, 1u);
  EXPECT_EQ(report.mean_contacts, 0.0);
  ASSERT_EQ(report.stage_seconds.size(), 5u);  // integrate x2, clear, gravity, drag
  EXPECT_GT(report.peak_memory_bytes, 0);

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
    EXPECT_NEAR(-frames[k].rows[0].position.z, fallen, bound * fallen + 1e-15) << "t " << t;
    const double v = vt * std::tanh(g * t / vt);
    EXPECT_NEAR(-frames[k].rows[0].velocity.z, v, bound * v + 1e-15) << "t " << t;
  }
  const ProbeTable probes = read_probe_file(dir.path() + "/free_fall_drag/probes.csv");
  ASSERT_EQ(probes.rows.size(), 201u);  // every 0.01 s
  for (const std::vector<double>& row : probes.rows) {
    const double v = vt * std::tanh(g * row[0] / vt);
    const double energy = 0.5 * mass * v * v;
    // v within `bound` gives the energy within 2 bound; + 1e-15 J for t = 0.
    EXPECT_NEAR(row[2], energy, 2 * bound * energy + 1e-15) << "t " << row[0];
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/free_fall_drag/frames/run.json"));
}

TEST(ProductionRun, FreeFallWithDragWithinPointOnePercentAtDt1e3) {
  check_free_fall(1e-3, 1e-3, Precision::float64);
}

TEST(ProductionRun, FreeFallWithDragWithinPointZeroOnePercentAtDt1e4) {
  check_free_fall(1e-4, 1e-4, Precision::float64);
}

// In float the positions carry ~1e-7 relative round-off per step; over 2000 steps that stays
// well inside the 0.1% bound of dt = 1e-3.
TEST(ProductionRun, FreeFallWithDragInFloatWithinPointOnePercentAtDt1e3) {
  check_free_fall(1e-3, 1e-3, Precision::float32);
}

// The same collision of two tilted cubes (volume model, friction, rotation) in float and in
// double: float rounds each step's state at ~6e-8 relative and the overlap's volume at
// ~1e-6 relative (its round-off scale is 64 eps times the size); over the 4000 steps of the
// contact that stays below 1e-4 of the cube size in position, while a wrong float instantiation
// (a lost contact, a wrong constant) would be off by the whole impact, ~1e-3 m.
TEST(ProductionRun, FloatFollowsDoubleThroughACollision) {
  const std::string yaml = R"(time: {step: 2.0e-6, end: 8.0e-3}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  cube: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.0062, 0.001, 0.0005], velocity: [1.0, 0, 0],
         orientation: {axis: [1, 1, 0], degrees: 30}, angular_velocity: [0, 5, 20]}
      - {template: cube, position: [0.0062, -0.001, 0], velocity: [-1.0, 0.2, 0],
         orientation: {axis: [0, 1, 1], degrees: 20}}
effects:
  contact: volume
  friction: true
  rotation: true
)";
  Scene as_double = talus_test::scene_from(yaml);
  Scene as_float = talus_test::scene_from(yaml);
  as_float.precision = Precision::float32;
  ProductionRunner d(as_double, ProductionSettings{});
  ProductionRunner f(as_float, ProductionSettings{});
  long long contact_steps = 0;
  while (!d.done()) {
    d.advance();
    f.advance();
    contact_steps += d.pair_contacts();
  }
  EXPECT_GT(contact_steps, 100);
  const std::vector<TrajectoryRow> rd = d.rows(), rf = f.rows();
  ASSERT_EQ(rd.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT(norm(rf[i].position - rd[i].position), 1e-6) << i;
    EXPECT_LT(norm(rf[i].velocity - rd[i].velocity), 1e-3) << i;
  }
  // The collision really happened: the first cube lost about half its speed along x.
  EXPECT_LT(rd[0].velocity.x, 0.9);
}

}  // namespace
}  // namespace talus
