// `talus run --solver reference` through the built binary: the summary JSON, the files it writes,
// the progress lines and the refusals.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "solver/io/trajectory.hpp"
#include "tests/app/run_talus.hpp"
#include "tests/support/json_test_util.hpp"
#include "tests/support/test_files.hpp"

namespace {

namespace fs = std::filesystem;
using talus_test::Json;
using talus_test::parse_or_fail;
using talus_test::ProcessResult;
using talus_test::run_talus;

std::string test_directory(const std::string& name) {
  return talus_test::fresh_test_directory("test-run-command", name);
}

std::string write_scene(const std::string& dir, const std::string& text) {
  return talus_test::write_text(dir + "/scene.yaml", text);
}

// Two spheres thrown at each other along x with the linear model, no gravity: 2000 steps.
const char* const kTwoBalls = R"(time: {step: 1.0e-5, end: 0.02}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  ball: {sphere: 0.005, material: glass}
particles:
  - explicit:
      - {template: ball, position: [-0.01, 0, 0], velocity: [0.5, 0, 0]}
      - {template: ball, position: [0.01, 0, 0], velocity: [-0.5, 0, 0]}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.0}
outputs:
  trajectories: {every: 500, directory: frames}
)";

TEST(TalusRunReference, RunsTheSceneWritesFramesAndSummarises) {
  const std::string dir = test_directory("two_balls");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult run =
      run_talus({"run", "--solver", "reference", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Json summary = parse_or_fail(run.out);
  EXPECT_EQ(summary["solver"].get<std::string>(), "reference");
  EXPECT_EQ(summary["steps"].get<double>(), 2000);
  EXPECT_NEAR(summary["simulated_time"].get<double>(), 0.02, 1e-12);  // 2000 sums of dt: ~1e-15 s
  EXPECT_EQ(summary["particles"].get<double>(), 2);
  // Progress goes to stderr, at least the final line at 100%.
  EXPECT_NE(run.err.find("100.0%"), std::string::npos) << run.err;

  const std::vector<talus::TrajectoryFrame> frames = talus::read_trajectory(dir + "/out/frames");
  ASSERT_EQ(frames.size(), 5u);  // steps 0, 500, 1000, 1500, 2000
  // Elastic (eta = 0) head-on collision of equal balls: they swap velocities. The 10 mm gap
  // closes at 10 ms; the contact lasts pi sqrt(m_eff / K_N) = 0.8 ms (80 steps), so by 20 ms the
  // balls are apart. The linear spring gives its energy back up to the integrator's O(dt^2)
  // error, ~1e-4 relative at 80 steps per contact; 1e-3 m/s of 0.5 m/s is above that and far
  // below any real error (a lost contact or wrong sign is O(1)).
  const talus::TrajectoryFrame& last = frames.back();
  ASSERT_EQ(last.rows.size(), 2u);
  EXPECT_NEAR(last.rows[0].velocity.x, -0.5, 1e-3);
  EXPECT_NEAR(last.rows[1].velocity.x, 0.5, 1e-3);
  EXPECT_TRUE(fs::exists(dir + "/out/frames/run.json"));
}

TEST(TalusRunReference, QuietRunPrintsNoProgress) {
  const std::string dir = test_directory("quiet");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult run =
      run_talus({"run", "--solver=reference", "--quiet", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
}

// What the reference cannot do is refused with exit 2 and a message saying what to change; so is
// the production solver's CUDA backend, which is not built yet.
TEST(TalusRunReference, RefusesFloatPrecisionAndTheUnbuiltCudaBackend) {
  const std::string dir = test_directory("refusals");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult as_float =
      run_talus({"run", "--solver", "reference", "--precision", "float", scene});
  EXPECT_EQ(as_float.exit_code, 2);
  EXPECT_NE(as_float.err.find("double only"), std::string::npos) << as_float.err;
  const ProcessResult cuda = run_talus({"run", "--backend", "cuda", scene});
  EXPECT_EQ(cuda.exit_code, 2);
  EXPECT_NE(cuda.err.find("--backend cpu"), std::string::npos) << cuda.err;
}

// An output path that cannot be created stops the run with the path and what is in the way named
// (exit 2: the user's setting, nothing half-written under a final name): here the output root
// itself, which the run creates first to hold its lock.
TEST(TalusRunReference, UnwritableOutputNamesThePath) {
  const std::string dir = test_directory("unwritable");
  const std::string scene = write_scene(dir, kTwoBalls);
  std::ofstream(dir + "/blocker") << "a file where a directory should go";
  const ProcessResult run =
      run_talus({"run", "--solver", "reference", "--output", dir + "/blocker", scene});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("cannot create output directory '" + dir +
                         "/blocker': it is a regular file, not a directory"),
            std::string::npos)
      << run.err;
}

}  // namespace
