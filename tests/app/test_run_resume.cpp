// `talus run --resume DIR` through the built binary: a run resumed from the middle checkpoint of
// a finished run's copy rewrites its later outputs to the same bytes; SIGTERM stops a run at a
// step boundary with a checkpoint and a message, and resuming it ends where the uninterrupted run
// ends; so does --stop-after; the refusals (no checkpoint, a scene path or a fixed option or --end
// beside --resume).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "tests/app/run_talus.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/support/json_test_util.hpp"

namespace {

namespace fs = std::filesystem;
using talus_test::Json;
using talus_test::parse_or_fail;
using talus_test::ProcessResult;
using talus_test::read_file;
using talus_test::run_talus;

std::string resume_directory(const std::string& name) {
  return talus_test::fresh_directory("test-run-resume", name);
}

using talus_test::write_scene;

// The restart scene run for `steps` steps of 2e-5 s, frames every 20 steps.
std::string scene_text(int steps) {
  std::string text = talus_test::restart_scene_yaml();
  const auto replace = [&](const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
  };
  replace("end: 2.4e-3", "end: " + std::to_string(steps * 2.0e-5));
  replace("trajectories: {every: 1,", "trajectories: {every: 20,");
  return text;
}

TEST(TalusRunResume, ResumesACopyFromItsMiddleCheckpoint) {
  const std::string dir = resume_directory("copy");
  const std::string scene = write_scene(dir, scene_text(120));
  const ProcessResult first =
      run_talus({"run", "--backend", "cpu", "--quiet", "--output", dir + "/whole", scene});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  fs::copy(dir + "/whole", dir + "/copy", fs::copy_options::recursive);
  fs::remove(dir + "/copy/checkpoints/checkpoint_000000080.bin");
  fs::remove(dir + "/copy/frames/trajectory_000000120.csv");
  const ProcessResult resumed =
      run_talus({"run", "--resume", dir + "/copy/checkpoints", "--threads", "1"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("resuming " + scene + " from step 40"), std::string::npos)
      << resumed.err;
  Json summary = parse_or_fail(resumed.out);
  EXPECT_EQ(summary["resumed_from_step"].get<double>(), 40);
  EXPECT_EQ(summary["steps"].get<double>(), 120);
  EXPECT_EQ(summary["backend"].get<std::string>(), "cpu");
  for (const char* file :
       {"/frames/trajectory_000000060.csv", "/frames/trajectory_000000120.csv", "/probes.csv",
        "/paraview/particles.pvd", "/paraview/walls.pvd", "/paraview/particles_000000120.vtp"}) {
    const std::string a = read_file(dir + "/whole" + file), b = read_file(dir + "/copy" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_TRUE(a == b) << file;
  }
}

// Starts talus with `args`, stdout and stderr to files in `dir`; returns its process id.
pid_t start_talus(const std::vector<std::string>& args, const std::string& dir) {
  const std::string binary = TALUS_BINARY_DIR "/talus";
  std::vector<char*> argv{const_cast<char*>(binary.c_str())};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string out = dir + "/stdout", err = dir + "/stderr";
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(out.c_str(), "w", stdout) || !freopen(err.c_str(), "w", stderr)) _exit(126);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

TEST(TalusRunResume, SigtermStopsAtAStepWithACheckpointAndResumes) {
  const std::string dir = resume_directory("sigterm");
  const std::string scene = write_scene(dir, scene_text(3000));
  const ProcessResult whole =
      run_talus({"run", "--backend", "cpu", "--quiet", "--output", dir + "/whole", scene});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  const pid_t pid =
      start_talus({"run", "--backend", "cpu", "--quiet", "--output", dir + "/cut", scene}, dir);
  ASSERT_GT(pid, 0);
  // Once the run is under way (some probe rows, the first checkpoint), stop it.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (talus::list_checkpoints(dir + "/cut/checkpoints").empty() &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  const std::string err = read_file(dir + "/stderr");
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
    GTEST_SKIP() << "the run ended before the signal came (a very fast machine)";
  ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal instead of stopping: " << err;
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << err;
  EXPECT_NE(err.find("run interrupted by SIGTERM at step "), std::string::npos) << err;
  EXPECT_NE(err.find("continue with 'talus run --resume " + dir + "/cut/checkpoints'"),
            std::string::npos)
      << err;
  // The summary of the steps made, on stdout as an ended run's, names the same stop.
  const Json summary = parse_or_fail(read_file(dir + "/stdout"));
  const std::string at = " at step " + std::to_string(summary["steps"].get<long long>()) + " ";
  EXPECT_NE(err.find("run interrupted by SIGTERM" + at), std::string::npos) << err;
  EXPECT_NE(summary["stopped"].get<std::string>().find("interrupted by SIGTERM" + at),
            std::string::npos);

  const ProcessResult resumed = run_talus({"run", "--resume", dir + "/cut/checkpoints", "--quiet"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(parse_or_fail(resumed.out)["steps"].get<double>(), 3000);
  for (const char* file : {"/frames/run.json", "/frames/trajectory_000003000.csv", "/probes.csv"}) {
    const std::string a = read_file(dir + "/whole" + file), b = read_file(dir + "/cut" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_TRUE(a == b) << file;
  }
}

TEST(TalusRunResume, StopAfterStopsWithACheckpointAndResumes) {
  // --stop-after 1e-6: the deadline has passed before the first step, so the run stops at step 0
  // whatever the machine's speed (the one stop this test can place exactly), writes the
  // checkpoint of step 0 and exits with 75; resumed with a deadline far off, it ends where the
  // uninterrupted run ends, to the byte.
  const std::string dir = resume_directory("stop-after");
  const std::string scene = write_scene(dir, scene_text(120));
  const ProcessResult whole =
      run_talus({"run", "--backend", "cpu", "--quiet", "--output", dir + "/whole", scene});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const ProcessResult cut = run_talus({"run", "--backend", "cpu", "--quiet", "--stop-after", "1e-6",
                                       "--output", dir + "/cut", scene});
  EXPECT_EQ(cut.exit_code, 75) << cut.err;
  EXPECT_NE(cut.err.find("run stopped after --stop-after 1e-06 s at step 0 "), std::string::npos)
      << cut.err;
  EXPECT_NE(cut.err.find("continue with 'talus run --resume " + dir + "/cut/checkpoints'"),
            std::string::npos)
      << cut.err;
  // The stopped run's summary on stdout: its steps (none) and the stop's message, so that a
  // driver of sittings keeps each one's numbers.
  const Json stopped = parse_or_fail(cut.out);
  EXPECT_EQ(stopped["steps"].get<double>(), 0);
  EXPECT_NE(stopped["stopped"].get<std::string>().find("at step 0 (t = 0"), std::string::npos)
      << cut.out;
  // Resumed to --end (step 50; a run writes no checkpoint at its last step, so the scene's own
  // of step 40 is the newest), then from step 40 to the scene's end with a deadline far off. An
  // --end not after the checkpoint's step is refused.
  const ProcessResult part = run_talus({"run", "--resume", dir + "/cut/checkpoints", "--quiet",
                                        "--end", "1.0e-3", "--stop-after", "3600"});
  ASSERT_EQ(part.exit_code, 0) << part.err;
  Json summary = parse_or_fail(part.out);
  EXPECT_EQ(summary["resumed_from_step"].get<double>(), 0);
  EXPECT_EQ(summary["steps"].get<double>(), 50);
  const ProcessResult early =
      run_talus({"run", "--resume", dir + "/cut/checkpoints", "--end", "8.0e-4"});
  EXPECT_EQ(early.exit_code, 2);
  EXPECT_NE(early.err.find("--end 0.0008: step 40 of 2e-05 s, not after the checkpoint's step "
                           "40; expected an end time after 0.0008 s"),
            std::string::npos)
      << early.err;
  const ProcessResult resumed =
      run_talus({"run", "--resume", dir + "/cut/checkpoints", "--quiet", "--stop-after", "3600"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  summary = parse_or_fail(resumed.out);
  EXPECT_EQ(summary["resumed_from_step"].get<double>(), 40);
  EXPECT_EQ(summary["steps"].get<double>(), 120);
  for (const char* file : {"/frames/trajectory_000000120.csv", "/probes.csv"}) {
    const std::string a = read_file(dir + "/whole" + file), b = read_file(dir + "/cut" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_TRUE(a == b) << file;
  }
  // Refused: not a positive number of seconds; with the reference solver, which writes no
  // checkpoint.
  for (const char* bad : {"0", "-5", "soon"}) {
    const ProcessResult run = run_talus({"run", "--stop-after", bad, scene});
    EXPECT_EQ(run.exit_code, 2) << bad;
    EXPECT_NE(run.err.find(std::string("--stop-after '") + bad +
                           "': expected a positive number of seconds"),
              std::string::npos)
        << run.err;
  }
  const ProcessResult reference =
      run_talus({"run", "--solver", "reference", "--stop-after", "10", scene});
  EXPECT_EQ(reference.exit_code, 2);
  EXPECT_NE(reference.err.find("the reference solver writes none"), std::string::npos)
      << reference.err;
}

TEST(TalusRunResume, Refusals) {
  const std::string dir = resume_directory("refusals");
  const std::string scene = write_scene(dir, scene_text(120));
  ProcessResult run = run_talus({"run", "--resume", dir});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(dir + ": no checkpoint to resume from"), std::string::npos) << run.err;
  run = run_talus({"run", "--resume", dir, scene});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--resume continues the run its checkpoint names; drop the scene file"),
            std::string::npos)
      << run.err;
  run = run_talus({"run", "--resume", dir, "--precision", "float"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("drop --precision"), std::string::npos) << run.err;
  run = run_talus({"run", "--resume"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--resume expects a value"), std::string::npos) << run.err;
}

}  // namespace
