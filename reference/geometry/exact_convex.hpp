// Shared pieces of the reference geometry: a posed template as an exact convex polytope (CGAL,
// exact predicates and exact constructions), segment clipping by half-spaces, and the measures of
// a convex point set. Independent of solver/geometry: only the template's vertex list is read.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "solver/core/quat.hpp"
#include "solver/shape/shape.hpp"

namespace talus::reference {

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactPoint = ExactKernel::Point_3;
using ExactPlane = ExactKernel::Plane_3;
using ExactMesh = CGAL::Surface_mesh<ExactPoint>;

// Body -> world: x = position + R(orientation) body. The quaternion is normalised here.
struct RefPose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// The production solver's pose type, converted (values only; no code of solver/ is used).
inline RefPose to_ref_pose(const Posed& p) {
  RefPose r;
  r.position = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  r.orientation =
      Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  return r;
}

// A posed template: the convex hull of its world vertices (rounded once to double, then exact).
// Merged faces whose rounded vertices are no longer coplanar become a slightly folded pair of
// facets: the polytope is exactly the hull of the rounded vertices, nothing else.
struct ExactConvex {
  std::vector<ExactPoint> vertices;       // hull vertices
  std::vector<std::array<int, 2>> edges;  // hull edges (diagonals of coplanar facets included)
  std::vector<ExactPlane> planes;         // facet planes, positive side = outside
};

// World vertices of a posed template, in double.
std::vector<Eigen::Vector3d> world_vertices(const ShapeTemplate& shape, const RefPose& pose);

ExactConvex make_exact_convex(const ShapeTemplate& shape, const RefPose& pose);

// Clip the segment [p0, p1] to the intersection of the half-spaces (the closed negative sides of
// `planes`). Appends the end points of the clipped segment (both, possibly equal) to `out`;
// returns false when nothing is left.
bool clip_segment(const ExactPoint& p0, const ExactPoint& p1, const std::vector<ExactPlane>& planes,
                  std::vector<ExactPoint>& out);

// True when the points span 3-D space (exact orientation test).
bool is_full_dimensional(const std::vector<ExactPoint>& points);

// Volume and volume centroid of a closed, outward-oriented triangle mesh with exact points,
// computed in double about the first vertex (CGAL::Polygon_mesh_processing volume and centroid).
struct MeshMeasures {
  double volume = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};
MeshMeasures measure_mesh(const ExactMesh& mesh);

// A lazy exact number rounded to double within a few ulps. CGAL::to_double of a lazy number only
// guarantees 1e-5 relative (the interval's midpoint, refined below that precision), which is far
// too coarse for an oracle: refine the interval to 1e-15, else round the exact value.
inline double to_double_tight(const ExactKernel::FT& x) {
  const auto& interval = x.approx();
  if (CGAL::has_smaller_relative_precision(interval, 1e-15)) return CGAL::to_double(interval);
  return CGAL::to_double(x.exact());
}

inline Eigen::Vector3d to_eigen(const ExactPoint& p) {
  return {to_double_tight(p.x()), to_double_tight(p.y()), to_double_tight(p.z())};
}

}  // namespace talus::reference
