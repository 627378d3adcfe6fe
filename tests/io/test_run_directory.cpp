// An output root belongs to one run (solver/io/run_directory.hpp): the lock refuses a second
// holder and names the first; a new run finds an earlier run's files among others and refuses
// them, or removes exactly those with overwrite; the probe file of a resumed run must be the one
// its checkpoint counted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/run_directory.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(RunDirectory, TheLockRefusesASecondHolderAndNamesTheFirst) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "run_lock");
  {
    const OutputLock first(dir, "pid 1 on here, run A");
    ASSERT_TRUE(first.held());
    EXPECT_EQ(message_of([&] { OutputLock second(dir, "pid 2, run B"); }),
              dir +
                  " is in use by another talus run (pid 1 on here, run A); wait for it to end, "
                  "or give this run another output directory");
    // A root below it is another root: locks are per directory.
    const OutputLock nested(dir + "/inner", "run C");
    EXPECT_TRUE(nested.held());
  }
  // Released with its holder (as the kernel releases it when a process dies).
  const OutputLock again(dir, "run D");
  EXPECT_TRUE(again.held());
  EXPECT_EQ(talus_test::read_text(dir + "/.talus.lock"), "run D\n");
}

TEST(RunDirectory, RunIdsDiffer) {
  const std::string a = new_run_id(), b = new_run_id();
  EXPECT_EQ(a.size(), 16u);
  EXPECT_NE(a, b);
  const std::string holder = run_holder_description(a, "s.yaml");
  EXPECT_NE(holder.find("pid "), std::string::npos) << holder;
  EXPECT_NE(holder.find(", run " + a + ", scene s.yaml"), std::string::npos) << holder;
}

Scene scene_writing_everything() {
  const std::string yaml =
      "time: {step: 1.0e-4, end: 1}\n"
      "materials:\n  m: {density: 1000, youngs_modulus: 1e6, poisson_ratio: 0.3, friction: 0,"
      " restitution: 0.5}\n"
      "templates:\n  g: {shape: \"cube:0.01\", material: m}\n"
      "particles:\n  - explicit:\n      - {template: g, position: [0, 0, 0]}\n"
      "outputs:\n"
      "  trajectories: {every: 2, directory: frames}\n"
      "  vtk: {every: 3, directory: vtk}\n"
      "  probes: {every: 4, file: probes.csv, quantities: [kinetic_energy]}\n"
      "  checkpoint: {every: 4}\n";
  return parse_scene(yaml, "test.yaml", ".");
}

void touch(const std::string& path) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << "x";
}

TEST(RunDirectory, ANewRunRefusesAnEarlierRunsOutputsOrRemovesExactlyThose) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "run_claim");
  const Scene scene = scene_writing_everything();
  EXPECT_TRUE(claim_output_root(scene, dir, "A", false, false).held());  // empty: claimed
  const std::vector<std::string> ours = {dir + "/checkpoints/checkpoint_000000008.bin",
                                         dir + "/frames/run.json",
                                         dir + "/frames/trajectory_000000002.h5",
                                         dir + "/frames/trajectory_000000004.csv.tmp",
                                         dir + "/probes.csv",
                                         dir + "/vtk/particles.pvd",
                                         dir + "/vtk/walls_000000000.vtp"};
  const std::vector<std::string> others = {dir + "/frames/notes.txt", dir + "/scene.yaml",
                                           dir + "/vtk/picture.png",
                                           dir + "/checkpoints/checkpoint_old.txt"};
  for (const std::string& path : ours) touch(path);
  for (const std::string& path : others) touch(path);
  EXPECT_EQ(existing_outputs(scene, dir), ours);
  EXPECT_EQ(message_of([&] { claim_output_root(scene, dir, "B", false, false); }),
            dir +
                " holds 7 output files of an earlier run (checkpoints/checkpoint_000000008.bin, "
                "frames/run.json, frames/trajectory_000000002.h5, ...); a new run would mix its "
                "outputs with them. Give it another output "
                "directory (--output), continue the earlier run with 'talus run --resume' if it "
                "was interrupted, or pass --overwrite to remove those files first");
  // A resume continues them.
  EXPECT_TRUE(claim_output_root(scene, dir, "A", true, false).held());
  EXPECT_TRUE(claim_output_root(scene, dir, "B", false, true).held());
  for (const std::string& path : ours) EXPECT_FALSE(fs::exists(path)) << path;
  for (const std::string& path : others) EXPECT_TRUE(fs::exists(path)) << path;
  // While one run holds the root, another cannot claim it, not even to overwrite.
  const OutputLock held = claim_output_root(scene, dir, "C", false, false);
  EXPECT_NE(message_of([&] {
              claim_output_root(scene, dir, "D", false, true);
            }).find(" is in use by another talus run (pid "),
            std::string::npos);
  // A scene without outputs writes nothing there and claims nothing.
  Scene quiet = scene;
  quiet.outputs = Outputs{};
  EXPECT_FALSE(claim_output_root(quiet, dir, "E", false, false).held());
}

TEST(RunDirectory, CheckpointRunIdIsReadFromTheFirstSections) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "run_id");
  Checkpoint c;
  c.put_text("run.id", "0123456789abcdef");
  c.put("step.big", std::vector<double>(100000, 1.0));
  write_checkpoint(dir + "/checkpoint_000000001.bin", c);
  EXPECT_EQ(checkpoint_run_id(dir + "/checkpoint_000000001.bin"), "0123456789abcdef");
  Checkpoint old;  // before run ids
  old.put("step.big", std::vector<double>(10, 1.0));
  write_checkpoint(dir + "/checkpoint_000000002.bin", old);
  EXPECT_EQ(checkpoint_run_id(dir + "/checkpoint_000000002.bin"), "");
  EXPECT_EQ(checkpoint_run_id(dir + "/missing.bin"), "");
  // Names with more digits than a step can have are not checkpoints (no stoll overflow).
  touch(dir + "/checkpoint_1234567890123456789012.bin");
  EXPECT_EQ(list_checkpoints(dir).size(), 2u);
}

// A resumed probe file must begin with the bytes its checkpoint counted: then it is cut back to
// them; shorter (it ends before the checkpoint's step) or different (another run's), it is
// refused.
TEST(RunDirectory, AResumedProbeFileMustBeTheOneTheCheckpointCounted) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "probe_resume");
  const std::string file = dir + "/probes.csv";
  ProbeResume at;
  std::string written;
  {
    ProbeWriter writer(file, {"kinetic_energy"});
    writer.write_row(0.0, 0, {1.0});
    writer.write_row(0.1, 10, {2.0});
    at = {10, writer.bytes(), writer.hash()};
    writer.sync();
    written = talus_test::read_text(file);
    writer.write_row(0.2, 20, {3.0});  // after the checkpoint
  }
  EXPECT_EQ(at.bytes, static_cast<long long>(written.size()));
  {
    ProbeWriter resumed(file, {"kinetic_energy"}, at);
    EXPECT_EQ(talus_test::read_text(file), written);  // the row of step 20 is gone
    EXPECT_EQ(resumed.bytes(), at.bytes);
    EXPECT_EQ(resumed.hash(), at.hash);
  }
  std::ofstream(file, std::ios::trunc) << "time,step,kinetic_energy\n0,0,1\n";
  EXPECT_EQ(message_of([&] { ProbeWriter(file, {"kinetic_energy"}, at); }),
            "cannot resume probe file '" + file +
                "': it holds 31 bytes, so it ends before the checkpoint's step (the checkpoint "
                "of step 10 counts " +
                std::to_string(at.bytes) +
                " bytes of rows written by then); it was cut or replaced since, and a resumed run "
                "would leave a gap");
  std::string other = written;
  other[other.size() - 3] = '9';  // the same length, another value
  std::ofstream(file, std::ios::trunc) << other;
  EXPECT_NE(message_of([&] { ProbeWriter(file, {"kinetic_energy"}, at); })
                .find("': its rows up to the checkpoint's step are not the ones the checkpoint's "
                      "run wrote"),
            std::string::npos);
  EXPECT_EQ(talus_test::read_text(file), other);  // a refused file is left as it was
}

}  // namespace
}  // namespace talus
