// The broad phase (solver/neighbor): candidate pairs per second of particles binned, counted,
// scanned and written, on one CPU core (build_candidate_pairs) and on the GPU (ContactPairsGpu,
// CUDA builds). The particles sit on a jittered cubic lattice whose spacing is 0.98 of a
// bounding diameter, so each overlaps its ~6 face neighbours: the density of a settled bed.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "solver/neighbor/contact_pairs.hpp"
#if TALUS_HAVE_CUDA
#include "solver/core/cuda_device.hpp"
#include "solver/neighbor/contact_pairs_gpu.hpp"
#endif

namespace {

struct Bed {
  std::vector<double> x, y, z, r;
  talus::NeighborInput<double> input() const {
    talus::NeighborInput<double> in;
    in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = r.data();
    in.count = static_cast<int>(x.size());
    return in;
  }
};

// n particles of radius 5 mm on a jittered lattice (spacing 9.8 mm, jitter +-0.05 mm), shuffled
// so that memory order does not follow space (as after particles have moved).
Bed make_bed(int n) {
  const double radius = 0.005, spacing = 0.98 * 2 * radius, jitter = 0.00005;
  const int side = static_cast<int>(std::ceil(std::cbrt(double(n))));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  Bed bed;
  bed.x.resize(n), bed.y.resize(n), bed.z.resize(n), bed.r.assign(n, radius);
  for (int k = 0; k < n; ++k) {
    const int i = order[k];
    bed.x[k] = spacing * (i % side) + u(rng);
    bed.y[k] = spacing * ((i / side) % side) + u(rng);
    bed.z[k] = spacing * (i / (side * side)) + u(rng);
  }
  return bed;
}

void cpu_pairs(benchmark::State& state) {
  const Bed bed = make_bed(static_cast<int>(state.range(0)));
  std::size_t pairs = 0;
  for (auto _ : state) {
    const std::vector<talus::ContactPair> list = talus::build_candidate_pairs(bed.input());
    pairs = list.size();
    benchmark::DoNotOptimize(list.data());
  }
  state.counters["particles/s"] =
      benchmark::Counter(double(bed.x.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["pairs_per_particle"] = double(pairs) / double(bed.x.size());
}
BENCHMARK(cpu_pairs)
    ->Name("cpu_contact_pairs")
    ->Arg(10000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);

#if TALUS_HAVE_CUDA
void gpu_pairs(benchmark::State& state) {
  std::string why;
  if (!talus::cuda_device_available(&why)) {
    state.SkipWithError(why.c_str());
    return;
  }
  const Bed bed = make_bed(static_cast<int>(state.range(0)));
  talus::ContactPairsGpu<double> gpu;
  gpu.set_particles(bed.input());
  for (auto _ : state) state.SetIterationTime(gpu.build() / 1e3);
  state.counters["particles/s"] =
      benchmark::Counter(double(bed.x.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["pairs_per_particle"] = double(gpu.pair_count()) / double(bed.x.size());
}
BENCHMARK(gpu_pairs)
    ->Name("gpu_contact_pairs")
    ->Arg(100000)
    ->Arg(1000000)
    ->Arg(4000000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#endif

}  // namespace

BENCHMARK_MAIN();
