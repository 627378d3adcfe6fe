// Overlap pairs per second on one CPU core (the host backend runs the same headers as the GPU):
// the exact overlap (paper §2.3) in double and float: the production default ("vertices": both
// culling filters and the vertex enumeration before the dual-space hull), the hull with both
// culling filters ("faces"), the plane filter only ("planes") and naive (every face plane in the
// hull), on shallow
// and random poses; and, on the same shallow dodecahedron poses, GJK alone (§2.2) and the simple
// contact (BLAZE-DEM), so that a report can say what accuracy costs in time.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>

#include "benchmarks/pose_sets.hpp"
#include "solver/geometry/gjk.hpp"
#include "solver/geometry/overlap_polyhedra.hpp"
#include "solver/geometry/simple_contact.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"

namespace talus::bench {
namespace {

constexpr std::size_t kPairs = std::size_t(1) << 16;  // distinct pairs per set, visited cyclically
const char* const kDodecahedron = "dodecahedron:0.01";
const char* const kCylinder = "cylinder:0.008,0.0053";  // paper §3.1: 80 facets, 22 merged faces

// One template pair in one precision with one pose set, built when the benchmark first runs (so
// a --benchmark_filter that skips it also skips its pose generation).
template <class Real>
struct Case {
  ShapeTemplate shape_a, shape_b;
  ShapeArrays<Real> arrays_a, arrays_b;
  std::vector<Pose<Real>> poses_a, poses_b;

  Case(const std::string& spec_a, const std::string& spec_b, const std::string& kind)
      : shape_a(make_builtin(spec_a)),
        shape_b(make_builtin(spec_b)),
        arrays_a(shape_a),
        arrays_b(shape_b) {
    const PoseSet& set = cached_set(spec_a, spec_b, kind, kPairs);
    poses_a = convert_poses<Real>(set.a);
    poses_b = convert_poses<Real>(set.b);
  }
};

// What one pair's computation reports, summed into the counters (also keeps it from being
// optimised away).
struct PairOutcome {
  int hull_points = 0;   // 0 for the kernels that build no hull
  bool contact = false;  // overlapping / intersecting / touching, by the kernel's own test
  double volume = 0;     // m^3, the exact overlap only
};

// Visits the pairs cyclically, one per iteration.
template <class Real, class PairKernel>
void run_pairs(benchmark::State& state, const Case<Real>& c, PairKernel pair_kernel) {
  const ConvexView<Real> a = c.arrays_a.view(), b = c.arrays_b.view();
  const std::size_t n = c.poses_a.size();
  std::size_t i = 0;
  long hull_points = 0, contacts = 0;
  double volume = 0;
  for (auto _ : state) {
    const PairOutcome outcome = pair_kernel(a, c.poses_a[i], b, c.poses_b[i]);
    hull_points += outcome.hull_points;
    contacts += outcome.contact;
    volume += outcome.volume;
    if (++i == n) i = 0;
  }
  const double iterations = double(state.iterations());
  state.SetItemsProcessed(state.iterations());
  state.counters["pairs/s"] = benchmark::Counter(iterations, benchmark::Counter::kIsRate);
  state.counters["hull_points"] = double(hull_points) / iterations;
  state.counters["contact_fraction"] = double(contacts) / iterations;
  // Mean V / min(V_a, V_b): 1e-4..1e-2 by construction on the shallow sets.
  state.counters["volume_fraction"] =
      volume / iterations / std::min(c.shape_a.volume, c.shape_b.volume);
}

template <class Real, int Capacity>
void overlap_with(benchmark::State& state, const Case<Real>& c, OverlapOptions options) {
  auto workspace = std::make_unique<OverlapWorkspace<Real, Capacity>>();
  state.counters["workspace_bytes"] = double(sizeof(OverlapWorkspace<Real, Capacity>));
  run_pairs(
      state, c,
      [&](const ConvexView<Real>& a, const Pose<Real>& pa, const ConvexView<Real>& b,
          const Pose<Real>& pb) {
        const OverlapResult<Real> r = overlap_polyhedra(a, pa, b, pb, *workspace, options);
        benchmark::DoNotOptimize(r);  // the centroid and vector area are not summed below
        return PairOutcome{r.hull_points, r.status == OverlapStatus::overlapping, double(r.volume)};
      });
}

// One exact-overlap case, in the workspace capacity the GPU batch picks for the pair
// (overlap_capacity_for), so that CPU and GPU run the same instantiation. Cases are built once
// and kept across the calls Google Benchmark makes while sizing the iteration count.
template <class Real>
void overlap_benchmark(benchmark::State& state, const std::string& spec_a,
                       const std::string& spec_b, const std::string& kind,
                       const std::string& variant) {
  static std::map<std::string, std::unique_ptr<Case<Real>>> cases;
  auto& c = cases[spec_a + spec_b + kind];
  if (!c) c = std::make_unique<Case<Real>>(spec_a, spec_b, kind);
  const OverlapOptions options = overlap_options_named(variant);
  switch (overlap_capacity_for(c->arrays_a.view().n_faces + c->arrays_b.view().n_faces)) {
    case 32:
      overlap_with<Real, 32>(state, *c, options);
      break;
    case 64:
      overlap_with<Real, 64>(state, *c, options);
      break;
    case 128:
      overlap_with<Real, 128>(state, *c, options);
      break;
    default:
      overlap_with<Real, 256>(state, *c, options);
      break;
  }
}

const Case<double>& dodecahedron_shallow() {
  static const Case<double> c(kDodecahedron, kDodecahedron, "shallow");
  return c;
}

void gjk_benchmark(benchmark::State& state) {
  run_pairs(state, dodecahedron_shallow(),
            [](const ConvexView<double>& a, const Posed& pa, const ConvexView<double>& b,
               const Posed& pb) {
              const GjkResult<double> r = gjk_intersect(a, pa, b, pb);
              benchmark::DoNotOptimize(r);
              return PairOutcome{0, r.intersecting, 0.0};
            });
}

void simple_contact_benchmark(benchmark::State& state) {
  run_pairs(state, dodecahedron_shallow(),
            [](const ConvexView<double>& a, const Posed& pa, const ConvexView<double>& b,
               const Posed& pb) {
              const SimpleContact<double> r = polyhedron_polyhedron_contact(a, pa, b, pb);
              benchmark::DoNotOptimize(r);  // depth, normal and point
              return PairOutcome{0, r.touching, 0.0};
            });
}

void register_all() {
  struct SetSpec {
    const char* name;
    const char* spec;
    const char* kind;
  };
  const SetSpec sets[] = {{"dodecahedron/shallow", kDodecahedron, "shallow"},
                          {"cylinder80/shallow", kCylinder, "shallow"},
                          {"dodecahedron/random", kDodecahedron, "random"}};
  for (const SetSpec& s : sets) {
    for (const std::string variant : {"vertices", "faces", "planes", "naive"}) {
      const std::string spec = s.spec, kind = s.kind;
      benchmark::RegisterBenchmark(
          ("overlap/" + std::string(s.name) + "/double/" + variant).c_str(),
          [=](benchmark::State& st) { overlap_benchmark<double>(st, spec, spec, kind, variant); });
      benchmark::RegisterBenchmark(
          ("overlap/" + std::string(s.name) + "/float/" + variant).c_str(),
          [=](benchmark::State& st) { overlap_benchmark<float>(st, spec, spec, kind, variant); });
    }
  }
  benchmark::RegisterBenchmark("gjk/dodecahedron/shallow/double", gjk_benchmark);
  benchmark::RegisterBenchmark("simple_contact/dodecahedron/shallow/double",
                               simple_contact_benchmark);
}

}  // namespace
}  // namespace talus::bench

int main(int argc, char** argv) {
  talus::bench::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
