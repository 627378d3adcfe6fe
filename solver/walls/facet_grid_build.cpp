#include "solver/walls/facet_grid_build.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace talus {

bool triangle_meets_box(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& centre,
                        const Vec3d& half) {
  const Vec3d v[3] = {a - centre, b - centre, c - centre};
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = std::min({v[0][axis], v[1][axis], v[2][axis]});
    const double hi = std::max({v[0][axis], v[1][axis], v[2][axis]});
    if (lo > half[axis] || hi < -half[axis]) return false;
  }
  const Vec3d edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const auto separates = [&](const Vec3d& axis) {
    const double r =
        half.x * std::fabs(axis.x) + half.y * std::fabs(axis.y) + half.z * std::fabs(axis.z);
    const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  if (separates(cross(edges[0], edges[1]))) return false;  // the triangle's plane
  const Vec3d units[3] = {Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1)};
  for (const Vec3d& u : units) {
    for (const Vec3d& e : edges) {
      if (separates(cross(u, e))) return false;
    }
  }
  return true;
}

template <class Real>
FacetGrid<Real>::FacetGrid(const std::vector<Vec3d>& vertices,
                           const std::vector<std::array<int, 3>>& triangles, double max_radius) {
  const int facets = static_cast<int>(triangles.size());
  const double inf = std::numeric_limits<double>::infinity();
  Vec3d lo(inf, inf, inf), hi(-inf, -inf, -inf);
  double vertex_scale = 0;
  for (int t = 0; t < facets; ++t) {
    for (const int k : triangles[t]) {
      if (k < 0 || k >= static_cast<int>(vertices.size()) || !is_finite(vertices[k])) {
        throw std::invalid_argument("wall mesh: triangle " + std::to_string(t) +
                                    " has a bad or non-finite corner");
      }
      const Vec3d& p = vertices[k];
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
      vertex_scale = std::max(vertex_scale, norm(p));
    }
  }
  if (facets == 0) lo = hi = Vec3d();
  const Vec3d extent = hi - lo;

  // The cell size h, the larger of:
  // - 2 (r_max + margin): a particle's query box then spans at most 2 cells per axis, so the
  //   query merges at most 8 ascending lists (FacetCursor's fast path). The margin is the
  //   query's for particles within the mesh's reach (|centre|, |translation| of a few times its
  //   scale);
  // - the smallest size that keeps the grid within the cell budget (max(2^15, 64 x facets)
  //   cells), so that memory follows the mesh, not the ratio of container to particle size.
  // The facet sizes need no term of their own: a facet larger than the cells is listed in each
  // cell its triangle crosses (area / h^2 entries), which costs entries but no candidates (a
  // particle still meets only the facets crossing its few cells), and facets smaller than the
  // cells are the ones a particle of that size reaches anyway. The listing is by the triangle,
  // not its bounding box, so that long thin facets (a cylinder's side, a cap's fan) stay in the
  // cells along them.
  const double margin = double(facet_grid_margin(Real(4 * vertex_scale + max_radius)));
  double h = 2 * (std::max(max_radius, 0.0) + margin);
  const double budget = std::max(kMinCells, kCellsPerFacet * facets);
  const double widest = std::max({extent.x, extent.y, extent.z});
  if (!(h > 0) || !std::isfinite(h)) h = widest > 0 ? widest : 1.0;
  h = std::max(h, widest / budget);
  const auto cells_at = [&](double size) {
    double n = 1;
    for (int a = 0; a < 3; ++a) n *= std::max(1.0, std::ceil(extent[a] / size));
    return n;
  };
  while (cells_at(h) > budget) h *= 1.0625;

  // The cell size and origin as the query sees them, in Real; the listing below uses these
  // rounded values (exact in double), so both agree on where the cells are.
  FacetGridView<Real>& g = shape_;
  g.cell_size = Real(h);
  g.origin = Vec3<Real>(lo);
  const double size = double(g.cell_size);
  const Vec3d origin(g.origin);
  double span = 0;
  for (int a = 0; a < 3; ++a) {
    g.dims[a] = std::max(1, static_cast<int>(std::ceil(extent[a] / size)));
    // The rounded origin may sit above lo: one more cell if the last would not reach hi.
    if (origin[a] + g.dims[a] * size < hi[a]) ++g.dims[a];
    span += g.dims[a] * size;
  }
  g.scale = Real(vertex_scale + norm(origin) + span);

  // The listing's own round-off (double, magnitudes within the grid's scale): every box grows by
  // it, so a triangle on a cell's face is listed on both sides.
  const double grow = double(facet_grid_margin(vertex_scale + norm(origin) + span));
  const auto cell_of = [&](double x, int a) {
    const double q = std::floor((x - origin[a]) / size);
    return q <= 0 ? 0 : q >= g.dims[a] - 1 ? g.dims[a] - 1 : static_cast<int>(q);
  };
  const long long cells = static_cast<long long>(g.dims[0]) * g.dims[1] * g.dims[2];
  std::vector<long long> entry_cell;  // per (cell, facet) entry, in facet order
  std::vector<int> entry_facet;
  for (int t = 0; t < facets; ++t) {
    const Vec3d& a = vertices[triangles[t][0]];
    const Vec3d& b = vertices[triangles[t][1]];
    const Vec3d& c = vertices[triangles[t][2]];
    int first[3], last[3];
    Vec3d facet_lo, facet_hi;
    for (int k = 0; k < 3; ++k) {
      facet_lo[k] = std::min({a[k], b[k], c[k]});
      facet_hi[k] = std::max({a[k], b[k], c[k]});
      first[k] = cell_of(facet_lo[k] - grow, k);
      last[k] = cell_of(facet_hi[k] + grow, k);
    }
    for (int z = first[2]; z <= last[2]; ++z) {
      for (int y = first[1]; y <= last[1]; ++y) {
        for (int x = first[0]; x <= last[0]; ++x) {
          const int index[3] = {x, y, z};
          Vec3d box_lo, box_hi;
          for (int k = 0; k < 3; ++k) {
            // The boundary cells reach to infinity (the query clamps to them); the part that
            // matters is where the facet is.
            box_lo[k] =
                index[k] == 0 ? std::min(origin[k], facet_lo[k]) : origin[k] + index[k] * size;
            box_hi[k] = index[k] == g.dims[k] - 1
                            ? std::max(origin[k] + g.dims[k] * size, facet_hi[k])
                            : origin[k] + (index[k] + 1) * size;
          }
          const Vec3d half = (box_hi - box_lo) * 0.5 + Vec3d(grow, grow, grow);
          if (triangle_meets_box(a, b, c, (box_lo + box_hi) * 0.5, half)) {
            entry_cell.push_back(x + g.dims[0] * (y + static_cast<long long>(g.dims[1]) * z));
            entry_facet.push_back(t);
          }
        }
      }
    }
  }
  if (entry_facet.size() >= static_cast<std::size_t>(INT_MAX)) {
    throw std::invalid_argument("wall mesh: the facet grid would hold more than 2^31 entries");
  }
  // A counting sort by cell, stable: each cell's facets stay ascending.
  cell_start_.assign(cells + 1, 0);
  for (const long long cell : entry_cell) ++cell_start_[cell + 1];
  for (long long k = 0; k < cells; ++k) cell_start_[k + 1] += cell_start_[k];
  cell_facets_.resize(entry_facet.size());
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t e = 0; e < entry_facet.size(); ++e) {
    cell_facets_[fill[entry_cell[e]]++] = entry_facet[e];
  }
}

template class FacetGrid<float>;
template class FacetGrid<double>;

}  // namespace talus
