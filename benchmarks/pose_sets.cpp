#include "benchmarks/pose_sets.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <thread>

#include "solver/geometry/overlap_polyhedra.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::bench {
namespace {

// SplitMix64: decorrelates the per-pair seeds seed + i.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Runs make_pair(i, rng, workspace) for i in [0, count) on all host cores; pair i always gets the
// generator seeded from (seed, i), so the set does not depend on the number of threads.
template <class MakePair>
PoseSet generate(std::size_t count, std::uint64_t seed, MakePair make_pair) {
  PoseSet set;
  set.a.resize(count);
  set.b.resize(count);
  const unsigned threads =
      std::max(1u, std::min(std::thread::hardware_concurrency(), unsigned(count / 256 + 1)));
  std::vector<std::thread> workers;
  for (unsigned t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      auto workspace = std::make_unique<OverlapWorkspace<double, 256>>();
      for (std::size_t i = t; i < count; i += threads) {
        std::mt19937_64 rng(mix(seed ^ mix(i)));
        make_pair(rng, *workspace, set.a[i], set.b[i]);
      }
    });
  }
  for (std::thread& w : workers) w.join();
  return set;
}

}  // namespace

PoseSet make_shallow_set(const ShapeTemplate& a, const ShapeTemplate& b, std::size_t count,
                         std::uint64_t seed) {
  const ShapeArrays<double> arrays_a(a), arrays_b(b);
  const ConvexView<double> view_a = arrays_a.view(), view_b = arrays_b.view();
  const double smaller_volume = std::min(a.volume, b.volume);
  const double reach = view_a.bounding_radius + view_b.bounding_radius;
  return generate(
      count, seed,
      [&](std::mt19937_64& rng, OverlapWorkspace<double, 256>& ws, Posed& pose_a, Posed& pose_b) {
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (;;) {  // a draw whose bisection misses its window is redrawn (rare)
          const double target =
              kShallowFractionMin * std::pow(kShallowFractionMax / kShallowFractionMin, unit(rng));
          // Accept within 10% of the target, clipped to the set's range: ~10 bisection steps.
          const double accept_low = std::max(kShallowFractionMin, target / 1.1);
          const double accept_high = std::min(kShallowFractionMax, target * 1.1);
          pose_a = random_pose(rng, 4 * view_a.bounding_radius);
          pose_b.orientation = random_rotation(rng);
          const Vec3d direction = random_direction(rng);
          auto fraction_at = [&](double distance, OverlapStatus& status) {
            pose_b.position = pose_a.position + direction * distance;
            const OverlapResult<double> r = overlap_polyhedra(view_a, pose_a, view_b, pose_b, ws);
            status = r.status;
            return r.volume / smaller_volume;
          };
          // The overlap volume along a ray is unimodal (V^(1/3) is concave, Brunn-Minkowski) and
          // zero at the bounding-sphere distance, so with V(0) above the target there is one
          // crossing.
          OverlapStatus status;
          double low = 0, high = reach;
          if (!(fraction_at(low, status) > accept_high)) continue;
          for (int step = 0; step < 60; ++step) {
            const double mid = 0.5 * (low + high);
            const double f = fraction_at(mid, status);
            if (f >= accept_low && f <= accept_high && status == OverlapStatus::overlapping) return;
            (f > target ? low : high) = mid;
          }
        }
      });
}

PoseSet make_random_set(const ShapeTemplate& a, const ShapeTemplate& b, std::size_t count,
                        std::uint64_t seed) {
  return generate(
      count, seed,
      [&](std::mt19937_64& rng, OverlapWorkspace<double, 256>&, Posed& pose_a, Posed& pose_b) {
        const PosePair pair =
            random_overlapping_pair(rng, a.bounding_radius, b.bounding_radius, 0, 0.7);
        pose_a = pair.a;
        pose_b = pair.b;
      });
}

PoseSet tile(const PoseSet& set, std::size_t count) {
  if (set.size() == 0) throw std::invalid_argument("tile: empty pose set");
  PoseSet out;
  out.a.reserve(count);
  out.b.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    out.a.push_back(set.a[i % set.size()]);
    out.b.push_back(set.b[i % set.size()]);
  }
  return out;
}

const PoseSet& cached_set(const std::string& spec_a, const std::string& spec_b,
                          const std::string& kind, std::size_t count, std::uint64_t seed) {
  static std::map<std::string, std::unique_ptr<PoseSet>> cache;
  const std::string key =
      spec_a + "|" + spec_b + "|" + kind + "|" + std::to_string(count) + "|" + std::to_string(seed);
  auto found = cache.find(key);
  if (found != cache.end()) return *found->second;
  const ShapeTemplate a = make_builtin(spec_a), b = make_builtin(spec_b);
  PoseSet set;
  if (kind == "shallow")
    set = make_shallow_set(a, b, count, seed);
  else if (kind == "random")
    set = make_random_set(a, b, count, seed);
  else
    throw std::invalid_argument("cached_set: kind '" + kind + "' (expected shallow or random)");
  return *cache.emplace(key, std::make_unique<PoseSet>(std::move(set))).first->second;
}

}  // namespace talus::bench
