// The production step on the host backend (solver/step/host/host_step): the same bed of dodecahedra
// with each effect taken away in turn, so that what an effect costs is the difference
// (docs/design.md, "Simulate only the effects a scene calls for": an absent effect has no
// stage), each on 1 and 2 threads (the argument `threads`; wall-clock time, as the step's threads
// run beside the timing one). The bed: a 10 x 10 x 10 cubic lattice
// of 10 mm dodecahedra at a spacing of 8.2 mm with random orientations (particles overlap
// neighbours from the first step), in a closed box wall. And the wall stage on a rotating drum of
// many facets, with the facet grid and by brute force.
#include <benchmark/benchmark.h>

#include <array>
#include <string>

#include "benchmarks/dodecahedron_bed.hpp"
#include "benchmarks/drum_bed.hpp"
#include "solver/step/host/host_step.hpp"

namespace {

void host_step(benchmark::State& state, const std::string& effects, bool walls) {
  const talus::Scene scene = talus_bench::dodecahedron_bed(10, effects, walls);
  talus::HostStep<double> step(scene, static_cast<int>(state.range(0)));
  step.step();  // the first step evaluates the forces at t = 0 too
  const talus::StageSeconds before = step.stage_seconds();
  double contacts = 0;
  long long steps = 0;
  for (auto _ : state) {
    step.step();
    contacts += double(step.pair_contact_count() + step.wall_contact_count());
    ++steps;
  }
  const double particles = step.particle_count();
  state.counters["particle_steps/s"] =
      benchmark::Counter(particles, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["contacts_per_step"] = steps > 0 ? contacts / double(steps) : 0;
  state.counters["particles"] = particles;
  // Milliseconds per step in the contact stages (HostStep's stage timers), to see which scale.
  for (const talus::Stage s : {talus::Stage::candidate_pairs, talus::Stage::pair_contacts,
                               talus::Stage::wall_contacts, talus::Stage::accumulate}) {
    const int k = static_cast<int>(s);
    if (steps > 0 && step.stage_seconds()[k] > before[k]) {
      state.counters[std::string("ms_") + talus::to_string(s)] =
          1e3 * (step.stage_seconds()[k] - before[k]) / double(steps);
    }
  }
}

// The particles' order in memory (range(1), the modes of bench_step_gpu.cpp): 0 the lattice's,
// 6 a random order (as a poured bed numbers them), 7 that order renumbered by cell at every
// build of the pair list (`reorder: true`), 8 the lattice's order renumbered so; a bed of
// side^3 (range(0)) with all effects, on all the host's threads.
void host_step_order(benchmark::State& state) {
  talus::Scene scene = talus_bench::dodecahedron_bed(static_cast<int>(state.range(0)),
                                                     talus_bench::kAllEffects, true);
  const int mode = static_cast<int>(state.range(1));
  if (mode == 6 || mode == 7) talus_bench::shuffle_particles(scene);
  scene.reorder = mode == 7 || mode == 8;
  talus::HostStep<double> step(scene);
  step.step();
  for (auto _ : state) step.step();
  state.counters["particle_steps/s"] = benchmark::Counter(
      double(step.particle_count()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = step.threads();
}

// Each case on 1 and 2 threads (this development host has 2 cores), in wall-clock time.
void threads_1_2(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
}

const std::string& kAll = talus_bench::kAllEffects;

// drum_bed.hpp with radius 60 mm and 4 layers each side of the middle (1,305 dodecahedra, about 300
// of them touching the drum), range(0) segments: 4 x segments facets. Each iteration is a whole
// step; ms_wall_contacts is the wall stage's share (the drum's corners placed, then every
// particle against the drum), the figure that compares the searches.
void host_wall_stage(benchmark::State& state, talus::WallSearch search) {
  const int segments = static_cast<int>(state.range(0));
  const talus::Scene scene = talus_bench::drum_bed(segments, 0.06, 4);
  talus::HostStep<double> step(scene, 1, search);  // one thread, as measured
  talus_bench::time_wall_stage(state, step, segments);
}

}  // namespace

BENCHMARK_CAPTURE(host_step, all_effects, kAll, true)->Apply(threads_1_2);
BENCHMARK_CAPTURE(host_step, no_walls, kAll, false)->Apply(threads_1_2);
BENCHMARK_CAPTURE(host_step, no_friction,
                  "  gravity: [0, 0, -9.81]\n  contact: volume\n  rotation: true\n", true)
    ->Apply(threads_1_2);
BENCHMARK_CAPTURE(host_step, no_rotation,
                  "  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n", true)
    ->Apply(threads_1_2);
BENCHMARK_CAPTURE(host_step, with_drag, kAll + "  drag: {alpha: 1.0e-4}\n", true)
    ->Apply(threads_1_2);
BENCHMARK_CAPTURE(host_step, linear_model,
                  "  gravity: [0, 0, -9.81]\n  contact: {model: linear, stiffness: 1.0e4, "
                  "damping: 0.5, tangential_damping: 1.0}\n  friction: true\n  rotation: true\n",
                  true)
    ->Apply(threads_1_2);
BENCHMARK_CAPTURE(host_step, gravity_only, "  gravity: [0, 0, -9.81]\n", false)->Apply(threads_1_2);

BENCHMARK(host_step_order)
    ->ArgNames({"side", "mode"})
    ->Args({30, 0})
    ->Args({30, 6})
    ->Args({30, 7})
    ->Args({30, 8})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(host_wall_stage, grid, talus::WallSearch::grid)
    ->Arg(64)
    ->Arg(256)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_wall_stage, brute_force, talus::WallSearch::brute_force)
    ->Arg(64)
    ->Arg(256)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
