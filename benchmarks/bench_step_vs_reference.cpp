// The production step on the host backend against the reference solver on the same scene, in
// one run (issue 4: "the same scene at 2e4 particles on the host backend (2 cores) against the
// reference solver, in one run: the ratio"). The bed of bench_step_cpu.cpp grown to N = side^3
// particles (default side 27: 19683 dodecahedra, ~3 pair contacts each, in a box wall, volume
// model with friction and rotation).
//
// Each solver is built from the scene (not timed) and its first step is timed: the force
// evaluation at t = 0 and one step, i.e. two force evaluations at configurations 1 us apart, the
// same work in both solvers. The ratio of these first steps is the figure (counters
// `ratio_1_thread`, `ratio_2_threads` of the reference case); the reference costs milliseconds
// per contact (exact arithmetic), so its first step at 2e4 particles is long (its time:
// benchmarks/history/README.md) and is taken once. The production host step then also takes 3
// more steps (its time per step, the benchmark's time), on 1 and 2 threads. TALUS_BENCH_SIDE=n
// changes the size.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <string>

#include "benchmarks/dodecahedron_bed.hpp"
#include "reference/run/scene_run.hpp"
#include "solver/step/host/host_step.hpp"

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

double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The production host step's first-step seconds by thread count, for the reference's ratios
// (the production cases run first: registration order).
std::map<int, double>& production_first_step() {
  static std::map<int, double> seconds;
  return seconds;
}

void production_host(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  talus::HostStep<double> step(scene(), threads);
  const double start = clock_seconds();
  step.step();
  const double first = clock_seconds() - start;
  production_first_step()[threads] = first;
  for (auto _ : state) step.step();
  state.counters["threads"] = step.threads();
  state.counters["first_step_s"] = first;
  state.counters["particles"] = step.particle_count();
  state.counters["pair_contacts"] = double(step.pair_contact_count());
  state.counters["wall_contacts"] = double(step.wall_contact_count());
}
// Wall-clock time: the step's threads run beside the one Google Benchmark times.
BENCHMARK(production_host)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kSecond)
    ->Iterations(3);

void reference(benchmark::State& state) {
  std::vector<int> template_of_body;
  talus::reference::RefWorld world(talus::reference::world_setup(scene(), template_of_body));
  double first = 0;
  for (auto _ : state) {
    const double start = clock_seconds();
    world.step();  // the first step: the evaluation at t = 0, then one step
    first = clock_seconds() - start;
  }
  long long pairs = 0, walls = 0;
  for (const auto& c : world.contacts()) (c.wall < 0 ? pairs : walls) += 1;
  state.counters["particles"] = double(world.bodies().size());
  state.counters["pair_contacts"] = double(pairs);
  state.counters["wall_contacts"] = double(walls);
  for (const auto& [threads, seconds] : production_first_step()) {
    state.counters[threads == 1 ? "ratio_1_thread"
                                : "ratio_" + std::to_string(threads) + "_threads"] =
        first / seconds;
  }
}
BENCHMARK(reference)->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
