// The setup of a large scene on the host: a random fill placed (solver/scene/initial_particles,
// random_fill_particles) and the initial-state check (check_initial_state), per particle. The
// scene is the scaling study's (experiments/scaling/run_scaling.py): dodecahedra of 1 cm placed
// at random in a box 2 m tall whose side makes their bounding spheres fill 0.25 of it, with
// random orientations, in an open box of generated plane walls. A run of 2e7 such particles
// placed them twice on one core (~17 us a particle, the check aside) before this benchmark's
// change; the fill now tests batches of candidates on every thread.
//
//   bench_setup [--benchmark_filter=fill/particles:1000000/]   (threads 1 and all)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "solver/core/host_parallel.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/scene/wall_meshes.hpp"

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

BENCHMARK_MAIN();
