// The setup of a large scene on the host: a random fill placed (solver/scene/initial_particles,
// random_fill_particles) and the initial-state check (check_initial_state), per particle. The
// scene is the scaling study's (experiments/scaling/run_scaling.py): dodecahedra of 1 cm placed
// at random in a box 2 m tall whose side makes their bounding spheres fill 0.25 of it, with
// random orientations, in an open box of generated plane walls. A run of 2e7 such particles
// placed them twice on one core (~17 us a particle, the check aside) before this benchmark's
// change; the fill now tests batches of candidates on every thread.
//
// feed_attempt: a fed silo's feed, called as a step calls it while the feed is due.
//
//   bench_setup [--benchmark_filter=fill/particles:1000000/]   (threads 1 and all)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "solver/core/host_parallel.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/step/feeding.hpp"

namespace {

talus::Scene scaling_scene(long long count) {
  const double diameter = 0.01, height = 2.0, fraction = 0.25;
  const double sphere = M_PI / 6 * diameter * diameter * diameter;
  const double side = std::sqrt(count * sphere / fraction / height);
  const std::string s = std::to_string(side), h = std::to_string(height);
  const std::string text = R"(time: {step: 8.0e-5, end: 8.0e-5}
seed: 3
materials:
  resin: {density: 1200, youngs_modulus: 1.0e7, poisson_ratio: 0.3, friction: 0.3,
          restitution: 0.5}
templates:
  grain: {shape: dodecahedron:0.01, material: resin}
particles:
  - random:
      template: grain
      region: {box: {min: [0, 0, 0], max: [)" +
                           s + ", " + s + ", " + h + R"(]}}
      count: )" + std::to_string(count) +
                           R"(
      random_orientation: true
walls:
  - box: {min: [-0.001, -0.001, -0.001], max: [)" +
                           std::to_string(side + 0.001) + ", " + std::to_string(side + 0.001) +
                           ", " + std::to_string(height + 0.5) +
                           R"(], open_top: true, material: resin}
effects: {gravity: [0, 0, -9.81], contact: volume}
)";
  return talus::parse_scene(text, "bench_setup.yaml", ".");
}

// The fill alone, on `threads` threads (state.range(1); 0: all) in batches of state.range(2)
// (0: the default).
void fill(benchmark::State& state) {
  const talus::Scene scene = scaling_scene(state.range(0));
  const std::vector<talus::WallMesh> walls = talus::make_wall_meshes(scene);
  const int threads = talus::host_thread_count(int(state.range(1)));
  double seconds = 0;
  for (auto _ : state) {
    const auto begin = std::chrono::steady_clock::now();
    std::vector<talus::ParticleState> particles;
    talus::random_fill_particles(scene, scene.random_fills.at(0), walls, particles,
                                 talus::FillWork{threads, int(state.range(2))});
    benchmark::DoNotOptimize(particles.data());
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  }
  state.counters["threads"] = threads;
  state.counters["us_per_particle"] = 1e6 * seconds / double(state.iterations() * state.range(0));
}

// What `talus run` does before building the solver: the particles made and checked.
void made_and_checked(benchmark::State& state) {
  const talus::Scene scene = scaling_scene(state.range(0));
  double seconds = 0;
  for (auto _ : state) {
    const auto begin = std::chrono::steady_clock::now();
    const std::vector<talus::ParticleState> particles = talus::initial_particles(scene);
    benchmark::DoNotOptimize(talus::check_initial_state(scene, particles).size());
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  }
  state.counters["threads"] = talus::host_thread_count(0);
  state.counters["us_per_particle"] = 1e6 * seconds / double(state.iterations() * state.range(0));
}

// A silo's feed as a fed run calls it every step it is due (CudaStep and HostStep, feeding.hpp):
// a bin 0.84 m across and 4.2 m tall (the silo study at scale 0.4, experiments/silo/) meshed as
// a band of 96 sides and state.range(1) rows, `particles` (state.range(0)) mineral-sized grains
// at random below the feed, and the feed's region under the top packed on a lattice, so that
// every call tries and places nothing (a feed that has fallen behind, as the silo's, fed "as
// fast as it can", is most steps). The time of one call: what such a step pays on the host.
std::string silo_band_obj(int rows) {
  const int sides = 96;
  const double radius = 0.42, height = 4.24;
  std::string text;
  for (int r = 0; r <= rows; ++r)
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * M_PI * k / sides, z = height * r / rows;
      text += "v " + std::to_string(radius * std::cos(a)) + " " +
              std::to_string(radius * std::sin(a)) + " " + std::to_string(z) + "\n";
    }
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < sides; ++k) {  // 1-based; normals toward the axis
      const int a = r * sides + k + 1, b = r * sides + (k + 1) % sides + 1;
      const int c = a + sides, d = b + sides;
      text += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(b) + "\n";
      text += "f " + std::to_string(b) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  return text;
}

void feed_attempt(benchmark::State& state) {
  const long long count = state.range(0);
  const int rows = int(state.range(1));
  const std::string dir = (std::filesystem::temp_directory_path() / "talus_bench_feed").string();
  std::filesystem::create_directories(dir);
  { std::ofstream(dir + "/band.obj") << silo_band_obj(rows); }
  const std::string text = R"(time: {step: 1.0e-5, end: 1.0}
materials:
  rock: {density: 2600, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.5,
         restitution: 0.3}
templates:
  grain: {shape: dodecahedron:0.03, material: rock}
particles:
  - feed:
      template: grain
      region: {cylinder: {base: [0, 0, 3.70], axis: [0, 0, 1], radius: 0.39, height: 0.42}}
      rate: 1.0e6
      stop: 1.0
      velocity: [0, 0, -1]
walls:
  - mesh: {name: bin, file: band.obj, material: rock}
effects: {gravity: [0, 0, -9.81], contact: volume}
)";
  const talus::Scene scene = talus::parse_scene(text, dir + "/feed.yaml", dir);
  // The grains: random below the feed, then a lattice at one bounding diameter over its region.
  std::vector<talus::Vec3d> positions;
  std::vector<int> templates;
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0, 1);
  while (static_cast<long long>(positions.size()) < count) {
    const double r = 0.39 * std::sqrt(unit(random)), a = 2 * M_PI * unit(random);
    positions.emplace_back(r * std::cos(a), r * std::sin(a), 3.6 * unit(random));
  }
  const double d = 0.03;
  for (double z = 3.70; z <= 4.12; z += d)
    for (double x = -0.39; x <= 0.39; x += d)
      for (double y = -0.39; y <= 0.39; y += d)
        if (x * x + y * y <= 0.39 * 0.39) positions.emplace_back(x, y, z);
  templates.assign(positions.size(), 0);
  talus::Feeding feeding(scene);
  long long placed = 0;
  for (auto _ : state) {
    placed += static_cast<long long>(feeding.insert_all(0.5, positions, templates).size());
  }
  state.counters["placed"] = double(placed);  // 0: the region is full, as meant
  state.counters["triangles"] = 2.0 * 96 * rows;
  state.counters["grains"] = double(positions.size());
}

}  // namespace

BENCHMARK(fill)
    ->ArgsProduct({{100000, 1000000}, {1, 0}, {0}})
    ->ArgNames({"particles", "threads", "batch"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(made_and_checked)
    ->Arg(1000000)
    ->ArgNames({"particles"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

BENCHMARK(feed_attempt)
    ->ArgsProduct({{64000}, {2, 340}})
    ->ArgNames({"particles", "rows"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
