// Helpers of the reference-geometry tests: boxes given by their vertices only (the reference reads
// nothing else of a template), so that binary-exact sizes stay exact through the pose.
#pragma once

#include <Eigen/Geometry>
#include <array>

#include "reference/geometry/exact_convex.hpp"
#include "solver/shape/shape.hpp"

namespace talus::reference::testing {

// Closed forms: the coordinates are rounded once to double (sizes ~1e-2 m, so 1e-18 m), the
// polytope is exact, and the measures are sums of a few dozen double products of coordinates
// taken about a vertex: a few hundred eps relative at most. 1e-12 leaves margin and still fails
// on any misplaced facet or wrong weight (those are O(1) errors).
inline constexpr double kClosedRel = 1e-12;

// Axis-aligned box with side lengths (lx, ly, lz) about the origin: its 8 corners.
inline ShapeTemplate box_vertices(double lx, double ly, double lz) {
  ShapeTemplate s;
  s.name = "box";
  for (int i = 0; i < 8; ++i) {
    s.vertices.push_back(
        {(i & 1 ? 0.5 : -0.5) * lx, (i & 2 ? 0.5 : -0.5) * ly, (i & 4 ? 0.5 : -0.5) * lz});
  }
  s.volume = lx * ly * lz;
  return s;
}

inline RefPose at(double x, double y, double z,
                  const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  RefPose p;
  p.position = Eigen::Vector3d(x, y, z);
  p.orientation = q;
  return p;
}

inline Eigen::Vector3d to_eigen(const Vec3d& v) {
  return {v.x, v.y, v.z};
}

// The pose turned by `angle` about the unit axis e through its position (the body's centroid).
inline RefPose turned(const RefPose& p, const Eigen::Vector3d& e, double angle) {
  RefPose q = p;
  q.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, e)) * p.orientation;
  return q;
}

// The axes the turn tests check: the coordinate axes and `extra` (unit).
inline std::array<Eigen::Vector3d, 4> turn_axes(const Eigen::Vector3d& extra) {
  return {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), extra};
}

}  // namespace talus::reference::testing
