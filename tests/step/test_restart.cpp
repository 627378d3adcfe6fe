// Restart (solver/io/checkpoint, HostStep::export_state/import_state, ProductionRunner with
// ProductionSettings::resume): a run resumed from a checkpoint equals the uninterrupted run bit for
// bit — the step's whole state (every array, both history stores), every trajectory frame, the
// probe file, the ParaView files — whether it resumes from a checkpoint in the middle of a
// finished run (whose later outputs it then rewrites, probe rows after the checkpoint dropped) or
// from the checkpoint an interrupted run wrote when it was asked to stop. And a checkpoint that
// cannot be used is refused with the reason: corrupt, truncated, another version, a changed scene,
// none at all, another scene's.
#include <gtest/gtest.h>

#include <algorithm>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/io/probes.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/step/step_test_util.hpp"
#include "tests/support/feed_scenes.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using talus_test::StepTempDir;
using talus_test::write_restart_scene;

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << path;
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every file under `a` has a twin under `b` with the same bytes, and the other way round
// (checkpoints left out: the runs keep different ones; and the run lock, which names its holder).
void expect_same_outputs(const std::string& a, const std::string& b) {
  std::vector<std::string> names_a, names_b;
  for (const auto& [root, names] : {std::pair{a, &names_a}, std::pair{b, &names_b}}) {
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
      const std::string relative = fs::relative(entry.path(), root).string();
      if (entry.is_regular_file() && relative.rfind("checkpoints", 0) != 0 &&
          relative != ".talus.lock")
        names->push_back(relative);
    }
    std::sort(names->begin(), names->end());
  }
  ASSERT_EQ(names_a, names_b);
  ASSERT_GT(names_a.size(), 120u);  // 121 frames, run.json, the probes, the ParaView files
  for (const std::string& name : names_a) {
    const std::string x = bytes_of(a + "/" + name), y = bytes_of(b + "/" + name);
    EXPECT_TRUE(x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size()) == 0) << name;
  }
}

ProductionReport run(const Scene& scene, const std::string& root,
                     std::shared_ptr<const Checkpoint> resume = nullptr,
                     std::function<bool()> stop = nullptr) {
  ProductionSettings settings;
  settings.output_root = root;
  settings.host_threads = 1;
  settings.resume = std::move(resume);
  settings.stop_requested = std::move(stop);
  return run_production(scene, settings);
}

// The step itself: 70 steps, or 30, a checkpoint's round trip through the file's bytes into a
// new step, and 40 more; every array and both history stores equal to the bit.
template <class Real>
void check_step_round_trip(const std::string& precision) {
  StepTempDir dir;
  const Scene scene = write_restart_scene(dir.path(), precision);
  HostStep<Real> whole(scene, 1), first(scene, 2);
  for (int k = 0; k < 70; ++k) whole.step();
  for (int k = 0; k < 30; ++k) first.step();
  Checkpoint written;
  put_step_state(written, first.export_state());
  const std::string path = dir.path() + "/state.bin";
  write_checkpoint(path, written);
  HostStep<Real> second(scene, 2);
  second.import_state(get_step_state<Real>(read_checkpoint(path)));
  for (int k = 0; k < 40; ++k) second.step();
  const StepState<Real> a = whole.export_state(), b = second.export_state();
  EXPECT_GT(a.pair_keys.size(), 0u) << "the scene should have pair contacts to carry over";
  EXPECT_GT(a.wall_keys.size(), 0u) << "and wall contacts";
  talus_test::expect_same_state(a, b);
}

TEST(Restart, HostStepStateRoundTripIsExactDouble) {
  check_step_round_trip<double>("double");
}

TEST(Restart, HostStepStateRoundTripIsExactFloat) {
  check_step_round_trip<float>("float");
}

// A feed into a box: 20 balls in 10 ms thrown down onto the floor; 30 ms.
const std::string kFeedScene = talus::testing::thrown_feed_scene("0.03");

// A feeding run: a checkpoint in the middle of a feed (half of its 20 balls inserted) carries the
// feeder's state (count and generator, "feeds.states"); the resumed step inserts the same balls
// at the same steps and ends equal to the uninterrupted one, to the bit.
TEST(Restart, FeedingHostStepResumesExactly) {
  StepTempDir dir;
  const Scene scene = parse_scene(kFeedScene, "feed.yaml", ".");
  HostStep<double> whole(scene, 1), first(scene, 2);
  EXPECT_EQ(whole.particle_count(), 0);
  for (int k = 0; k < 6000; ++k) whole.step();
  for (int k = 0; k < 1000; ++k) first.step();
  EXPECT_EQ(first.particle_count(), 9);  // floor(2000 * 999 * 5e-6) at the last step's start
  Checkpoint written;
  put_step_state(written, first.export_state());
  const std::string path = dir.path() + "/state.bin";
  write_checkpoint(path, written);
  HostStep<double> second(scene, 2);
  second.import_state(get_step_state<double>(read_checkpoint(path)));
  std::size_t contacts = 0;  // the resumed steps go through the landing's contacts
  for (int k = 0; k < 5000; ++k) {
    second.step();
    contacts += second.wall_contact_count() + second.pair_contact_count();
  }
  EXPECT_GT(contacts, 100u);
  EXPECT_EQ(whole.particle_count(), 20);
  const StepState<double> a = whole.export_state(), b = second.export_state();
  talus_test::expect_same_state(a, b);
  EXPECT_EQ(a.feed_states, b.feed_states);

  // A state without the feed's (another scene's) does not fit.
  StepState<double> lacking = first.export_state();
  lacking.feed_states.clear();
  HostStep<double> third(scene, 1);
  EXPECT_THROW(third.import_state(lacking), CheckpointError);
}

// The same through the runner: a feeding run's checkpoint in the middle of the feed, resumed,
// writes the same last frame and probe rows as the uninterrupted run.
TEST(Restart, FeedingRunResumesExactly) {
  StepTempDir dir;
  const std::string whole = dir.path() + "/whole", copy = dir.path() + "/copy";
  fs::create_directories(whole);
  std::ofstream(whole + "/scene.yaml")
      << kFeedScene
      << "outputs:\n  trajectories: {every: 1000, directory: frames}\n"
         "  probes: {every: 100, file: probes.csv, quantities: [kinetic_energy]}\n"
         "  checkpoint: {every: 1000, keep: 10}\n";
  const Scene scene = load_scene(whole + "/scene.yaml");
  const ProductionReport full = run(scene, whole);
  EXPECT_EQ(full.particles, 20u);
  fs::copy(whole, copy, fs::copy_options::recursive);
  for (const std::string& file : list_checkpoints(copy + "/checkpoints"))
    if (fs::path(file).filename() != "checkpoint_000001000.bin") fs::remove(file);
  const ResumePoint point = read_resume_point(copy + "/checkpoints");
  EXPECT_EQ(point.step, 1000);
  EXPECT_NE(point.checkpoint->text("feeds.states"), "");
  const ProductionReport resumed = run(scene, point.output_root, point.checkpoint);
  EXPECT_EQ(resumed.particles, 20u);
  for (const std::string name : {"frames/trajectory_000006000.csv", "probes.csv"})
    EXPECT_EQ(bytes_of(whole + "/" + name), bytes_of(copy + "/" + name)) << name;
}

TEST(Restart, ResumedRunEqualsUninterruptedRun) {
  StepTempDir dir;
  const std::string whole = dir.path() + "/whole", copy = dir.path() + "/copy";
  const Scene scene = write_restart_scene(whole);
  const ProductionReport full = run(scene, whole);
  EXPECT_EQ(full.steps, 120);
  EXPECT_GT(full.mean_contacts, 0);
  // Checkpoints at 40 and 80 (not at the end).
  const std::vector<std::string> written = list_checkpoints(whole + "/checkpoints");
  ASSERT_EQ(written.size(), 2u);
  EXPECT_EQ(fs::path(written[1]).filename(), "checkpoint_000000080.bin");

  // A copy of the finished run with its last checkpoint gone: it resumes at step 40 and writes
  // steps 41..120 again over the outputs the first run left (the probe rows after step 40 are
  // dropped first), into the copy (the checkpoint finds the output root relative to itself).
  fs::copy(whole, copy, fs::copy_options::recursive);
  fs::remove(copy + "/checkpoints/checkpoint_000000080.bin");
  fs::remove(copy + "/frames/trajectory_000000120.csv");
  const ResumePoint point = read_resume_point(copy + "/checkpoints");
  EXPECT_EQ(point.step, 40);
  EXPECT_EQ(point.output_root, fs::absolute(copy).lexically_normal().string());
  EXPECT_EQ(point.backend, "cpu");
  const ProductionReport resumed = run(scene, point.output_root, point.checkpoint);
  EXPECT_EQ(resumed.resumed_from_step, 40);
  EXPECT_EQ(resumed.steps, 120);
  EXPECT_EQ(resumed.mean_contacts, full.mean_contacts);
  expect_same_outputs(whole, copy);
  EXPECT_EQ(read_probe_file(copy + "/probes.csv").rows.size(), 121u);
}

// A stack of three soft cubes at rest on a floor holds elastic energy in its contacts, which a
// restored step reads as zero until it has evaluated its forces. The energy watchdog took the
// resumed run's reference there and, 100 steps on, the stack's unchanged elastic energy for energy
// the contacts created (bench_scenes' settled 1e4 bed stopped so on resuming). Resumed at step 300,
// the run must reach its end like the uninterrupted one: the watchdog's reference is the first
// step after the checkpoint. And the stored energy is real: far more than the run is given after
// the checkpoint (the test would not fail without it).
TEST(Restart, ResumedRestingStackIsNotTakenForEnergyCreated) {
  StepTempDir dir;
  const std::string whole = dir.path() + "/whole", copy = dir.path() + "/copy";
  fs::create_directories(whole);
  std::ofstream(whole + "/scene.yaml") << R"(time: {step: 1.0e-5, end: 6.0e-3}
materials:
  soft: {density: 2000, youngs_modulus: 2.0e5, poisson_ratio: 0.3, friction: 0.5,
         restitution: 0.05}
templates:
  cube: {shape: "cube:0.0173205", material: soft}
particles:
  - explicit:
      - {template: cube, position: [0, 0, 0.00499]}
      - {template: cube, position: [0, 0, 0.01497]}
      - {template: cube, position: [0, 0, 0.02495]}
walls:
  - plane: {name: floor, point: [0, 0, 0], normal: [0, 0, 1], size: 0.1, material: soft}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
outputs:
  probes: {every: 100, file: probes.csv, quantities: [energy]}
  checkpoint: {every: 300, keep: 2}
)";
  const Scene scene = load_scene(whole + "/scene.yaml");
  const ProductionReport full = run(scene, whole);
  ASSERT_EQ(full.steps, 600);
  fs::copy(whole, copy, fs::copy_options::recursive);
  const ResumePoint point = read_resume_point(copy + "/checkpoints");
  ASSERT_EQ(point.step, 300);
  ProductionReport resumed;
  ASSERT_NO_THROW(resumed = run(scene, point.output_root, point.checkpoint));
  EXPECT_EQ(resumed.steps, 600);
  EXPECT_EQ(bytes_of(whole + "/probes.csv"), bytes_of(copy + "/probes.csv"));
  // The elastic energy held at the end against what gravity could still give after the
  // checkpoint: the settled stack's drop over the last 300 steps.
  const ProbeTable probes = read_probe_file(whole + "/probes.csv");
  const auto column = [&](const std::string& name) {
    const auto at = std::find(probes.header.begin(), probes.header.end(), name);
    EXPECT_NE(at, probes.header.end()) << name;
    return static_cast<std::size_t>(at - probes.header.begin());
  };
  const std::size_t elastic = column("elastic_normal"), gravity = column("gravitational");
  const std::vector<double>&at_checkpoint = probes.rows.at(3), &last = probes.rows.back();
  const double given = at_checkpoint[gravity] - last[gravity] +
                       at_checkpoint[column("kinetic_translational")] +
                       at_checkpoint[column("kinetic_rotational")];
  EXPECT_GT(last[elastic], 10 * std::max(given, 0.0));
}

TEST(Restart, InterruptedRunResumesExactly) {
  StepTempDir dir;
  const std::string whole = dir.path() + "/whole", cut = dir.path() + "/cut";
  // One scene file for both (run.json names it).
  const Scene scene = write_restart_scene(dir.path());
  run(scene, whole);
  // Stopped when asked before step 58: a checkpoint at step 57, besides the one at 40.
  int asked = 0;
  const ProductionReport stopped = run(scene, cut, nullptr, [&] { return ++asked > 57; });
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_EQ(stopped.steps, 57);
  EXPECT_EQ(fs::path(stopped.last_checkpoint).filename(), "checkpoint_000000057.bin");
  EXPECT_EQ(read_probe_file(cut + "/probes.csv").rows.size(), 58u);
  const ResumePoint point = read_resume_point(cut + "/checkpoints");
  EXPECT_EQ(point.step, 57);
  const ProductionReport resumed = run(scene, point.output_root, point.checkpoint);
  EXPECT_FALSE(resumed.interrupted);
  EXPECT_EQ(resumed.steps, 120);
  expect_same_outputs(whole, cut);
}

// The checkpoint a run wrote when it was stopped at step 45, its bytes, and the run's directory.
struct WrittenRun {
  StepTempDir dir;
  std::string checkpoint, bytes;
  WrittenRun() {
    const Scene scene = write_restart_scene(dir.path());
    int asked = 0;
    run(scene, dir.path(), nullptr, [&] { return ++asked > 45; });
    checkpoint = dir.path() + "/checkpoints/checkpoint_000000045.bin";
    bytes = bytes_of(checkpoint);
  }
  void write(const std::string& text) const { std::ofstream(checkpoint) << text; }
};

void expect_refused(const std::string& directory, const std::string& part) {
  try {
    read_resume_point(directory);
    ADD_FAILURE() << "expected an error containing '" << part << "'";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(Restart, CorruptCheckpointsAreRefusedWithTheReason) {
  const WrittenRun r;
  const std::string directory = r.dir.path() + "/checkpoints";
  ASSERT_NO_THROW(read_resume_point(directory));
  std::string flipped = r.bytes;
  flipped[flipped.size() / 2] ^= 0x10;
  r.write(flipped);
  expect_refused(directory,
                 "checkpoint_000000045.bin: corrupt checkpoint (the checksum does not "
                 "match its bytes)");
  r.write(r.bytes.substr(0, r.bytes.size() - 100));
  expect_refused(directory, "truncated checkpoint");
  r.write(r.bytes.substr(0, 20));
  expect_refused(directory, "truncated checkpoint");
  r.write("not a checkpoint at all");
  expect_refused(directory, "not a talus checkpoint");
  std::string other_version = r.bytes;
  other_version[8] = 7;
  r.write(other_version);  // a damaged byte: the checksum no longer matches
  expect_refused(directory,
                 "corrupt checkpoint (the checksum does not match its bytes; its "
                 "version field reads 7)");
  // Another talus's file: its checksum matches its bytes.
  const std::size_t body = other_version.size() - sizeof(std::uint64_t);
  const std::uint64_t hash = fnv1a64(other_version.data(), body);
  std::memcpy(&other_version[body], &hash, sizeof hash);
  r.write(other_version);
  expect_refused(directory, "checkpoint format version 7; this talus reads version 1");
  r.write(r.bytes + "extra");
  expect_refused(directory, "5 bytes were appended to the checkpoint");
  r.write("");
  expect_refused(directory, "an empty file (0 bytes), not a checkpoint");
  r.write(r.bytes);
  std::ofstream(r.dir.path() + "/scene.yaml", std::ios::app) << "# edited\n";
  expect_refused(directory, "has changed since the checkpoint was written");
  expect_refused(r.dir.path() + "/nowhere", "/nowhere: no such checkpoint file or directory");
}

TEST(Restart, CheckpointOfAnotherSceneDoesNotFit) {
  const WrittenRun r;
  StepTempDir other;
  std::ofstream(other.path() + "/scene.yaml")
      << talus_test::restart_scene_yaml() << "  # another scene\n";
  Scene scene = load_scene(other.path() + "/scene.yaml");
  scene.lattices.pop_back();  // 6 particles instead of 12
  const auto checkpoint = std::make_shared<Checkpoint>(read_checkpoint(r.checkpoint));
  try {
    run(scene, other.path(), checkpoint);
    ADD_FAILURE() << "expected the checkpoint to be refused";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("does not fit the scene: 12 particles"), std::string::npos)
        << e.what();
  }
}

TEST(Restart, CheckpointFileRoundTripAndListing) {
  StepTempDir dir;
  Checkpoint c;
  c.put("values", std::vector<double>{1.5, -0.0, 1e-300});
  c.put_text("name", "drum");
  c.put_value<long long>("count", 7);
  write_checkpoint(dir.path() + "/" + checkpoint_file_name(12), c);
  write_checkpoint(dir.path() + "/" + checkpoint_file_name(3), c);
  std::ofstream(dir.path() + "/checkpoint_5.bin") << "too few digits: not listed";
  const std::vector<std::string> files = list_checkpoints(dir.path());
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(fs::path(files[0]).filename(), "checkpoint_000000003.bin");
  const Checkpoint back = read_checkpoint(files[1]);
  const std::vector<double> values = back.get<double>("values");
  ASSERT_EQ(values.size(), 3u);
  EXPECT_TRUE(std::signbit(values[1]));
  EXPECT_EQ(values[2], 1e-300);
  EXPECT_EQ(back.text("name"), "drum");
  EXPECT_EQ(back.get_value<long long>("count"), 7);
  EXPECT_THROW(back.get<float>("values"), CheckpointError);  // another element size
  EXPECT_THROW(back.text("missing"), CheckpointError);
}

}  // namespace
}  // namespace talus
