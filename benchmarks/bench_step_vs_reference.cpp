// The production step on the host backend against the reference solver on the same scene, in
// one run (issue 4: "the same scene at 2e4 particles on the host backend against the reference
// solver: the ratio"). The bed of bench_step_cpu.cpp grown to N = side^3 particles (default
// side 27: 19683 dodecahedra, ~3 pair contacts each, in a box wall, volume model with friction
// and rotation); each solver is built from the scene and its first step taken, then one more
// step is timed. The reference costs milliseconds per contact (exact arithmetic), so a run at
// 2e4 particles takes several minutes. TALUS_BENCH_SIDE=n changes the size.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "benchmarks/dodecahedron_bed.hpp"
#include "reference/run/scene_run.hpp"
#include "solver/step/host_step.hpp"

namespace {

int bed_side() {
  const char* text = std::getenv("TALUS_BENCH_SIDE");
  const int side = text ? std::atoi(text) : 27;
  return side > 0 ? side : 27;
}

const talus::Scene& scene() {
  static const talus::Scene bed =
      talus_bench::dodecahedron_bed(bed_side(), talus_bench::kAllEffects, true);
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
