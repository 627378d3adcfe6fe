// Polyhedron templates (paper §2.1): convex hull of a vertex list, coplanar triangles merged into
// faces with outward normals, exact mass properties, and the body frame (principal axes).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "solver/core/quat.hpp"

namespace talus {

// A merged planar face: every point x on it satisfies dot(normal, x) = offset (body frame).
struct Face {
  Vec3d normal;           // unit, outward
  double offset = 0;      // > 0 since the centroid is inside
  std::vector<int> loop;  // vertex indices, counter-clockwise seen from outside
};

struct ShapeTemplate {
  std::string name;
  // Geometry in the body frame: centroid at the origin, axes along the principal axes of inertia.
  std::vector<Vec3d> vertices;
  std::vector<int> input_indices;  // each vertex's index in the points the template was built from
  std::vector<std::array<int, 3>> triangles;  // outward-oriented triangulation (output, §2.1)
  std::vector<Face> faces;                    // coplanar triangles merged
  std::vector<std::array<int, 2>> edges;      // edges between merged faces, i < j
  double volume = 0;                          // m^3
  Vec3d principal_moments;                    // inertia per unit density (m^5), ascending
  double bounding_radius = 0;                 // max |vertex|, m
  // Where the body frame sits in the input frame: input = input_centroid + R(body_to_input) body.
  Vec3d input_centroid;
  Quatd body_to_input;
};

}  // namespace talus
