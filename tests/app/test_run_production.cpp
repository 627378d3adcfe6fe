// `talus run` with the production solver (the default) through the built binary: the host
// backend, the notice for `auto`, the summary with stage times, and the refusals.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "solver/io/trajectory.hpp"
#include "tests/app/json_reader.hpp"
#include "tests/app/run_talus.hpp"

namespace {

namespace fs = std::filesystem;
using talus_test::Json;
using talus_test::parse_or_fail;
using talus_test::ProcessResult;
using talus_test::run_talus;

std::string production_directory(const std::string& name) {
  const fs::path dir = fs::path(TALUS_BINARY_DIR) / "test-run-production" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string write_scene(const std::string& dir, const std::string& text) {
  const std::string path = dir + "/scene.yaml";
  std::ofstream(path) << text;
  return path;
}

// Two spheres thrown at each other along x, linear model, elastic: 2000 steps.
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

TEST(TalusRunProduction, CpuBackendRunsAndSummarises) {
  const std::string dir = production_directory("cpu");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult run = run_talus({"run", "--backend", "cpu", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json summary = parse_or_fail(run.out);
  EXPECT_EQ(summary["solver"].text, "talus");
  EXPECT_EQ(summary["backend"].text, "cpu");
  EXPECT_EQ(summary["steps"].value, 2000);
  EXPECT_EQ(summary["particles"].value, 2);
  // The contact lasts pi sqrt(m_eff / K_N) = 0.8 ms of the 20 ms: about 80 of 2000 steps with one
  // contact, a mean of about 0.04 per step.
  EXPECT_GT(summary["mean_contacts_per_step"].value, 0.02);
  EXPECT_LT(summary["mean_contacts_per_step"].value, 0.08);
  EXPECT_EQ(summary["stage_seconds"]["pair_contacts"].kind, Json::number);
  EXPECT_EQ(summary["stage_seconds"].members.count("gravity"), 0u);  // not in the scene
  EXPECT_GT(summary["peak_memory_bytes"].value, 0);
  EXPECT_EQ(run.err.find("no GPU backend"), std::string::npos) << run.err;
  // Elastic head-on collision of equal balls: they swap velocities (1e-3 of 0.5 m/s: above the
  // integrator's O(dt^2) energy error at 80 steps per contact, far below a wrong sign).
  const std::vector<talus::TrajectoryFrame> frames = talus::read_trajectory(dir + "/out/frames");
  ASSERT_EQ(frames.size(), 5u);
  EXPECT_NEAR(frames.back().rows[0].velocity.x, -0.5, 1e-3);
  EXPECT_NEAR(frames.back().rows[1].velocity.x, 0.5, 1e-3);
}

// `auto` without a GPU backend runs on the host and says so in one line.
TEST(TalusRunProduction, AutoBackendFallsBackToCpuWithANotice) {
  const std::string dir = production_directory("auto");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult run = run_talus({"run", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("talus run: no GPU backend available yet; running on the host (cpu)\n"),
            std::string::npos)
      << run.err;
}

// The CUDA backend and what the host step cannot do yet are refused with exit 2 and what to do.
TEST(TalusRunProduction, RefusesCudaAndFeeds) {
  const std::string dir = production_directory("refusals");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult cuda = run_talus({"run", "--backend", "cuda", scene});
  EXPECT_EQ(cuda.exit_code, 2);
  EXPECT_NE(cuda.err.find("CUDA backend is not built yet"), std::string::npos) << cuda.err;

  std::string fed_text = kTwoBalls;
  const std::string list = "particles:\n";
  fed_text.insert(fed_text.find(list) + list.size(),
                  "  - feed: {template: ball, region: {box: {min: [0, 0, 0.1], max: [0.1, 0.1, "
                  "0.2]}}, rate: 100}\n");
  const std::string feed = write_scene(dir, fed_text);
  const ProcessResult fed = run_talus({"run", "--quiet", "--output", dir + "/out", feed});
  EXPECT_EQ(fed.exit_code, 2) << fed.err;
  EXPECT_NE(fed.err.find("--solver reference"), std::string::npos) << fed.err;
}

}  // namespace
