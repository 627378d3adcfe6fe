// `talus run` with the production solver (the default) through the built binary: the host
// backend and its threads, the notice for `auto`, the summary with stage times, and the
// refusals.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/io/trajectory.hpp"
#include "tests/app/run_talus.hpp"
#include "tests/support/json_test_util.hpp"
#include "tests/support/test_files.hpp"

namespace {

using talus_test::Json;
using talus_test::parse_or_fail;
using talus_test::ProcessResult;
using talus_test::run_talus;

std::string production_directory(const std::string& name) {
  return talus_test::fresh_directory("test-run-production", name);
}

using talus_test::write_scene;

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
  Json summary = parse_or_fail(run.out);
  EXPECT_EQ(summary["solver"].get<std::string>(), "talus");
  EXPECT_EQ(summary["backend"].get<std::string>(), "cpu");
  EXPECT_GE(summary["host_threads"].get<double>(), 1);  // OpenMP's default: this machine's cores
  EXPECT_EQ(summary["steps"].get<double>(), 2000);
  EXPECT_EQ(summary["particles"].get<double>(), 2);
  // The contact lasts pi sqrt(m_eff / K_N) = 0.8 ms of the 20 ms: about 80 of 2000 steps with one
  // contact, a mean of about 0.04 per step.
  EXPECT_GT(summary["mean_contacts_per_step"].get<double>(), 0.02);
  EXPECT_LT(summary["mean_contacts_per_step"].get<double>(), 0.08);
  EXPECT_TRUE(summary["stage_seconds"]["pair_contacts"].is_number());
  EXPECT_FALSE(summary["stage_seconds"].contains("gravity"));  // not in the scene
  EXPECT_GT(summary["peak_memory_bytes"].get<double>(), 0);
  EXPECT_FALSE(summary.contains("cuda_graphs"));    // the CUDA step's alone
  EXPECT_FALSE(summary.contains("stages_beside"));  // the host runs its stages in turn
  // The steps after the first, timed alone: 1999 of them, within the run's wall time, their
  // stages' seconds no more than the whole run's.
  EXPECT_EQ(summary["steady"]["steps"].get<double>(), 1999);
  EXPECT_GT(summary["steady"]["seconds"].get<double>(), 0);
  EXPECT_LT(summary["steady"]["seconds"].get<double>(), summary["wall_seconds"].get<double>());
  EXPECT_LE(summary["steady"]["stage_seconds"]["pair_contacts"].get<double>(),
            summary["stage_seconds"]["pair_contacts"].get<double>());
  EXPECT_EQ(run.err.find("running on the host"), std::string::npos) << run.err;
  // Elastic head-on collision of equal balls: they swap velocities (1e-3 of 0.5 m/s: above the
  // integrator's O(dt^2) energy error at 80 steps per contact, far below a wrong sign).
  const std::vector<talus::TrajectoryFrame> frames = talus::read_trajectory(dir + "/out/frames");
  ASSERT_EQ(frames.size(), 5u);
  EXPECT_NEAR(frames.back().rows[0].velocity.x, -0.5, 1e-3);
  EXPECT_NEAR(frames.back().rows[1].velocity.x, 0.5, 1e-3);
}

// `auto` takes the CUDA backend where this talus has one and a device is usable; otherwise it
// runs on the host and says so in one line, with the reason.
TEST(TalusRunProduction, AutoBackendUsesTheGpuOrFallsBackWithANotice) {
  const std::string dir = production_directory("auto");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult run = run_talus({"run", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Json summary = parse_or_fail(run.out);
  const std::string notice = "talus run: no usable GPU backend (";
  if (summary["backend"].get<std::string>() == "cuda") {
    EXPECT_EQ(run.err.find(notice), std::string::npos) << run.err;
  } else {
    EXPECT_EQ(summary["backend"].get<std::string>(), "cpu");
    const std::size_t at = run.err.find(notice);
    ASSERT_NE(at, std::string::npos) << run.err;
    const std::size_t line_end = run.err.find('\n', at);
    ASSERT_NE(line_end, std::string::npos);
    // The notice names the host's thread count, as the summary does.
    const std::string threads =
        std::to_string(static_cast<int>(summary["host_threads"].get<double>()));
    EXPECT_NE(run.err.substr(at, line_end - at).find("); running on the host (cpu, " + threads),
              std::string::npos)
        << run.err;
  }
}

// `--threads N` runs the host step on N threads: the summary says so, and the frames are the
// same as on one thread (the step's bits do not depend on the thread count:
// tests/step/test_host_threads.cpp checks that on a bed that uses the threads).
TEST(TalusRunProduction, ThreadsOptionSetsTheHostThreads) {
  const std::string dir = production_directory("threads");
  const std::string scene = write_scene(dir, kTwoBalls);
  std::vector<std::vector<talus::TrajectoryFrame>> frames;
  for (const char* threads : {"1", "3"}) {
    const ProcessResult run = run_talus({"run", "--quiet", "--backend", "cpu", "--threads", threads,
                                         "--output", dir + "/t" + threads, scene});
    ASSERT_EQ(run.exit_code, 0) << run.err;
#ifdef _OPENMP
    EXPECT_EQ(parse_or_fail(run.out)["host_threads"].get<double>(), std::stoi(threads));
#else
    EXPECT_EQ(parse_or_fail(run.out)["host_threads"].get<double>(), 1);  // a build without OpenMP
#endif
    frames.push_back(talus::read_trajectory(dir + "/t" + threads + "/frames"));
  }
  ASSERT_EQ(frames[0].size(), frames[1].size());
  for (std::size_t f = 0; f < frames[0].size(); ++f) {
    for (std::size_t i = 0; i < frames[0][f].rows.size(); ++i) {
      EXPECT_EQ(frames[0][f].rows[i].position.x, frames[1][f].rows[i].position.x);
      EXPECT_EQ(frames[0][f].rows[i].velocity.x, frames[1][f].rows[i].velocity.x);
    }
  }
  // The reference solver is serial: --threads is refused rather than ignored.
  const ProcessResult reference =
      run_talus({"run", "--solver", "reference", "--threads", "2", scene});
  EXPECT_EQ(reference.exit_code, 2) << reference.err;
  EXPECT_NE(reference.err.find("--threads"), std::string::npos) << reference.err;
}

// `--backend cuda` runs on the GPU where it can, with the same outputs as the host (the same
// frames, velocities within round-off); elsewhere it is refused with exit 2 and what to do.
TEST(TalusRunProduction, CudaBackendRunsLikeTheHostOrIsRefused) {
  const std::string dir = production_directory("cuda");
  const std::string scene = write_scene(dir, kTwoBalls);
  const ProcessResult cuda =
      run_talus({"run", "--backend", "cuda", "--output", dir + "/gpu", scene});
  if (cuda.exit_code == 2) {
    EXPECT_NE(cuda.err.find("--backend cpu"), std::string::npos) << cuda.err;
    return;
  }
  ASSERT_EQ(cuda.exit_code, 0) << cuda.err;
  const Json gpu = parse_or_fail(cuda.out);
  EXPECT_EQ(gpu["backend"].get<std::string>(), "cuda");
  // Two balls, no walls, no feed: the steps that keep the pair list (all but its few builds) run
  // as graph launches, captured at least once; none can overrun (no walls). Unless the
  // environment turns graphs off (TALUS_CUDA_GRAPHS=0, or TALUS_CUDA_SYNC's launch by launch).
  const char* graphs = std::getenv("TALUS_CUDA_GRAPHS");
  const char* sync = std::getenv("TALUS_CUDA_SYNC");
  if ((graphs == nullptr || std::string(graphs) != "0") &&
      (sync == nullptr || std::string(sync) != "1")) {
    EXPECT_GT(gpu["cuda_graphs"]["steps"].get<double>(), 1000);
    EXPECT_GE(gpu["cuda_graphs"]["captures"].get<double>(), 1);
  }
  EXPECT_EQ(gpu["cuda_graphs"]["aborted"].get<double>(), 0);
  EXPECT_FALSE(gpu.contains("stages_beside"));  // no walls: no wall stage beside the pairs
  const ProcessResult cpu = run_talus({"run", "--backend", "cpu", "--output", dir + "/cpu", scene});
  ASSERT_EQ(cpu.exit_code, 0) << cpu.err;
  const std::vector<talus::TrajectoryFrame> g = talus::read_trajectory(dir + "/gpu/frames");
  const std::vector<talus::TrajectoryFrame> c = talus::read_trajectory(dir + "/cpu/frames");
  ASSERT_EQ(g.size(), c.size());
  for (std::size_t f = 0; f < g.size(); ++f) {
    EXPECT_EQ(g[f].step, c[f].step);
    ASSERT_EQ(g[f].rows.size(), c[f].rows.size());
    for (std::size_t i = 0; i < c[f].rows.size(); ++i) {
      // 1e-12 m/s of 0.5: the same arithmetic but for nvcc's fused multiply-adds.
      EXPECT_NEAR(g[f].rows[i].velocity.x, c[f].rows[i].velocity.x, 1e-12);
    }
  }
}

// outputs.vtk: a ParaView frame at every trajectory frame's step, listed in particles.pvd; the
// two balls drawn as surfaces (the default for a small run); no walls, so no walls series.
// tests/io/vtk_readback.py reads such files back with VTK and checks their values.
TEST(TalusRunProduction, WritesParaViewFramesBesideTheTrajectories) {
  const std::string dir = production_directory("vtk");
  const std::string scene =
      write_scene(dir, std::string(kTwoBalls) + "  vtk: {every: 500, directory: pv}\n");
  const ProcessResult run = run_talus({"run", "--quiet", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Json outputs = parse_or_fail(run.out)["outputs"];
  ASSERT_EQ(outputs.size(), 2u);
  EXPECT_EQ(outputs[1].get<std::string>(), dir + "/out/pv");
  EXPECT_EQ(talus_test::file_names(dir + "/out/pv"),
            (std::vector<std::string>{"particles.pvd", "particles_000000000.vtp",
                                      "particles_000000500.vtp", "particles_000001000.vtp",
                                      "particles_000001500.vtp", "particles_000002000.vtp"}));
  const std::string pvd = talus_test::read_text(dir + "/out/pv/particles.pvd");
  // One DataSet a frame, at its time: step * 1e-5 s, summed step by step (round-off of 1e-16
  // relative a step).
  std::vector<double> times;
  const std::string key = "timestep=\"";
  for (std::size_t at = pvd.find(key); at != std::string::npos; at = pvd.find(key, at + 1))
    times.push_back(std::stod(pvd.substr(at + key.size())));
  ASSERT_EQ(times.size(), 5u);
  for (std::size_t f = 0; f < times.size(); ++f) EXPECT_NEAR(times[f], 0.005 * f, 1e-15);
  // Two spheres of 6 bands of 12 segments: 62 points and 72 faces each.
  const std::string frame = talus_test::read_text(dir + "/out/pv/particles_000002000.vtp");
  EXPECT_NE(frame.find("NumberOfPoints=\"124\""), std::string::npos);
  EXPECT_NE(frame.find("NumberOfPolys=\"144\""), std::string::npos);
}

// A feed runs on the host step: the particle it inserts is counted at the end, and the summary
// gives each feed's progress; one that fell behind is told on stderr.
TEST(TalusRunProduction, HostStepRunsFeeds) {
  const std::string dir = production_directory("feeds");
  std::string fed_text = kTwoBalls;
  const std::string list = "particles:\n";
  fed_text.insert(fed_text.find(list) + list.size(),
                  "  - feed: {template: ball, region: {box: {min: [0, 0, 0.1], max: [0.1, 0.1, "
                  "0.2]}}, rate: 100}\n");
  const std::string feed = write_scene(dir, fed_text);
  const ProcessResult fed = run_talus({"run", "--backend", "cpu", "--output", dir + "/out", feed});
  ASSERT_EQ(fed.exit_code, 0) << fed.err;
  // 100 per second from 0 until the last step's start, 0.01999 s: floor(1.999) = 1 more.
  const Json summary = parse_or_fail(fed.out);
  EXPECT_EQ(summary["particles"].get<double>(), 3);
  ASSERT_EQ(summary["feeds"].size(), 1u);
  EXPECT_EQ(summary["feeds"][0]["inserted"].get<double>(), 1);
  EXPECT_EQ(summary["feeds"][0]["due"].get<double>(), 1);
  EXPECT_EQ(fed.err.find("fell behind"), std::string::npos) << fed.err;
  // A region with room for one ball (its centres' box 1 mm wide) at 1000 a second, the balls
  // thrown at no speed: the first stays and blocks it; floor(19.99) = 19 due, 1 inserted, and
  // the run says so on stderr (with --quiet too), naming the feed's place in the scene.
  std::string blocked_text = kTwoBalls;
  blocked_text.insert(blocked_text.find(list) + list.size(),
                      "  - feed: {template: ball, region: {box: {min: [0, 0, 0.1], max: [0.011, "
                      "0.011, 0.111]}}, rate: 1000}\n");
  const std::string blocked_scene = write_scene(dir, blocked_text);
  const ProcessResult blocked = run_talus(
      {"run", "--backend", "cpu", "--quiet", "--output", dir + "/blocked", blocked_scene});
  ASSERT_EQ(blocked.exit_code, 0) << blocked.err;
  const Json b = parse_or_fail(blocked.out);
  EXPECT_EQ(b["feeds"][0]["inserted"].get<double>(), 1);
  EXPECT_EQ(b["feeds"][0]["due"].get<double>(), 19);
  EXPECT_EQ(b["particles"].get<double>(), 3);
  EXPECT_NE(blocked.err.find("the feed fell behind: 1 of the 19 particles due"), std::string::npos)
      << blocked.err;
  EXPECT_NE(blocked.err.find(blocked_scene), std::string::npos) << blocked.err;
  // Without --quiet the progress lines say it while the run goes on (the last one at the end).
  const ProcessResult told =
      run_talus({"run", "--backend", "cpu", "--output", dir + "/told", blocked_scene});
  ASSERT_EQ(told.exit_code, 0) << told.err;
  EXPECT_NE(told.err.find("steps/s"), std::string::npos) << told.err;
  EXPECT_NE(told.err.find("feeds behind: 1 of 19 due inserted\n"), std::string::npos) << told.err;
}

// The setup's parts, each told on stderr as it ends and summarised in order as setup_seconds: a
// new run's (the scene read, the initial particles made and checked, the step built, step 0),
// a resumed run's (the scene, the step, the checkpoint restored); --quiet tells none. The
// runner's parts lie within wall_seconds (which starts with the runner), so their sum cannot
// exceed it; the command's own parts come before it.
TEST(TalusRunProduction, SetupPartsAreToldAndSummarised) {
  const std::string dir = production_directory("setup");
  std::string text = kTwoBalls;
  text += "  checkpoint: {every: 1000, directory: checkpoints}\n";
  const std::string scene = write_scene(dir, text);
  const ProcessResult run = run_talus({"run", "--backend", "cpu", "--output", dir + "/out", scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // In the order written (nlohmann::json would sort the keys).
  const auto summary = nlohmann::ordered_json::parse(run.out);
  const auto& setup = summary["setup_seconds"];
  std::vector<std::string> parts;
  for (auto it = setup.begin(); it != setup.end(); ++it) {
    parts.push_back(it.key());
    EXPECT_GE(it.value().get<double>(), 0) << it.key();
  }
  EXPECT_EQ(parts,
            (std::vector<std::string>{"scene", "initial_particles", "step", "first_forces"}));
  EXPECT_LE(setup["step"].get<double>() + setup["first_forces"].get<double>(),
            summary["wall_seconds"].get<double>());
  // Told in order, each before the first progress line.
  const std::size_t read = run.err.find("talus run: setup: the scene and its walls read in ");
  const std::size_t made =
      run.err.find("talus run: setup: 2 initial particles made and checked in ");
  const std::size_t built = run.err.find("talus run: setup: the step built in ");
  const std::size_t first = run.err.find("talus run: setup: step 0's contacts and outputs in ");
  const std::size_t progress = run.err.find("talus run: 100.0%");
  ASSERT_NE(read, std::string::npos) << run.err;
  ASSERT_NE(progress, std::string::npos) << run.err;
  EXPECT_LT(read, made) << run.err;
  EXPECT_LT(made, built) << run.err;
  EXPECT_LT(built, first) << run.err;
  EXPECT_LT(first, progress) << run.err;

  const ProcessResult resumed =
      run_talus({"run", "--resume", dir + "/out/checkpoints", "--backend", "cpu", "--end", "0.03"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto again = nlohmann::ordered_json::parse(resumed.out);
  parts.clear();
  for (auto it = again["setup_seconds"].begin(); it != again["setup_seconds"].end(); ++it)
    parts.push_back(it.key());
  EXPECT_EQ(parts, (std::vector<std::string>{"scene", "step", "restore"}));
  EXPECT_NE(resumed.err.find("talus run: setup: the checkpoint restored in "), std::string::npos)
      << resumed.err;

  const ProcessResult quiet = run_talus(
      {"run", "--backend", "cpu", "--quiet", "--overwrite", "--output", dir + "/out", scene});
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("talus run: setup:"), std::string::npos) << quiet.err;
  EXPECT_TRUE(parse_or_fail(quiet.out)["setup_seconds"].contains("initial_particles"));
}

}  // namespace
