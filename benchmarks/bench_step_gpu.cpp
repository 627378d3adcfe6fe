// The production step on the GPU (solver/step/cuda/cuda_step): the dodecahedron bed of
// dodecahedron_bed.hpp (about 3 pair contacts per particle, i.e. 6 contacts per particle, in a
// box wall, gravity, volume model, friction, rotation, double) at 1e5, 1e6 and 4e6 particles
// (side 46, 100 and 159): polyhedron-steps per second, contacts, time per stage, pair-list builds
// per step and device bytes per particle. The second argument is the mode: 0 the defaults
// (deterministic sums, the default skin), 1 atomic sums (deterministic: false), 2 no skin (the
// list rebuilt every step, the worst case of a fast flow), 3 the templates read from global
// memory instead of constant memory, 4 no GJK filter before the culling
// (CudaStepOptions::gjk_filter), 5 the paper's law (`contact: volume_paper`, Eqs. 12-13, the
// bed's law before the default law of bounded stiffness: the same geometry, less arithmetic per
// contact, so 0 against 5 is what the default law costs), 6 the particles in a random order (as
// a poured bed numbers them), 7 that order renumbered by cell at every build of the list
// (`reorder: true`), 8 the lattice's order renumbered so. Each iteration is one step (the
// stages synchronise at their ends; the time is the wall time of the step).
// And the wall stage on a rotating drum of many facets (drum_bed.hpp), with the facet grid and
// by brute force.
#include <benchmark/benchmark.h>

#include <array>
#include <string>

#include "benchmarks/dodecahedron_bed.hpp"
#include "benchmarks/drum_bed.hpp"
#include "solver/core/cuda_device.hpp"
#include "solver/step/cuda/cuda_step.hpp"

namespace {

void gpu_step(benchmark::State& state) {
  std::string why;
  if (!talus::cuda_device_available(&why)) {
    state.SkipWithError(why.c_str());
    return;
  }
  const int side = static_cast<int>(state.range(0));
  talus::Scene scene = talus_bench::dodecahedron_bed(side, talus_bench::kAllEffects, true);
  const int mode = static_cast<int>(state.range(1));
  if (mode == 1) scene.deterministic = false;
  if (mode == 2) scene.skin = 0.0;
  if (mode == 5) scene.effects.contact = talus::ContactModel::volume_paper;
  if (mode == 6 || mode == 7) talus_bench::shuffle_particles(scene);
  // The GPU's default renumbers; modes 0 to 6 are the step as it ran before that.
  scene.reorder = mode == 7 || mode == 8;
  talus::CudaStepOptions options;
  options.constant_templates = mode != 3;
  options.gjk_filter = mode != 4;
  const std::size_t used_before = talus::cuda_device_used_bytes();
  talus::CudaStep<double> step(scene, options);
  step.step();  // the first step evaluates the forces at t = 0 too
  const talus::StageSeconds before = step.stage_seconds();
  const long long builds_before = step.pair_list_builds();
  long long steps = 0;
  double contacts = 0;
  for (auto _ : state) {
    step.step();
    contacts += double(step.pair_contact_count() + step.wall_contact_count());
    ++steps;
  }
  const double particles = step.particle_count();
  state.counters["polyhedron_steps/s"] =
      benchmark::Counter(particles, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["particles"] = particles;
  state.counters["constant_templates"] = step.templates_in_constant_memory() ? 1 : 0;
  state.counters["contacts_per_step"] = steps > 0 ? contacts / double(steps) : 0;
  // Every device array of the step (particle state, pair list and slots, walls, CUB scratch);
  // the overlap workspace is per-thread local memory and not among them.
  state.counters["bytes_per_particle"] = double(step.allocated_bytes()) / particles;
  state.counters["list_bytes_per_particle"] = double(step.pair_list_bytes()) / particles;
  // What the device lost to the step (cudaMemGetInfo before and after): the arrays above with
  // the allocator's rounding, the driver's local memory for the kernels' workspaces, the graphs.
  state.counters["device_bytes_per_particle"] =
      double(talus::cuda_device_used_bytes() - used_before) / particles;
  // bytes_per_particle by part (CudaStep::memory_parts), e.g. "B_slot forces".
  for (const auto& part : step.memory_parts()) {
    state.counters["B_" + part.first] = double(part.second) / particles;
  }
  state.counters["candidates"] = double(step.candidate_pair_count());
  state.counters["list_builds_per_step"] =
      steps > 0 ? double(step.pair_list_builds() - builds_before) / double(steps) : 0;
  const talus::StageSeconds& after = step.stage_seconds();
  for (int k = 0; k < talus::kStageCount; ++k) {
    if (after[k] > before[k] && steps > 0) {
      state.counters[std::string("ms_") + talus::to_string(static_cast<talus::Stage>(k))] =
          1e3 * (after[k] - before[k]) / double(steps);
    }
  }
}
BENCHMARK(gpu_step)
    ->Name("gpu_step/dodecahedron_bed")
    ->Args({46, 0})
    ->Args({100, 0})
    ->Args({100, 1})
    ->Args({100, 2})
    ->Args({100, 3})
    ->Args({100, 4})
    ->Args({100, 5})
    ->Args({100, 6})
    ->Args({100, 7})
    ->Args({100, 8})
    ->Args({159, 0})
    ->Unit(benchmark::kMillisecond);

// drum_bed.hpp with radius 200 mm and 12 layers each side of the middle (44,725
// dodecahedra), range(0) segments: 4 x segments facets. ms_wall_contacts: the wall stage per step
// (the drum's corners placed by a kernel, the wall kernel, ordering and history).
void gpu_wall_stage(benchmark::State& state, talus::WallSearch search) {
  std::string why;
  if (!talus::cuda_device_available(&why)) {
    state.SkipWithError(why.c_str());
    return;
  }
  const int segments = static_cast<int>(state.range(0));
  const talus::Scene scene = talus_bench::drum_bed(segments, 0.2, 12);
  talus::CudaStepOptions options;
  options.wall_search = search;
  talus::CudaStep<double> step(scene, options);
  talus_bench::time_wall_stage(state, step, segments);
}
BENCHMARK_CAPTURE(gpu_wall_stage, grid, talus::WallSearch::grid)
    ->Arg(256)
    ->Arg(1024)
    ->Arg(4096)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(gpu_wall_stage, brute_force, talus::WallSearch::brute_force)
    ->Arg(256)
    ->Arg(1024)
    ->Arg(4096)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
