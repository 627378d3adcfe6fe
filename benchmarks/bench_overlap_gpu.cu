// Overlap pairs per second on the GPU: OverlapBatchGpu (one thread per pair, §2.3) over a batch of
// 2^22 pose pairs, timed by CUDA events around all the launches of a run (manual time). The goal of
// the issue: at least 1e9 dodecahedron pair overlaps per second in double on shallow overlaps on an
// H100. The shallow set holds kDistinctPairs distinct pairs generated on the host and tiled to the
// batch size (bisection of 4M poses on the host would dominate the run).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "benchmarks/overlap_batch/overlap_batch.hpp"
#include "benchmarks/pose_sets.hpp"
#include "solver/core/cuda_device.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"

namespace talus::bench {
namespace {

constexpr std::size_t kDistinctPairs = std::size_t(1) << 16;
const char* const kDodecahedron = "dodecahedron:0.01";
const char* const kCylinder = "cylinder:0.008,0.0053";  // paper §3.1: 80 facets, 22 merged faces

// 2^22 unless TALUS_BENCH_GPU_PAIRS says otherwise (smaller runs under a profiler).
std::size_t batch_pairs() {
  const char* text = std::getenv("TALUS_BENCH_GPU_PAIRS");
  const long long value = text ? std::atoll(text) : 0;
  return value > 0 ? std::size_t(value) : std::size_t(1) << 22;
}

// What a batch computed, summarised once per (batch, culling) because the download is 100s of MB.
struct BatchSummary {
  double hull_points = 0;      // mean planes bounding the intersection
  double enumerated = 0;       // fraction of pairs answered by the vertex enumeration
  double overlapping = 0;      // fraction of pairs with status overlapping (1 on shallow sets)
  double volume_fraction = 0;  // mean V / V_body (1e-4..1e-2 on shallow sets)
};

// The batch of the last template run in this precision, kept across the calls Google Benchmark
// makes while it sizes the iteration count (tiling and uploading 2^22 poses takes seconds); the
// culled and naive variants share it.
template <class Real>
struct CachedBatch {
  std::string spec;
  ShapeTemplate shape;
  std::unique_ptr<ShapeArrays<Real>> arrays;
  std::unique_ptr<OverlapBatchGpu<Real>> batch;
  std::map<std::string, BatchSummary> summary;  // by variant
};

template <class Real>
CachedBatch<Real>& cached_batch() {
  static CachedBatch<Real> cached;
  return cached;
}

template <class Real>
CachedBatch<Real>& batch_for(const std::string& spec) {
  CachedBatch<Real>& cached = cached_batch<Real>();
  if (cached.batch && cached.spec == spec) return cached;
  cached.batch.reset();  // free the previous template's device memory first
  cached.spec = spec;
  cached.summary.clear();
  cached.shape = make_builtin(spec);
  cached.arrays = std::make_unique<ShapeArrays<Real>>(cached.shape);
  cached.batch =
      std::make_unique<OverlapBatchGpu<Real>>(cached.arrays->view(), cached.arrays->view());
  const PoseSet poses = tile(cached_set(spec, spec, "shallow", kDistinctPairs), batch_pairs());
  cached.batch->set_poses(convert_poses<Real>(poses.a), convert_poses<Real>(poses.b));
  return cached;
}

template <class Real>
void overlap_batch_benchmark(benchmark::State& state, const std::string& spec,
                             const std::string& variant, OverlapBatchPath path) {
  std::string reason;
  if (!cuda_device_available(&reason)) {
    state.SkipWithError(reason.c_str());
    return;
  }
  CachedBatch<Real>& cached = batch_for<Real>(spec);
  OverlapBatchGpu<Real>& batch = *cached.batch;
  const OverlapOptions options = overlap_options_named(variant);
  batch.run(options, path);  // warm-up: module load, first touch of the buffers

  double seconds = 0;
  for (auto _ : state) {
    const double kernel_seconds = batch.run(options, path) * 1e-3;
    state.SetIterationTime(kernel_seconds);
    seconds += kernel_seconds;
  }
  const double pairs = double(batch.pair_count());
  const double processed = pairs * double(state.iterations());
  state.SetItemsProcessed(std::int64_t(processed));
  // Kernel time only, computed here so it does not depend on how the library treats rates under
  // manual time.
  state.counters["pairs/s"] = processed / seconds;
  state.counters["pairs"] = pairs;
  state.counters["workspace_bytes"] = double(batch.workspace_bytes());
  state.counters["capacity"] = batch.workspace_capacity();
  // Checks that the batch is what its name says.
  auto found = cached.summary.find(variant);
  if (found == cached.summary.end()) {
    BatchSummary s;
    for (const OverlapResult<Real>& r : batch.results()) {
      s.hull_points += r.hull_points;
      s.enumerated += r.enumerated;
      s.overlapping += r.status == OverlapStatus::overlapping;
      s.volume_fraction += double(r.volume);
    }
    s.hull_points /= pairs;
    s.enumerated /= pairs;
    s.overlapping /= pairs;
    s.volume_fraction /= pairs * cached.shape.volume;
    found = cached.summary.emplace(variant, s).first;
  }
  state.counters["hull_points"] = found->second.hull_points;
  state.counters["enumerated"] = found->second.enumerated;
  state.counters["overlapping"] = found->second.overlapping;
  state.counters["volume_fraction"] = found->second.volume_fraction;
}

void register_all() {
  struct Variant {
    const char* name;
    const char* spec;
    bool is_float;
    const char* culling;  // overlap_options_named
    OverlapBatchPath path;
  };
  const OverlapBatchPath phased = OverlapBatchPath::phased, whole = OverlapBatchPath::whole;
  const Variant variants[] = {
      // The production default: both culls and the vertex enumeration first.
      {"dodecahedron/shallow/double/vertices", kDodecahedron, false, "vertices", phased},
      {"dodecahedron/shallow/float/vertices", kDodecahedron, true, "vertices", phased},
      {"cylinder80/shallow/double/vertices", kCylinder, false, "vertices", phased},
      {"cylinder80/shallow/float/vertices", kCylinder, true, "vertices", phased},
      // The dual hull for every pair, with each filter (faces: both culls).
      {"dodecahedron/shallow/double/faces", kDodecahedron, false, "faces", phased},
      {"dodecahedron/shallow/double/planes", kDodecahedron, false, "planes", phased},
      {"dodecahedron/shallow/double/naive", kDodecahedron, false, "naive", phased},
      // What the phases gain over each pair's whole overlap in one thread.
      {"dodecahedron/shallow/double/faces/whole", kDodecahedron, false, "faces", whole},
      {"dodecahedron/shallow/float/faces", kDodecahedron, true, "faces", phased},
      {"dodecahedron/shallow/float/planes", kDodecahedron, true, "planes", phased},
      {"dodecahedron/shallow/float/naive", kDodecahedron, true, "naive", phased},
      {"cylinder80/shallow/double/faces", kCylinder, false, "faces", phased},
      {"cylinder80/shallow/double/planes", kCylinder, false, "planes", phased},
      {"cylinder80/shallow/double/naive", kCylinder, false, "naive", phased},
      {"cylinder80/shallow/double/faces/whole", kCylinder, false, "faces", whole},
      {"cylinder80/shallow/float/faces", kCylinder, true, "faces", phased},
      {"cylinder80/shallow/float/planes", kCylinder, true, "planes", phased},
      {"cylinder80/shallow/float/naive", kCylinder, true, "naive", phased},
  };
  for (const Variant& v : variants) {
    const std::string spec = v.spec, culling = v.culling;
    const OverlapBatchPath path = v.path;
    const std::string name = "gpu_overlap/" + std::string(v.name);
    benchmark::internal::Benchmark* b =
        v.is_float ? benchmark::RegisterBenchmark(name.c_str(),
                                                  [=](benchmark::State& st) {
                                                    overlap_batch_benchmark<float>(st, spec,
                                                                                   culling, path);
                                                  })
                   : benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
                       overlap_batch_benchmark<double>(st, spec, culling, path);
                     });
    b->UseManualTime()->Unit(benchmark::kMillisecond);
  }
}

}  // namespace
}  // namespace talus::bench

int main(int argc, char** argv) {
  talus::bench::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  // Device memory goes back before the CUDA runtime unloads at exit.
  talus::bench::cached_batch<double>().batch.reset();
  talus::bench::cached_batch<float>().batch.reset();
  benchmark::Shutdown();
  return 0;
}
