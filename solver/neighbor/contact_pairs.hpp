// The broad phase (docs/design.md, "The step", 3; paper §2.2 and Fig. 3c; BLAZE-DEM's spatial
// hashing with sorting): particles binned in a uniform grid whose cells are at least one bounding
// diameter (plus the skin) wide, the cells hashed into a table, particles sorted by bucket; then
// per particle the candidates in its 27 neighbour cells are counted, the counts exclusive-scanned,
// and every pair whose bounding spheres overlap written into one 1-D array of ContactPair {a, b},
// a < b, sorted by (a, b).
//
// The per-particle steps are TALUS_HD functions (one thread per particle on the GPU); the host
// driver build_candidate_pairs runs them in loops, the per-particle ones (bucket, count, write)
// on several threads (core/host_parallel.hpp): each particle writes only its own entries, and the
// binning and the scan stay serial, so the list is the same for any thread count. Correctness does
// not depend on the hash: any two overlapping spheres lie in neighbouring cells (cell >= 2 r_max +
// skin), so the partner's bucket is among the 27 visited; a bucket shared by several visited cells
// is visited once, and collisions only add candidates that the exact sphere test rejects.
//
// Where the particles' box spans few cells (a bed, a packing: at most 4 per particle), the host
// driver numbers the cells densely instead of hashing them (NeighborGrid::dims): neighbouring
// cells are then neighbouring buckets, no two cells share a bucket, and with the particles visited
// in bucket order a particle's 27 cells are mostly in cache. On 1e6 spheres of a lattice, one
// thread, side by side on a loaded 2-core VM: 12.8-15.4 s hashed, 1.6-2.1 s dense (shuffled
// order: 23.5 s, 4.9 s); the hashed table scattered the 27 cells over 8 MB, a cache miss each.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/core/hd.hpp"
#include "solver/core/host_parallel.hpp"
#include "solver/core/math.hpp"

namespace talus {

struct ContactPair {
  int a, b;  // particle indices, a < b
};
inline bool operator==(const ContactPair& p, const ContactPair& q) {
  return p.a == q.a && p.b == q.b;
}

// The particles as the step holds them (structure of arrays).
template <class Real>
struct NeighborInput {
  const Real* x = nullptr;
  const Real* y = nullptr;
  const Real* z = nullptr;
  const Real* radius = nullptr;  // bounding radius about the centroid, m
  int count = 0;
  Real skin = 0;  // m: pairs are kept while |x_a - x_b| <= r_a + r_b + skin (a Verlet skin)
  // The lowest corner of the region the particles lie in, when the local domain bounds it
  // (Domain::reach_box): the grid's origin then, with no reduction over the particles; otherwise
  // (fixed_origin false) the particles' lowest coordinates. The list does not depend on it (it is
  // sorted), only the binning does.
  bool fixed_origin = false;
  Real origin[3] = {0, 0, 0};
};

// The binning: a cell size, an origin and a table of 2^k buckets.
template <class Real>
struct NeighborGrid {
  Real origin[3] = {0, 0, 0};
  Real cell_size = 1;
  std::uint32_t bucket_mask = 0;  // table size - 1 (a power of two)
  // Dense numbering: the cells of a box of dims[0] x dims[1] x dims[2] cells from origin - one
  // cell, bucket = (cx + 1) + dims[0] (cy + 1 + dims[1] (cz + 1)), within the table. 0: hashed
  // (the GPU's grids, a fixed origin, particles spread over too many cells).
  std::int64_t dims[3] = {0, 0, 0};
};

// Integer cell coordinate of x (floor((x - origin) / cell)), clamped to +-2^40 so that a far-off
// particle cannot overflow the hash; clamping merges far cells, which only adds candidates.
template <class Real>
TALUS_HD inline std::int64_t cell_coordinate(Real x, Real origin, Real cell_size) {
  const Real c = (x - origin) / cell_size;
  const Real limit = Real(1099511627776.0);  // 2^40
  const Real clamped = c < -limit ? -limit : (c > limit ? limit : c);
  std::int64_t i = static_cast<std::int64_t>(clamped);
  if (Real(i) > clamped) --i;  // floor for negative values
  return i;
}

TALUS_HD inline std::uint32_t cell_bucket(std::int64_t cx, std::int64_t cy, std::int64_t cz,
                                          std::uint32_t mask) {
  // Large odd multipliers mix the three coordinates (Teschner et al. 2003 use these primes).
  const std::uint64_t h = static_cast<std::uint64_t>(cx) * 73856093ull ^
                          static_cast<std::uint64_t>(cy) * 19349663ull ^
                          static_cast<std::uint64_t>(cz) * 83492791ull;
  return static_cast<std::uint32_t>((h ^ (h >> 29)) & mask);
}

// The bucket of cell (cx, cy, cz): its dense index, or its hash.
template <class Real>
TALUS_HD inline std::uint32_t grid_bucket(const NeighborGrid<Real>& grid, std::int64_t cx,
                                          std::int64_t cy, std::int64_t cz) {
  if (grid.dims[0] > 0)
    return static_cast<std::uint32_t>((cx + 1 + grid.dims[0] * (cy + 1 + grid.dims[1] * (cz + 1))) &
                                      grid.bucket_mask);
  return cell_bucket(cx, cy, cz, grid.bucket_mask);
}

template <class Real>
TALUS_HD inline std::uint32_t particle_bucket(const NeighborInput<Real>& in,
                                              const NeighborGrid<Real>& grid, int i) {
  return grid_bucket(grid, cell_coordinate(in.x[i], grid.origin[0], grid.cell_size),
                     cell_coordinate(in.y[i], grid.origin[1], grid.cell_size),
                     cell_coordinate(in.z[i], grid.origin[2], grid.cell_size));
}

// Spreads the low 21 bits of v three apart (bit k to bit 3k): one coordinate of a Morton code.
TALUS_HD inline std::uint64_t spread_bits_by_three(std::uint64_t v) {
  v &= 0x1fffffull;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// The Z-order (Morton) key of particle i's cell: its cell coordinates from the grid's origin,
// clamped to [0, 2^21), bits interleaved. Particles sorted by it sit with those of their own cell
// and, mostly, of the cells next to it: the order the step renumbers them in (`reorder`).
template <class Real>
TALUS_HD inline std::uint64_t particle_cell_key(const NeighborInput<Real>& in,
                                                const NeighborGrid<Real>& grid, int i) {
  const Real* coordinates[3] = {in.x, in.y, in.z};
  std::uint64_t key = 0;
  for (int k = 0; k < 3; ++k) {
    std::int64_t c = cell_coordinate(coordinates[k][i], grid.origin[k], grid.cell_size);
    c = c < 0 ? 0 : (c > 0x1fffff ? 0x1fffff : c);
    key |= spread_bits_by_three(static_cast<std::uint64_t>(c)) << k;
  }
  return key;
}

// The distinct buckets of particle i's 27 neighbour cells, ascending; returns how many (<= 27).
template <class Real>
TALUS_HD inline int neighbour_buckets(const NeighborInput<Real>& in, const NeighborGrid<Real>& grid,
                                      int i, std::uint32_t (&buckets)[27]) {
  const std::int64_t cx = cell_coordinate(in.x[i], grid.origin[0], grid.cell_size);
  const std::int64_t cy = cell_coordinate(in.y[i], grid.origin[1], grid.cell_size);
  const std::int64_t cz = cell_coordinate(in.z[i], grid.origin[2], grid.cell_size);
  int n = 0;
  if (grid.dims[0] > 0) {  // dense: 27 distinct buckets, ascending in this order
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          buckets[n++] = grid_bucket(grid, cx + dx, cy + dy, cz + dz);
    return n;
  }
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        const std::uint32_t b = cell_bucket(cx + dx, cy + dy, cz + dz, grid.bucket_mask);
        // Insertion into the sorted list, skipping a bucket already there.
        int k = n;
        while (k > 0 && buckets[k - 1] > b) --k;
        if (k > 0 && buckets[k - 1] == b) continue;
        for (int m = n; m > k; --m) buckets[m] = buckets[m - 1];
        buckets[k] = b;
        ++n;
      }
    }
  }
  return n;
}

// The bounding-sphere test: |x_a - x_b| <= r_a + r_b + skin (touching counts).
template <class Real>
TALUS_HD inline bool spheres_overlap(const NeighborInput<Real>& in, int a, int b) {
  const Real dx = in.x[a] - in.x[b], dy = in.y[a] - in.y[b], dz = in.z[a] - in.z[b];
  const Real reach = in.radius[a] + in.radius[b] + in.skin;
  return dx * dx + dy * dy + dz * dz <= reach * reach;
}

// Visits every j > i whose sphere overlaps i's, bucket by bucket: bucket b holds
// sorted[bucket_begin[b]] .. sorted[bucket_end[b] - 1] (sorted: particle indices ordered by
// bucket). Calls visit(j).
template <class Real, class Visit>
TALUS_HD inline void for_each_partner(const NeighborInput<Real>& in, const NeighborGrid<Real>& grid,
                                      const int* bucket_begin, const int* bucket_end,
                                      const int* sorted, int i, Visit&& visit) {
  std::uint32_t buckets[27];
  const int n = neighbour_buckets(in, grid, i, buckets);
  for (int k = 0; k < n; ++k) {
    for (int s = bucket_begin[buckets[k]]; s < bucket_end[buckets[k]]; ++s) {
      const int j = sorted[s];
      if (j > i && spheres_overlap(in, i, j)) visit(j);
    }
  }
}

// Sorts pairs[begin, end) by b (insertion sort: one particle's segment holds its few partners),
// so that the list does not depend on the hash or on the order of the buckets.
TALUS_HD inline void sort_segment_by_partner(ContactPair* pairs, int begin, int end) {
  for (int s = begin + 1; s < end; ++s) {
    const ContactPair p = pairs[s];
    int t = s;
    while (t > begin && pairs[t - 1].b > p.b) {
      pairs[t] = pairs[t - 1];
      --t;
    }
    pairs[t] = p;
  }
}

// ---- Host driver (std::vector; the CUDA backend runs the same steps with CUB).

// What one build did, for the step's statistics and the tests.
struct NeighborStats {
  int buckets = 0;
  long long candidates = 0;  // particles looked at in neighbour buckets (j > i), before the test
  long long pairs = 0;
};

// The grid for these particles: cells of 2 r_max + skin (at least `min_cell`), origin at the
// lowest corner, about 2 buckets per particle, hashed; with `dense`, numbered densely where the
// particles' box (one cell of margin around) has at most 4 cells a particle (and 2^30 in all).
// Throws std::invalid_argument for a non-finite position or radius, naming the particle.
template <class Real>
NeighborGrid<Real> make_neighbor_grid(const NeighborInput<Real>& in, Real min_cell = 0,
                                      bool dense = false) {
  NeighborGrid<Real> grid;
  Real r_max = 0;
  Real top[3] = {0, 0, 0};
  for (int i = 0; i < in.count; ++i) {
    const Real v[4] = {in.x[i], in.y[i], in.z[i], in.radius[i]};
    for (int k = 0; k < 4; ++k) {
      if (!is_finite(v[k]) || (k == 3 && v[k] < 0)) {
        throw std::invalid_argument("neighbour search: particle " + std::to_string(i) +
                                    " has a non-finite position or a bad bounding radius");
      }
    }
    for (int k = 0; k < 3; ++k) {
      grid.origin[k] = i == 0 ? v[k] : min_of(grid.origin[k], v[k]);
      top[k] = i == 0 ? v[k] : max_of(top[k], v[k]);
    }
    r_max = max_of(r_max, v[3]);
  }
  if (in.fixed_origin)
    for (int k = 0; k < 3; ++k) grid.origin[k] = in.origin[k];
  grid.cell_size = max_of(min_cell, Real(2) * r_max + in.skin);
  if (!(grid.cell_size > 0)) grid.cell_size = 1;  // all points: any size bins them
  std::uint32_t size = 64;
  while (size < 2u * static_cast<std::uint32_t>(in.count) && size < (1u << 30)) size *= 2;
  grid.bucket_mask = size - 1;
  if (dense && !in.fixed_origin && in.count > 0) {
    double cells = 1;
    std::int64_t dims[3];
    for (int k = 0; k < 3; ++k) {
      dims[k] = cell_coordinate(top[k], grid.origin[k], grid.cell_size) + 3;  // margin each side
      cells *= double(dims[k]);
    }
    if (cells <= 4.0 * in.count + 64 && cells <= double(1u << 30)) {
      std::uint32_t dense_size = 64;
      while (dense_size < cells) dense_size *= 2;
      grid.bucket_mask = std::max(grid.bucket_mask, dense_size - 1);
      for (int k = 0; k < 3; ++k) grid.dims[k] = dims[k];
    }
  }
  return grid;
}

// Every pair of particles whose bounding spheres overlap (within the skin), as ContactPair
// {a, b} with a < b, sorted by (a, b): bin, count per particle, exclusive scan, write. The
// per-particle loops run on `threads` threads (the same list for any count).
template <class Real>
std::vector<ContactPair> build_candidate_pairs(const NeighborInput<Real>& in,
                                               NeighborStats* stats = nullptr, Real min_cell = 0,
                                               int threads = 1) {
  const NeighborGrid<Real> grid = make_neighbor_grid(in, min_cell, /*dense=*/true);
  const int buckets = static_cast<int>(grid.bucket_mask) + 1;
  // Bin: bucket of each particle, counting sort into `sorted` (stable: indices ascend per bucket).
  std::vector<std::uint32_t> bucket_of(in.count);
  std::vector<int> bucket_start(buckets + 1, 0);
  parallel_for(threads, in.count,
               [&](long long i) { bucket_of[i] = particle_bucket(in, grid, static_cast<int>(i)); });
  for (int i = 0; i < in.count; ++i) ++bucket_start[bucket_of[i] + 1];
  for (int b = 0; b < buckets; ++b) bucket_start[b + 1] += bucket_start[b];
  std::vector<int> sorted(in.count), fill(bucket_start.begin(), bucket_start.end() - 1);
  for (int i = 0; i < in.count; ++i) sorted[fill[bucket_of[i]]++] = i;

  // Count, exclusive scan, write (paper Fig. 3c).
  std::vector<int> first(in.count + 1, 0);
  long long candidates = 0;
  const int* begin = bucket_start.data();
  const int* end = bucket_start.data() + 1;
  // The spheres in bucket order, so that a bucket's candidates are one run of memory (not a
  // cache miss each); the particles visited in that order too, in chunks of 128 (visiting 27
  // cells costs about a microsecond a particle), so that neighbours' cells are shared in cache.
  struct Sphere {
    Real x, y, z, r;
  };
  std::vector<Sphere> spheres(in.count);
  parallel_for(threads, in.count, [&](long long s) {
    const int j = sorted[s];
    spheres[s] = Sphere{in.x[j], in.y[j], in.z[j], in.radius[j]};
  });
  // for_each_partner on the bucket-ordered copy: the partners j > i of sorted[index].
  const auto partners = [&](long long index, auto&& visit) {
    const int i = sorted[index];
    std::uint32_t visited[27];
    const int n = neighbour_buckets(in, grid, i, visited);
    const Sphere& p = spheres[index];
    for (int k = 0; k < n; ++k) {
      for (int s = begin[visited[k]]; s < end[visited[k]]; ++s) {
        const int j = sorted[s];
        const Sphere& q = spheres[s];
        // spheres_overlap(in, i, j), term for term (the same list as the GPU's).
        const Real dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z, reach = p.r + q.r + in.skin;
        if (j > i && dx * dx + dy * dy + dz * dz <= reach * reach) visit(j);
      }
    }
  };
  parallel_for_dynamic(threads, in.count, 128, [&](long long index) {
    int count = 0;
    partners(index, [&](int) { ++count; });
    first[sorted[index] + 1] = count;
  });
  for (int i = 0; i < in.count; ++i) first[i + 1] += first[i];
  std::vector<ContactPair> pairs(first[in.count]);
  parallel_for_dynamic(threads, in.count, 128, [&](long long index) {
    const int i = sorted[index];
    int slot = first[i];
    partners(index, [&](int j) { pairs[slot++] = ContactPair{i, j}; });
    sort_segment_by_partner(pairs.data(), first[i], first[i + 1]);
  });
  if (stats) {
    stats->buckets = buckets;
    for (int i = 0; i < in.count; ++i) {
      std::uint32_t visited[27];
      const int n = neighbour_buckets(in, grid, i, visited);
      for (int k = 0; k < n; ++k) {
        for (int s = bucket_start[visited[k]]; s < bucket_start[visited[k] + 1]; ++s) {
          candidates += sorted[s] > i ? 1 : 0;
        }
      }
    }
    stats->candidates = candidates;
    stats->pairs = static_cast<long long>(pairs.size());
  }
  return pairs;
}

// The particles' indices in the order of their cells' Morton keys (particle_cell_key over
// make_neighbor_grid's grid); a stable sort, so particles of one cell keep their order.
template <class Real>
std::vector<int> cell_order(const NeighborInput<Real>& in, int threads = 1) {
  const NeighborGrid<Real> grid = make_neighbor_grid(in);
  std::vector<std::uint64_t> key(in.count);
  parallel_for(threads, in.count,
               [&](long long i) { key[i] = particle_cell_key(in, grid, static_cast<int>(i)); });
  std::vector<int> order(in.count);
  for (int i = 0; i < in.count; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  return order;
}

}  // namespace talus
