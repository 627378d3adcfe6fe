// The scenes of bench_scenes (benchmarks/scene_cases.hpp, benchmarks/scenes/*.yaml): a change to
// a scene, to the loader or to the time-step advisor that would break the benchmark fails here,
// in CI, which does not build the benchmarks. Every scene file is in the table; each loads, has a
// time step that `talus run` accepts, runs long enough for the benchmark's settle, warm-up and
// timed steps, writes probes within the timed steps (their cost is part of what is measured) and
// holds the particle count its header states; the small ones' initial particles pass talus run's
// initial-state check without a warning (a lattice that reaches into a wall would warn).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "benchmarks/scene_cases.hpp"
#include "solver/contact/time_step_advisor.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_loader.hpp"

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
  const fs::path folder = fs::path(TALUS_SOURCE_DIR) / "benchmarks" / "scenes";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    EXPECT_EQ(in_table.count(entry.path().lexically_normal().string()), 1u)
        << entry.path() << " is not in benchmarks/scene_cases.hpp";
  }
  EXPECT_EQ(files, 5);  // bed_1e4, bed_1e6, drum_quasi2d, drum_1e6, hopper
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

}  // namespace
