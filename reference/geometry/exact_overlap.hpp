// Reference overlap of two posed convex polyhedra (the oracle for solver/geometry/overlap_*.hpp):
// the intersection polytope built exactly with CGAL, its volume, centroid and the vector area and
// surface moment of its boundary on A's surface.
#pragma once

#include <Eigen/Core>

#include "reference/geometry/exact_convex.hpp"
#include "solver/shape/shape.hpp"

namespace talus::reference {

struct RefOverlap {
  bool overlapping = false;  // the intersection has interior (positive exact volume)
  bool touching = false;     // common points but no interior
  double volume = 0;         // m^3
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world; zero unless overlapping
  // m^2: sum of (outward area vector) over the intersection's facets lying on A's surface; a facet
  // lying on both surfaces counts half. Points from A into B (dV/dx_A = +S).
  Eigen::Vector3d vector_area_a = Eigen::Vector3d::Zero();
  // m^3: the moment of that same part of the boundary about the centroid, the integral of
  // (r - centroid) x n dA (each flat facet: (its centroid - centroid) x its area vector), with the
  // same half weight for shared facets. Turning A by a small angle theta about a unit axis e
  // through x_A changes the volume by dV/dtheta = e . ((centroid - x_A) x S + M): the surface
  // moves at e x (r - x_A). So U(V)'s couple on A about the centroid is -U'(V) M.
  Eigen::Vector3d surface_moment_a = Eigen::Vector3d::Zero();
  double boundary_area = 0;  // m^2: total area of the intersection's surface
  int facets = 0;            // triangles of the intersection's hull
};

// A and B are the convex hulls of their templates' vertices placed by the poses (rounded once to
// double). The intersection P = A ∩ B is the convex hull of the end points of A's edges clipped
// to B and of B's edges clipped to A: every vertex of P lies on an edge of A or of B (its minimal
// faces in A and B have dimensions summing to at most 3), and every clipped end point is in P.
// Clipping, the hull and the facet classification use exact arithmetic
// (CGAL::Exact_predicates_exact_constructions_kernel), so coplanar faces, touching contact and
// coincident vertices need no tolerance; the measures are then summed in double.
RefOverlap exact_overlap(const ShapeTemplate& a, const RefPose& pose_a, const ShapeTemplate& b,
                         const RefPose& pose_b);

RefOverlap exact_overlap(const ExactConvex& a, const ExactConvex& b);

}  // namespace talus::reference
