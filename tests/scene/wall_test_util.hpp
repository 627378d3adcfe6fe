// Helpers for the tests of generated walls: triangle normals, edge counts and wall specs built
// in code.
#pragma once

#include <map>
#include <utility>

#include "solver/scene/wall_meshes.hpp"

namespace talus {

inline Vec3d triangle_normal(const TriangleMesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  const Vec3d& a = mesh.vertices[tri[0]];
  const Vec3d n = cross(mesh.vertices[tri[1]] - a, mesh.vertices[tri[2]] - a);
  return n / norm(n);
}

inline Vec3d triangle_centroid(const TriangleMesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  return (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
}

// Directed edges (from, to) of all triangles with their counts.
inline std::map<std::pair<int, int>, int> directed_edges(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  return edges;
}

// Watertight and consistently wound: every directed edge occurs once and its reverse once, so
// every undirected edge is shared by exactly two triangles that traverse it opposite ways.
inline bool is_watertight(const TriangleMesh& mesh) {
  const auto edges = directed_edges(mesh);
  for (const auto& [edge, count] : edges) {
    if (count != 1) return false;
    const auto reverse = edges.find({edge.second, edge.first});
    if (reverse == edges.end() || reverse->second != 1) return false;
  }
  return true;
}

// Directed edges with no reverse (the rim of an open wall); -1 when some edge is used twice the
// same way (inconsistent winding).
inline int boundary_edges(const TriangleMesh& mesh) {
  const auto edges = directed_edges(mesh);
  int boundary = 0;
  for (const auto& [edge, count] : edges) {
    if (count != 1) return -1;
    if (!edges.count({edge.second, edge.first})) ++boundary;
  }
  return boundary;
}

template <class Shape>
WallSpec wall_spec(WallKind kind, const Shape& shape) {
  WallSpec wall;
  wall.name = to_string(kind);
  wall.kind = kind;
  wall.shape = shape;
  wall.source.file = "walls.yaml";
  return wall;
}

}  // namespace talus
