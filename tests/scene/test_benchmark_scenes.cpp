// The scenes of bench_scenes (benchmarks/scene_cases.hpp, benchmarks/scenes/*.yaml): a change to
// a scene, to the loader or to the time-step advisor that would break the benchmark fails here,
// in CI, which does not build the benchmarks. Every scene file is in the table; each loads, has a
// time step that `talus run` accepts, runs long enough for the benchmark's settle, warm-up and
// timed steps, writes probes within the timed steps (their cost is part of what is measured) and
// holds the particle count its header states; the small ones' initial particles pass talus run's
// initial-state check without a warning (a lattice that reaches into a wall would warn).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "benchmarks/effect_cases.hpp"
#include "benchmarks/scene_cases.hpp"
#include "solver/contact/time_step_advisor.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/step/step_state.hpp"

namespace {

namespace fs = std::filesystem;

std::string path_of(const talus_bench::SceneCase& c) {
  return (fs::path(TALUS_SOURCE_DIR) / c.file).string();
}

// The count the header's comment names: the first "<N> regular dodecahedra" (N may have commas).
long long header_count(const std::string& path) {
  std::ifstream in(path);
  const std::regex pattern("([0-9][0-9,]*) regular dodecahedra");
  for (std::string line; std::getline(in, line) && line.rfind("#", 0) == 0;) {
    std::smatch match;
    if (std::regex_search(line, match, pattern)) {
      std::string digits = match[1].str();
      digits.erase(std::remove(digits.begin(), digits.end(), ','), digits.end());
      return std::stoll(digits);
    }
  }
  return -1;
}

TEST(BenchmarkScenes, EverySceneFileIsBenchmarked) {
  std::set<std::string> in_table;
  for (const auto& c : talus_bench::kSceneCases) {
    EXPECT_TRUE(fs::is_regular_file(path_of(c))) << c.name << ": " << c.file;
    in_table.insert(fs::path(path_of(c)).lexically_normal().string());
  }
  // bench_effects' scene, which bench_scenes does not run.
  in_table.insert(fs::path(path_of(talus_bench::kEffectsCase)).lexically_normal().string());
  const fs::path folder = fs::path(TALUS_SOURCE_DIR) / "benchmarks" / "scenes";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    EXPECT_EQ(in_table.count(entry.path().lexically_normal().string()), 1u)
        << entry.path() << " is not in benchmarks/scene_cases.hpp";
  }
  EXPECT_EQ(files, 6);  // bed_1e4, bed_1e6, drum_quasi2d, drum_1e6, hopper, effects
}

TEST(BenchmarkScenes, LoadWithAStableStepAndRunLongEnough) {
  for (const auto& c : talus_bench::kSceneCases) {
    SCOPED_TRACE(c.name);
    const talus::Scene scene = talus::load_scene(path_of(c));
    const talus::TimeStepAdvice advice = talus::advise_time_step(scene);
    EXPECT_LE(scene.time_step, advice.critical_step) << "talus run refuses this step";
    const long long needed = c.settle_steps + c.warmup_steps + std::max(c.cuda_steps, c.host_steps);
    EXPECT_GE(talus::scene_step_count(scene), needed);
    ASSERT_TRUE(scene.outputs.probes.has_value());
    // A probe in every timed window of the GPU, and of the host but for the large scenes.
    EXPECT_LE(scene.outputs.probes->every, c.cuda_steps);
    if (!c.large) {
      EXPECT_LE(scene.outputs.probes->every, c.host_steps);
    }
    EXPECT_EQ(header_count(path_of(c)), static_cast<long long>(talus::scene_particle_count(scene)));
    EXPECT_GT(c.cuda_steps, 0);
    EXPECT_GT(c.host_steps, 0);
  }
}

// The paper's numbers for the quasi-2D drum (section 3.4, Table 3) and issue 18's.
TEST(BenchmarkScenes, QuasiTwoDimensionalDrumIsThePapers) {
  const talus::Scene scene =
      talus::load_scene(std::string(TALUS_SOURCE_DIR) + "/benchmarks/scenes/drum_quasi2d.yaml");
  EXPECT_EQ(talus::scene_particle_count(scene), 300);
  EXPECT_DOUBLE_EQ(scene.time_step, 1e-5);
  ASSERT_EQ(scene.walls.size(), 1u);
  const auto* drum = std::get_if<talus::DrumWall>(&scene.walls[0].shape);
  ASSERT_NE(drum, nullptr);
  EXPECT_DOUBLE_EQ(drum->radius, 0.15);
  EXPECT_DOUBLE_EQ(drum->length, 0.011);
  EXPECT_EQ(drum->segments, 256);
  EXPECT_EQ(scene.walls[0].motion.kind, talus::WallMotion::Kind::rotation);
  EXPECT_DOUBLE_EQ(scene.walls[0].motion.rpm, 45);
}

TEST(BenchmarkScenes, SmallScenesStartWithoutWarnings) {
  for (const auto& c : talus_bench::kSceneCases) {
    if (c.large) continue;  // 1e6 particles: seconds in Release, more in Debug
    SCOPED_TRACE(c.name);
    const talus::Scene scene = talus::load_scene(path_of(c));
    const std::vector<talus::ParticleState> particles = talus::initial_particles(scene);
    EXPECT_EQ(static_cast<double>(particles.size()), talus::scene_particle_count(scene));
    const std::vector<std::string> warnings = talus::check_initial_state(scene, particles);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
}

// bench_effects' scene (benchmarks/effect_cases.hpp): what makes its table fair. It loads with a
// step talus run accepts and runs long enough; every output is written within each timed window
// (the host's is the shorter); the feed begins where the settle ends, so the settled state has
// the same particles in every variant, and inserts within each window; the drum turns a whole
// number of its polygon's sides during the settle, so the drum held still stands where the
// turning one stood.
TEST(EffectsScene, LoadsWithEveryOutputDueInEachTimedWindow) {
  const talus_bench::SceneCase& c = talus_bench::kEffectsCase;
  const talus::Scene scene = talus::load_scene(path_of(c));
  EXPECT_LE(scene.time_step, talus::advise_time_step(scene).critical_step);
  EXPECT_GE(talus::scene_step_count(scene), c.settle_steps + c.warmup_steps + c.cuda_steps);
  const std::vector<talus::ParticleState> particles = talus::initial_particles(scene);
  EXPECT_EQ(header_count(path_of(c)), static_cast<long long>(particles.size()));
  const std::vector<std::string> warnings = talus::check_initial_state(scene, particles);
  EXPECT_TRUE(warnings.empty()) << warnings.front();

  const talus::Outputs& o = scene.outputs;
  ASSERT_TRUE(o.trajectories && o.vtk && o.checkpoint && o.probes);
  for (const long long every :
       {o.trajectories->every, o.vtk->every, o.checkpoint->every, o.probes->every})
    EXPECT_LE(every, c.host_steps);
  EXPECT_EQ(o.probes->quantities.size(), 5u) << "every probe quantity the format has";

  ASSERT_EQ(scene.feeds.size(), 1u);
  const double settled = double(c.settle_steps) * scene.time_step;
  EXPECT_NEAR(scene.feeds[0].start, settled, 1e-9);
  const talus::Feeder feed(scene, 0);
  const double window = settled + double(c.warmup_steps) * scene.time_step;
  EXPECT_GT(feed.due(window + double(c.host_steps) * scene.time_step), feed.due(window));

  int moving = 0, fixed = 0;
  for (const talus::WallSpec& wall : scene.walls) {
    if (wall.motion.kind == talus::WallMotion::Kind::none) {
      ++fixed;
      continue;
    }
    ++moving;
    const auto* drum = std::get_if<talus::CylinderWall>(&wall.shape);
    ASSERT_NE(drum, nullptr) << wall.name;
    const double sides =
        std::abs(wall.motion.angular_speed()) * settled / (2 * M_PI / drum->segments);
    EXPECT_NEAR(sides, std::round(sides), 1e-6) << wall.name;
  }
  EXPECT_EQ(moving, 1);
  EXPECT_EQ(fixed, 2);
}

// What a scene simulates and writes, as names: from its step plan (the stages and arrays that
// run), its walls and its outputs.
std::set<std::string> features(const talus::Scene& scene) {
  const talus::StepPlan plan = talus::plan_step(scene);
  std::set<std::string> f;
  if (plan.gravity && plan.has(talus::Stage::gravity)) f.insert("gravity");
  if (plan.drag && plan.has(talus::Stage::drag)) f.insert("drag");
  if (plan.friction) f.insert("friction");
  if (plan.rotation && plan.arrays.angular_velocity) f.insert("rotation");
  if (plan.feed) f.insert("feed");
  for (const talus::WallSpec& wall : scene.walls) {
    const bool moves = wall.motion.kind != talus::WallMotion::Kind::none;
    if (!moves) f.insert("walls");
    if (moves && scene.effects.moving_walls) f.insert("moving_walls");
  }
  const talus::Outputs& o = scene.outputs;
  if (o.trajectories) f.insert("output_trajectories");
  if (o.vtk) f.insert("output_vtk");
  if (o.checkpoint) f.insert("output_checkpoint");
  if (o.probes) {
    f.insert("output_probes");
    for (const talus::Probe probe : o.probes->quantities)
      f.insert(std::string("output_probe_") + talus::to_string(probe));
  }
  return f;
}

TEST(EffectsScene, EachVariantLacksExactlyWhatItsNameSays) {
  const talus::Scene all = talus::load_scene(path_of(talus_bench::kEffectsCase));
  const std::vector<talus_bench::EffectVariant> variants = talus_bench::effect_variants(all);
  std::vector<std::string> names;
  for (const auto& v : variants) names.push_back(v.name);
  const std::vector<std::string> expected_names = {"all",
                                                   "without_gravity",
                                                   "without_friction",
                                                   "without_rotation",
                                                   "without_walls",
                                                   "without_moving_walls",
                                                   "without_drag",
                                                   "without_feed",
                                                   "without_output_trajectories",
                                                   "without_output_vtk",
                                                   "without_output_checkpoint",
                                                   "without_output_probes",
                                                   "without_output_probe_kinetic_energy",
                                                   "without_output_probe_wall_forces",
                                                   "without_output_probe_contact_count",
                                                   "without_output_probe_bed_height",
                                                   "without_output_probe_energy"};
  EXPECT_EQ(names, expected_names);

  const std::set<std::string> everything = features(all);
  EXPECT_EQ(everything.size(), 16u);
  for (const auto& v : variants) {
    SCOPED_TRACE(v.name);
    const talus::Scene scene = talus_bench::make_variant(all, v);
    std::set<std::string> expected = everything;
    if (v.name != "all") {
      const std::string taken = v.name.substr(std::string("without_").size());
      ASSERT_EQ(expected.erase(taken), 1u) << "no such effect or output";
      // bed_height is measured along -g: the runner refuses it without gravity.
      if (taken == "gravity") expected.erase("output_probe_bed_height");
      if (taken == "output_probes")
        for (const char* q :
             {"kinetic_energy", "wall_forces", "contact_count", "bed_height", "energy"})
          expected.erase(std::string("output_probe_") + q);
    }
    EXPECT_EQ(features(scene), expected);
    EXPECT_LE(scene.time_step, talus::advise_time_step(scene).critical_step);
    EXPECT_FALSE(scene.walls.empty()) << "the drum stays: it holds the bed";
  }
}

// Every variant's step takes the whole scene's checkpoint as bench_effects hands it over
// (checkpoint_for_variant): the arrays its plan allocates, the histories of the walls it keeps
// under their new indices, no feed state without the feed.
TEST(EffectsScene, EveryVariantResumesFromTheWholeScenesCheckpoint) {
  const talus::Scene all = talus::load_scene(path_of(talus_bench::kEffectsCase));
  talus::HostStep<double> whole(all, 1);
  talus::StepState<double> state = whole.export_state();
  // A particle against each of the three walls (drum, front, back), another against the back.
  state.wall_keys = {{5, 0}, {5, 1}, {5, 2}, {9, 2}};
  state.wall_histories.resize(state.wall_keys.size());
  for (std::size_t k = 0; k < state.wall_histories.size(); ++k)
    state.wall_histories[k].approach_speed = double(k + 1);
  talus::Checkpoint settled;
  talus::put_step_state(settled, state);
  for (const auto& v : talus_bench::effect_variants(all)) {
    SCOPED_TRACE(v.name);
    const talus::Scene scene = talus_bench::make_variant(all, v);
    talus::HostStep<double> step(scene, 1);
    const talus::Checkpoint handed = talus_bench::checkpoint_for_variant(settled, all, scene);
    ASSERT_NO_THROW(step.import_state(talus::get_step_state<double>(handed)));
    const talus::StepState<double> resumed = step.export_state();
    EXPECT_EQ(resumed.count, state.count);
    EXPECT_EQ(resumed.global_ids, state.global_ids);
    std::vector<long long> keys;
    std::vector<double> speeds;
    for (std::size_t k = 0; k < resumed.wall_keys.size(); ++k) {
      keys.insert(keys.end(), {resumed.wall_keys[k].low, resumed.wall_keys[k].high});
      speeds.push_back(resumed.wall_histories[k].approach_speed);
    }
    if (v.name == "without_walls") {  // the plates gone, the drum still wall 0
      EXPECT_EQ(keys, (std::vector<long long>{5, 0}));
      EXPECT_EQ(speeds, (std::vector<double>{1}));
    } else {
      EXPECT_EQ(keys, (std::vector<long long>{5, 0, 5, 1, 5, 2, 9, 2}));
      EXPECT_EQ(speeds, (std::vector<double>{1, 2, 3, 4}));
    }
  }
}

}  // namespace
