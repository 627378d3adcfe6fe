// The bin grid over one wall's facets, built on the host once per wall (the layout and the query:
// facet_grid.hpp). Host code: std::vector, exceptions.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "solver/walls/facet_grid.hpp"

namespace talus {

template <class Real>
class FacetGrid {
 public:
  // The cell budget: at most max(kMinCells, kCellsPerFacet x facets) cells (4 bytes each).
  static constexpr double kMinCells = 32768;
  static constexpr double kCellsPerFacet = 64;

  // Over the triangles of a mesh (in its own frame; indices into `vertices`), for particles whose
  // bounding radius is at most `max_radius` (m). Throws std::invalid_argument for a non-finite
  // corner or a bad index, naming the triangle.
  FacetGrid(const std::vector<Vec3d>& vertices, const std::vector<std::array<int, 3>>& triangles,
            double max_radius);

  // The view over this object's arrays, or over copies of them elsewhere (the device).
  FacetGridView<Real> view() const { return view_of(cell_start_.data(), cell_facets_.data()); }
  FacetGridView<Real> view_of(const int* cell_start, const int* cell_facets) const {
    FacetGridView<Real> v = shape_;
    v.cell_start = cell_start;
    v.cell_facets = cell_facets;
    return v;
  }
  const std::vector<int>& cell_start() const { return cell_start_; }
  const std::vector<int>& cell_facets() const { return cell_facets_; }
  std::size_t bytes() const {
    return (cell_start_.capacity() + cell_facets_.capacity()) * sizeof(int);
  }

 private:
  FacetGridView<Real> shape_;  // origin, cell size, dims, scale; no arrays
  std::vector<int> cell_start_, cell_facets_;
};

// Whether triangle (a, b, c) meets the box centre +- half (the separating-axis test of
// Akenine-Moeller: the box's 3 axes, the triangle's normal, the 9 edge x axis directions). A
// degenerate triangle is never separated by its zero axes, so it is kept: conservative.
bool triangle_meets_box(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& centre,
                        const Vec3d& half);

extern template class FacetGrid<float>;
extern template class FacetGrid<double>;

}  // namespace talus
