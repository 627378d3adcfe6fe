// Building a polyhedron template from a point cloud (paper §2.1): convex hull, merged faces,
// exact mass properties and the principal-axes body frame.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "solver/shape/shape.hpp"

namespace talus {

using Matrix3d = std::array<std::array<double, 3>, 3>;

// Volume, centroid and inertia tensor about the centroid, per unit density, of the solid bounded
// by a closed outward triangulation (signed-tetrahedron decomposition).
struct MassProperties {
  double volume = 0;   // m^3
  Vec3d centroid;      // m
  Matrix3d inertia{};  // m^5
};
MassProperties mass_properties(const std::vector<Vec3d>& vertices,
                               const std::vector<std::array<int, 3>>& triangles);

// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations: values ascending,
// vectors[k] the unit eigenvector of values[k], and (vectors[0], vectors[1], vectors[2]) a
// right-handed orthonormal frame even where values coincide.
struct SymmetricEigen {
  Vec3d values;
  std::array<Vec3d, 3> vectors;
};
SymmetricEigen symmetric_eigen(const Matrix3d& matrix);

// Unit quaternion of the rotation whose matrix has the given columns (a right-handed frame).
Quatd quaternion_from_columns(const std::array<Vec3d, 3>& columns);

// The most points a template is built from: the hull of 2 x 10^5 points takes several seconds
// (docs/geometry.md has the timings); a cloud larger than this is refused rather than left to run
// for minutes.
constexpr std::size_t kMaxTemplatePoints = 250000;

// The sizes a particle shape may have, in metres (a built-in spec's sizes, a mesh's extent and its
// vertices' distance from the origin after scaling). Within them the volume (~D^3) and the
// principal moments (~D^5) stay normal numbers even in single precision for densities up to
// ~10^4 kg/m^3, and the hull's tolerances resolve the shape; beyond them the hull sees round-off
// (a cube:1e300 once read as "collinear") and the mass properties overflow.
constexpr double kMinShapeSize = 1e-7;
constexpr double kMaxShapeSize = 1e6;

// "" when `metres` lies within [kMinShapeSize, kMaxShapeSize], else why not, as in "1e+300 m is
// beyond the largest size talus supports, 1e+06 m".
std::string shape_size_problem(double metres);

// The template of the convex hull of `points` (input frame, metres). Hull vertices keep the
// order in which they appear in `points`. Faces are hull triangles merged where coplanar within
// rel_tol times the cloud's extent. Throws std::runtime_error for a cloud without volume or of
// more than kMaxTemplatePoints points.
ShapeTemplate make_template(const std::string& name, const std::vector<Vec3d>& points,
                            double rel_tol = 1e-10);

// The smallest angle, in degrees, between the normals of two merged faces that share an edge
// (180 for a shape without edges). Throws std::logic_error when an edge is not shared by exactly
// two faces.
double smallest_edge_bend_degrees(const ShapeTemplate& shape);

// Body-frame vertex mapped back to the input frame: input_centroid + R(body_to_input) * body.
Vec3d body_to_input_point(const ShapeTemplate& shape, const Vec3d& body_point);

}  // namespace talus
