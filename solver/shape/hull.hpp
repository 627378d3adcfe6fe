// Convex hull of a 3-D point cloud (host only), the first step of building a template (paper
// §2.1): incremental Quickhull with conflict lists, then coplanar triangles grouped into facets.
#pragma once

#include <array>
#include <vector>

#include "solver/core/vec3.hpp"

namespace talus {

// Absolute tolerance for a point cloud: rel_tol times the largest side of its bounding box.
double hull_tolerance(const std::vector<Vec3d>& points, double rel_tol);

// Outward-oriented triangles (counter-clockwise seen from outside) of the convex hull, as indices
// into `points`. Hull vertices are corners: duplicates, and points on a facet or an edge (within
// hull_tolerance(points, rel_tol), the merge tolerance) are dropped and the hull rebuilt from the
// corners, at most kCornerPasses times (a vertex left on fewer than three facets after that lies
// on an edge or inside a facet within the tolerance). Every point lies within (1 + the rebuilds
// made) times that tolerance of the inner side of every face plane: a dropped point is within it
// of its facet, whose corners are within it of the hull rebuilt without the point. Which faces a
// new point sees is decided at the smaller of that tolerance and kHullRelTol of the extent, so that
// dense points on a curved surface (closer to each other's planes than the merge tolerance) still
// give a convex triangulation; its triangles are then grouped into facets at the merge tolerance.
// Where points cluster a few tolerances apart, so that round-off cannot resolve their planes,
// both tolerances are raised tenfold (at most kToleranceRaises times, and not past
// kLargestRaisedRelTol of the extent). Expected time O(n log n) for n points. Throws
// std::runtime_error when the points do not span a volume (fewer than 4 non-coplanar points).
std::vector<std::array<int, 3>> convex_hull(const std::vector<Vec3d>& points,
                                            double rel_tol = 1e-10);

constexpr double kHullRelTol = 1e-10;
constexpr int kCornerPasses = 2;  // rebuilds of the hull from its corners (see hull.cpp)
constexpr int kToleranceRaises = 4;
constexpr double kLargestRaisedRelTol = 1e-5;

struct Hull {
  std::vector<std::array<int, 3>> triangles;
  double tolerance = 0;  // the absolute merge tolerance used, m
};
// convex_hull, also reporting the tolerance it used (for merging faces consistently).
Hull convex_hull_with_tolerance(const std::vector<Vec3d>& points, double rel_tol = 1e-10);

// Partition of a closed outward triangulation of a convex polyhedron into planar facets: each
// group holds the indices of triangles whose vertices lie within abs_tol of the plane of the
// group's largest triangle, grown across shared edges.
std::vector<std::vector<int>> coplanar_groups(const std::vector<Vec3d>& points,
                                              const std::vector<std::array<int, 3>>& triangles,
                                              double abs_tol);

// Boundary of a group of outward triangles forming a disk, as one counter-clockwise vertex loop
// seen from outside. Throws std::runtime_error if the boundary is not a single simple loop.
std::vector<int> group_boundary_loop(const std::vector<std::array<int, 3>>& triangles,
                                     const std::vector<int>& group);

}  // namespace talus
