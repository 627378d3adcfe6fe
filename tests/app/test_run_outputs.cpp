// An output directory belongs to one run, and a resume checks everything it continues (issue
// "Runs that never lose data"), through the built binary: a rerun into a used directory is
// refused (--overwrite clears it); a resume while another process holds the directory is refused
// naming the holder; pruning removes only the run's own checkpoints; a cut probe file, a changed
// mesh file or an unreadable newest checkpoint stop a resume with a message that says what to do,
// and the older checkpoint it names resumes to the uninterrupted run's bytes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/io/run_directory.hpp"
#include "tests/app/run_talus.hpp"
#include "tests/step/restart_scene.hpp"

namespace {

namespace fs = std::filesystem;
using talus_test::ProcessResult;
using talus_test::read_file;
using talus_test::run_talus;

std::string test_directory(const std::string& name) {
  return talus_test::fresh_directory("test-run-outputs", name);
}

// The restart scene (120 steps of 2e-5 s unless `steps` says otherwise) with frames every 20
// steps, checkpoints every 40, the newest `keep` kept.
std::string scene_text(int steps = 120, int keep = 5) {
  std::string text = talus_test::restart_scene_yaml();
  const auto replace = [&](const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
  };
  replace("end: 2.4e-3", "end: " + std::to_string(steps * 2.0e-5));
  replace("trajectories: {every: 1,", "trajectories: {every: 20,");
  replace("keep: 5", "keep: " + std::to_string(keep));
  return text;
}

ProcessResult run_scene(const std::string& scene, const std::string& output,
                        const std::vector<std::string>& more = {}) {
  std::vector<std::string> args{"run", "--backend", "cpu", "--quiet", "--output", output, scene};
  args.insert(args.end(), more.begin(), more.end());
  return run_talus(args);
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(TalusRunOutputs, ARerunIntoAUsedDirectoryIsRefusedOrOverwritten) {
  const std::string dir = test_directory("rerun");
  const std::string scene = talus_test::write_scene(dir, scene_text());
  ASSERT_EQ(run_scene(scene, dir + "/out").exit_code, 0);
  const std::string probes = read_file(dir + "/out/probes.csv");
  std::ofstream(dir + "/out/notes.txt") << "mine";
  const ProcessResult again = run_scene(scene, dir + "/out");
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_TRUE(has(again.err, dir + "/out holds ")) << again.err;
  EXPECT_TRUE(has(again.err, " output files of an earlier run (checkpoints/")) << again.err;
  EXPECT_TRUE(has(again.err, "or pass --overwrite to remove those files first")) << again.err;
  EXPECT_EQ(read_file(dir + "/out/probes.csv"), probes);                    // nothing of it touched
  EXPECT_EQ(talus::list_checkpoints(dir + "/out/checkpoints").size(), 2u);  // steps 40 and 80

  // --overwrite: the earlier files go, the run's are written (the same scene: the same bytes),
  // and what is not an output stays.
  fs::copy_file(dir + "/out/frames/trajectory_000000120.csv", dir + "/old_frame.csv");
  std::ofstream(dir + "/out/frames/trajectory_000000200.csv") << "an older, longer run's frame";
  const ProcessResult overwritten = run_scene(scene, dir + "/out", {"--overwrite"});
  ASSERT_EQ(overwritten.exit_code, 0) << overwritten.err;
  EXPECT_FALSE(fs::exists(dir + "/out/frames/trajectory_000000200.csv"));
  EXPECT_EQ(read_file(dir + "/out/frames/trajectory_000000120.csv"),
            read_file(dir + "/old_frame.csv"));
  EXPECT_EQ(read_file(dir + "/out/probes.csv"), probes);
  EXPECT_EQ(read_file(dir + "/out/notes.txt"), "mine");
}

TEST(TalusRunOutputs, AResumeIntoADirectoryInUseIsRefusedNamingTheHolder) {
  const std::string dir = test_directory("in_use");
  const std::string scene = talus_test::write_scene(dir, scene_text());
  ASSERT_EQ(run_scene(scene, dir + "/out").exit_code, 0);
  const std::string probes = read_file(dir + "/out/probes.csv");
  {
    // This process holds the root as a running talus would.
    const talus::OutputLock holder(dir + "/out", "pid 4242 on gpu-node-7, run 1234");
    const ProcessResult resumed = run_talus({"run", "--resume", dir + "/out/checkpoints"});
    EXPECT_EQ(resumed.exit_code, 2);
    EXPECT_TRUE(has(resumed.err, "talus: error: " + dir +
                                     "/out is in use by another talus run (pid 4242 on "
                                     "gpu-node-7, run 1234)"))
        << resumed.err;
    const ProcessResult rerun = run_scene(scene, dir + "/out", {"--overwrite"});
    EXPECT_EQ(rerun.exit_code, 2);
    EXPECT_TRUE(has(rerun.err, "is in use by another talus run")) << rerun.err;
  }
  EXPECT_EQ(read_file(dir + "/out/probes.csv"), probes);
  const ProcessResult resumed = run_talus({"run", "--resume", dir + "/out/checkpoints", "--quiet"});
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
}

// A run stopped early (--end: 100 of 200 steps, checkpoints at 40 and 80, one kept) and resumed to
// the scene's end prunes its own checkpoints as it goes, never another run's in the directory.
TEST(TalusRunOutputs, PruningRemovesOnlyTheRunsOwnCheckpoints) {
  const std::string dir = test_directory("prune");
  const std::string scene = talus_test::write_scene(dir, scene_text(200, 1));
  ASSERT_EQ(run_scene(scene, dir + "/other", {"--end", "2.0e-3"}).exit_code, 0);
  ASSERT_EQ(run_scene(scene, dir + "/out", {"--end", "2.0e-3"}).exit_code, 0);
  const std::string ours = dir + "/out/checkpoints/checkpoint_000000080.bin";
  ASSERT_EQ(talus::list_checkpoints(dir + "/out/checkpoints"), std::vector<std::string>{ours});
  const std::string foreign = dir + "/out/checkpoints/checkpoint_000000010.bin";
  fs::copy_file(dir + "/other/checkpoints/checkpoint_000000080.bin", foreign);
  ASSERT_NE(talus::checkpoint_run_id(foreign), talus::checkpoint_run_id(ours));
  const ProcessResult resumed = run_talus({"run", "--resume", dir + "/out/checkpoints", "--quiet"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(talus::list_checkpoints(dir + "/out/checkpoints"),
            (std::vector<std::string>{foreign, dir + "/out/checkpoints/checkpoint_000000160.bin"}));
}

TEST(TalusRunOutputs, AResumeRefusesAProbeFileThatEndsBeforeItsCheckpoint) {
  const std::string dir = test_directory("cut_probes");
  const std::string scene = talus_test::write_scene(dir, scene_text());
  ASSERT_EQ(run_scene(scene, dir + "/out").exit_code, 0);
  fs::remove(dir + "/out/checkpoints/checkpoint_000000080.bin");
  const std::string probes = read_file(dir + "/out/probes.csv");
  const std::string cut = probes.substr(0, probes.find('\n') + 1);  // the header alone
  std::ofstream(dir + "/out/probes.csv", std::ios::trunc) << cut;
  const ProcessResult resumed = run_talus({"run", "--resume", dir + "/out/checkpoints"});
  EXPECT_EQ(resumed.exit_code, 2);
  EXPECT_TRUE(has(resumed.err, "cannot resume probe file '" + dir + "/out/probes.csv': it holds " +
                                   std::to_string(cut.size()) +
                                   " bytes, so it ends before the checkpoint's step (the "
                                   "checkpoint of step 40 counts "))
      << resumed.err;
  EXPECT_EQ(read_file(dir + "/out/probes.csv"), cut);  // left as it was
}

// A mesh wall far below the drum (no particle reaches it) whose file gains a comment: the same
// geometry, but not the file the checkpoint's run read.
TEST(TalusRunOutputs, AResumeRefusesAChangedMeshFile) {
  const std::string dir = test_directory("mesh");
  fs::create_directories(dir + "/meshes");
  std::ofstream(dir + "/meshes/plate.obj") << "v -0.1 -0.1 -0.2\nv 0.1 -0.1 -0.2\nv 0.1 0.1 -0.2\n"
                                              "v -0.1 0.1 -0.2\nf 1 2 3\nf 1 3 4\n";
  std::string text = scene_text();
  const std::string walls = "walls:\n";
  text.replace(text.find(walls), walls.size(),
               walls + "  - mesh: {name: floor, file: meshes/plate.obj, material: glass}\n");
  const std::string scene = talus_test::write_scene(dir, text);
  const ProcessResult first = run_scene(scene, dir + "/out");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  std::ofstream(dir + "/meshes/plate.obj", std::ios::app) << "# moved later\n";
  const ProcessResult resumed = run_talus({"run", "--resume", dir + "/out/checkpoints"});
  EXPECT_EQ(resumed.exit_code, 2);
  EXPECT_TRUE(has(resumed.err, "checkpoint_000000080.bin: the mesh file '" + dir +
                                   "/meshes/plate.obj', which the scene reads, has changed "
                                   "since the checkpoint was written (its hash differs)"))
      << resumed.err;
}

// The newest checkpoint cut short (a disk that filled, a copy that stopped): the error names the
// older one and how to continue from it; continuing from it gives the uninterrupted run's files.
TEST(TalusRunOutputs, AnUnreadableNewestCheckpointNamesTheOlderOne) {
  const std::string dir = test_directory("older");
  const std::string scene = talus_test::write_scene(dir, scene_text());
  ASSERT_EQ(run_scene(scene, dir + "/whole").exit_code, 0);
  fs::copy(dir + "/whole", dir + "/copy", fs::copy_options::recursive);
  const std::string newest = dir + "/copy/checkpoints/checkpoint_000000080.bin";
  fs::resize_file(newest, fs::file_size(newest) / 2);
  const std::string older = dir + "/copy/checkpoints/checkpoint_000000040.bin";
  const ProcessResult refused = run_talus({"run", "--resume", dir + "/copy/checkpoints"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_TRUE(has(refused.err, newest + ": truncated checkpoint")) << refused.err;
  EXPECT_TRUE(has(refused.err,
                  "; an older checkpoint is there: continue from it with 'talus run "
                  "--resume " +
                      older + "'"))
      << refused.err;
  const ProcessResult resumed = run_talus({"run", "--resume", older, "--quiet"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  for (const char* file : {"/frames/run.json", "/frames/trajectory_000000120.csv", "/probes.csv",
                           "/paraview/particles.pvd"})
    EXPECT_TRUE(read_file(dir + "/whole" + file) == read_file(dir + "/copy" + file)) << file;
  // The run rewrote the newest checkpoint whole.
  EXPECT_NO_THROW(talus::read_checkpoint(newest));
}

}  // namespace
