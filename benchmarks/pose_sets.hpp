// Deterministic pose-pair sets shared by the CPU and GPU overlap benchmarks. A set is generated
// on the host once (in parallel, one seed per pair, so the result does not depend on the thread
// count) and reused by every variant (double/float, culled/naive, CPU/GPU).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "solver/core/quat.hpp"
#include "solver/shape/shape.hpp"

namespace talus::bench {

struct PoseSet {
  std::vector<Posed> a, b;  // pair i is (a[i], b[i])
  std::size_t size() const { return a.size(); }
};

// Overlap volume fractions (of the smaller body's volume) of the "shallow" set: typical of dense
// granular flow, where contacts are a small fraction of a particle deep.
constexpr double kShallowFractionMin = 1e-4;
constexpr double kShallowFractionMax = 1e-2;

// `count` pairs that truly overlap, each with a volume fraction V / min(V_a, V_b) within 10% of a
// target drawn log-uniformly in [1e-4, 1e-2] (and inside that interval): random orientations and
// a random direction from A to B, then the centre distance bisected with the production overlap
// in double. A lies within two diameters of the origin, as in random_overlapping_pair.
PoseSet make_shallow_set(const ShapeTemplate& a, const ShapeTemplate& b, std::size_t count,
                         std::uint64_t seed);

// `count` pairs from random_overlapping_pair with depth fraction in [0, 0.7] of the sum of the
// bounding radii: a mix of separate and overlapping pairs, as a broad phase would hand over.
PoseSet make_random_set(const ShapeTemplate& a, const ShapeTemplate& b, std::size_t count,
                        std::uint64_t seed);

// The set repeated until it holds `count` pairs (pair i is pair i % set.size()), so that
// neighbouring GPU threads still get different pairs.
PoseSet tile(const PoseSet& set, std::size_t count);

// Cached by (specs, kind, count, seed): the CPU and GPU programs ask for the same sets from
// several benchmarks. kind is "shallow" or "random". Not thread-safe (benchmarks register and
// run on one thread).
const PoseSet& cached_set(const std::string& spec_a, const std::string& spec_b,
                          const std::string& kind, std::size_t count, std::uint64_t seed = 2024);

// Poses in the real type a benchmark runs in.
template <class Real>
std::vector<Pose<Real>> convert_poses(const std::vector<Posed>& poses) {
  std::vector<Pose<Real>> out;
  out.reserve(poses.size());
  for (const Posed& p : poses) out.push_back({Vec3<Real>(p.position), Quat<Real>(p.orientation)});
  return out;
}

}  // namespace talus::bench
