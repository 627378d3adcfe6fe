// The production step on the host backend against the reference solver on the same scene, in
// one run (issue 4: "the same scene at 2e4 particles on the host backend against the reference
// solver: the ratio"). The bed of bench_step_cpu.cpp grown to N = side^3 particles (default
// side 27: 19683 dodecahedra, ~3 pair contacts each, in a box wall, volume model with friction
// and rotation); each solver is built from the scene and its first step taken, then one more
// step is timed. The reference costs milliseconds per contact (exact arithmetic), so a run at
// 2e4 particles takes several minutes. TALUS_BENCH_SIDE=n changes the size.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <random>
#include <string>

#include "reference/run/scene_run.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/host_step.hpp"

namespace {

int bed_side() {
  const char* text = std::getenv("TALUS_BENCH_SIDE");
  const int side = text ? std::atoi(text) : 27;
  return side > 0 ? side : 27;
}

talus::Scene bed_scene(int side) {
  const double spacing = 0.0082, extent = spacing * side;
  std::string yaml = R"(time: {step: 1.0e-6, end: 1.0}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: "dodecahedron:0.01", material: glass}
particles:
  - explicit:
)";
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int i = 0; i < side * side * side; ++i) {
    const double x = spacing * (0.5 + i % side), y = spacing * (0.5 + (i / side) % side);
    const double z = spacing * (0.5 + i / (side * side));
    yaml += "      - {template: grain, position: [" + std::to_string(x) + ", " + std::to_string(y) +
            ", " + std::to_string(z) + "], orientation: {axis: [" + std::to_string(unit(rng)) +
            ", " + std::to_string(unit(rng)) + ", " + std::to_string(unit(rng) + 1.5) +
            "], degrees: " + std::to_string(180 * unit(rng)) + "}}\n";
  }
  const std::string lo = std::to_string(-0.0005), hi = std::to_string(extent + 0.0005);
  yaml += "walls:\n  - box: {min: [" + lo + ", " + lo + ", " + lo + "], max: [" + hi + ", " + hi +
          ", " + hi + "], material: glass}\n";
  yaml +=
      "effects:\n  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n"
      "  rotation: true\n";
  return talus::parse_scene(yaml, "bench_step_vs_reference.yaml", ".");
}

const talus::Scene& scene() {
  static const talus::Scene bed = bed_scene(bed_side());
  return bed;
}

void production_host(benchmark::State& state) {
  talus::HostStep<double> step(scene());
  step.step();
  for (auto _ : state) step.step();
  state.counters["particles"] = step.particle_count();
  state.counters["pair_contacts"] = double(step.pair_contact_count());
  state.counters["wall_contacts"] = double(step.wall_contact_count());
}
BENCHMARK(production_host)->Unit(benchmark::kSecond)->Iterations(3);

void reference(benchmark::State& state) {
  std::vector<int> template_of_body;
  talus::reference::RefWorld world(talus::reference::world_setup(scene(), template_of_body));
  world.step();
  for (auto _ : state) world.step();
  long long pairs = 0, walls = 0;
  for (const auto& c : world.contacts()) (c.wall < 0 ? pairs : walls) += 1;
  state.counters["particles"] = double(world.bodies().size());
  state.counters["pair_contacts"] = double(pairs);
  state.counters["wall_contacts"] = double(walls);
}
BENCHMARK(reference)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
