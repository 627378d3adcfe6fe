// A uniform bin grid over one wall's facets (paper §2.4: particle-triangle candidates from a bin
// grid), and its query as TALUS_HD code: the wall stage runs it per particle and wall on the host
// and on the GPU. The grid is built once, on the host (facet_grid_build.hpp), in the mesh's own
// frame: walls move rigidly, so the particle's centre is mapped into that frame by the inverse of
// the wall's current transform instead of rebuilding the grid as the wall moves.
//
// Layout (CSR in plain arrays, so that a device copy is two pointers): cell (x, y, z) has index
// x + nx (y + ny z); its facets are cell_facets[cell_start[c] .. cell_start[c + 1]), ascending.
// A facet is listed in every cell its triangle meets (the boundary cells reach to infinity, as
// the query clamps to them).
//
// The query (FacetCursor) yields the facets of the cells that the particle's bounding-sphere box
// touches, each once and in ascending index, and stops at the wall's present count (a closed
// outlet's plate is the mesh's last triangles). The wall stage still applies its exact test
// (closest point farther than the bounding radius) to each, so the grid only prunes facets that
// test would skip, and the area-weighted sums run over the same facets in the same order as
// brute force: the same bits (tests/walls/test_facet_grid.cpp tests the query against brute
// force, tests/step/test_wall_grid_step.cpp the step with it).
#pragma once

#include "solver/core/hd.hpp"
#include "solver/core/math.hpp"
#include "solver/core/quat.hpp"
#include "solver/core/vec3.hpp"

namespace talus {

// How the wall stage finds a particle's facets: through the grid (the default) or by testing
// every facet of the wall (kept for the benchmarks and as the tests' oracle).
enum class WallSearch { grid, brute_force };

// The margin (m) added to the query box for round-off, given a bound `scale` (m) on the
// magnitudes involved. The exact test runs on the placed corners in Real (each mesh-frame corner
// moved in double, then rounded), the grid on the mesh-frame triangles, with the centre mapped
// back in Real; the inverse rotation and translation, the corners' rounding, the cell index and
// closest_point_on_triangle each err by a few units of round-off of the coordinates (the last
// more on thin triangles: roughly |p - a| |p - c| / (2 area) units, which for a fan facet of a
// 1000-segment cap is about a hundred). 1024 units is generous and still far below a cell:
// 2.3e-13 scale in double, 1.2e-4 scale in float.
template <class Real>
TALUS_HD inline Real facet_grid_margin(Real scale) {
  return Real(1024) * Eps<Real>::value * scale;
}

// One wall's grid, non-owning (host or device arrays; FacetGrid owns the host copies). Absent
// (null arrays): the query yields every facet.
template <class Real>
struct FacetGridView {
  Vec3<Real> origin;   // the lower corner of cell (0, 0, 0), mesh frame, m
  Real cell_size = 0;  // m
  int dims[3] = {0, 0, 0};
  Real scale = 0;  // bounds |vertex|, |origin| and the grid's extent, m (the margin's)
  const int* cell_start = nullptr;   // dims[0] dims[1] dims[2] + 1 offsets into cell_facets
  const int* cell_facets = nullptr;  // per cell, ascending facet indices
  TALUS_HD bool present() const { return cell_start != nullptr; }
};

// The facets near one particle, in ascending index, each once: `next()` returns the next one or
// -1. No fixed cap: a box over at most kMergedCells cells (the usual case, since cells are at
// least a particle's diameter: at most 2 x 2 x 2) is a k-way merge of the cells' ascending lists
// (each step takes the smallest head and advances every list at it, which drops duplicates);
// a larger box (a particle larger than the scene's largest, or a far one in float, whose margin
// is large) falls back to a search: each step takes the smallest facet above the last over all
// its cells, by binary search in each list. Without a grid, or for a non-finite centre (which
// the exact test cannot skip), every facet below `count` in order, as brute force.
template <class Real>
class FacetCursor {
 public:
  static constexpr int kMergedCells = 8;

  // Every facet 0 .. count - 1.
  TALUS_HD explicit FacetCursor(int count) : count_(count) {}

  // The facets below `count` listed in the cells that the box of the sphere (centre, radius)
  // touches, the centre in world coordinates; the wall's mesh is now at
  // world = rotate(rotation, mesh) + translation.
  TALUS_HD FacetCursor(const FacetGridView<Real>& grid, int count, const Quat<Real>& rotation,
                       const Vec3<Real>& translation, const Vec3<Real>& centre, Real radius)
      : count_(count) {
    if (!grid.present() || count <= 0) return;
    const Vec3<Real> local = rotate_inverse(rotation, centre - translation);
    // An infinite radius or scale gives the whole grid (in the search), still correct.
    const Real scale = norm(centre) + norm(translation) + grid.scale + radius;
    if (!is_finite(local) || !(radius >= Real(0))) return;
    const Real reach = radius + facet_grid_margin(scale);
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const Real c = local[a] - grid.origin[a];
      const Real first = (c - reach) / grid.cell_size, last = (c + reach) / grid.cell_size;
      const Real top = Real(grid.dims[a] - 1);
      // Every facet lies within the grid's box [0, dims] (up to the origin's rounding, far below
      // a cell): a box a cell beyond it on some axis meets none. Nearer, the query clamps to the
      // boundary cells, which hold what lies beyond their outer faces.
      if (!(last >= Real(-1)) || !(first <= top + Real(2))) {
        mode_ = Mode::merge;
        return;
      }
      // Clamped before the conversion (no overflow); truncation is floor for values >= 0.
      lo[a] = first <= Real(0) ? 0 : static_cast<int>(first);
      hi[a] = last >= top ? grid.dims[a] - 1 : static_cast<int>(last);
    }
    facets_ = grid.cell_facets;
    start_ = grid.cell_start;
    const long long cells =
        static_cast<long long>(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    if (cells <= kMergedCells) {
      mode_ = Mode::merge;
      for (int z = lo[2]; z <= hi[2]; ++z) {
        for (int y = lo[1]; y <= hi[1]; ++y) {
          for (int x = lo[0]; x <= hi[0]; ++x) {
            const int cell = x + grid.dims[0] * (y + grid.dims[1] * z);
            if (start_[cell] < start_[cell + 1]) {
              begin_[lists_] = start_[cell];
              end_[lists_] = start_[cell + 1];
              ++lists_;
            }
          }
        }
      }
      return;
    }
    mode_ = Mode::search;
    for (int a = 0; a < 3; ++a) lo_[a] = lo[a], hi_[a] = hi[a], dims_[a] = grid.dims[a];
  }

  // Drops every facet below `end` not yet returned (a planar patch's, planar_patch.hpp, once
  // its stand-in is clipped): next() then returns the first at or above it.
  TALUS_HD void skip_below(int end) {
    if (mode_ == Mode::all) {
      next_all_ = max_of(next_all_, end);
    } else if (mode_ == Mode::merge) {
      for (int k = 0; k < lists_; ++k) {
        int first = begin_[k], last = end_[k];  // the first entry >= end (lists ascending)
        while (first < last) {
          const int mid = first + (last - first) / 2;
          if (facets_[mid] < end) {
            first = mid + 1;
          } else {
            last = mid;
          }
        }
        begin_[k] = first;
      }
    } else {
      last_ = max_of(last_, end - 1);
    }
  }

  // The merge's lists as they stand (a warp that gathers them itself, cuda_wall_stage.cu):
  // whether the cursor merges at most kMergedCells cells' lists, list k's entries
  // entries()[list_begin(k) .. list_end(k)) (ascending facets, some maybe >= count()).
  TALUS_HD bool merging() const { return mode_ == Mode::merge; }
  TALUS_HD int lists() const { return lists_; }
  TALUS_HD int list_begin(int k) const { return begin_[k]; }
  TALUS_HD int list_end(int k) const { return end_[k]; }
  TALUS_HD const int* entries() const { return facets_; }
  TALUS_HD int count() const { return count_; }

  TALUS_HD int next() {
    if (mode_ == Mode::all) return next_all_ < count_ ? next_all_++ : -1;
    int best = count_;  // facets at or above the present count are skipped (outlet plates)
    if (mode_ == Mode::merge) {
      for (int k = 0; k < lists_; ++k) {
        if (begin_[k] < end_[k] && facets_[begin_[k]] < best) best = facets_[begin_[k]];
      }
      if (best >= count_) return -1;
      for (int k = 0; k < lists_; ++k) {
        if (begin_[k] < end_[k] && facets_[begin_[k]] == best) ++begin_[k];
      }
      return best;
    }
    for (int z = lo_[2]; z <= hi_[2]; ++z) {
      for (int y = lo_[1]; y <= hi_[1]; ++y) {
        for (int x = lo_[0]; x <= hi_[0]; ++x) {
          const int cell = x + dims_[0] * (y + dims_[1] * z);
          // The first entry above last_ (lists ascending).
          int first = start_[cell], end = start_[cell + 1];
          while (first < end) {
            const int mid = first + (end - first) / 2;
            if (facets_[mid] <= last_) {
              first = mid + 1;
            } else {
              end = mid;
            }
          }
          if (first < start_[cell + 1] && facets_[first] < best) best = facets_[first];
        }
      }
    }
    if (best >= count_) return -1;
    last_ = best;
    return best;
  }

 private:
  enum class Mode { all, merge, search };
  Mode mode_ = Mode::all;
  int count_ = 0;
  int next_all_ = 0;
  const int* facets_ = nullptr;
  const int* start_ = nullptr;
  // merge: the cells' remaining ranges
  int lists_ = 0;
  int begin_[kMergedCells] = {}, end_[kMergedCells] = {};
  // search: the box of cells and the last facet returned
  int lo_[3] = {}, hi_[3] = {}, dims_[3] = {};
  int last_ = -1;
};

}  // namespace talus
