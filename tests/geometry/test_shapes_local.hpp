// Hand-built convex shapes (box, regular tetrahedron) as ConvexViews for the wall-clip and
// simple-contact tests, independent of the shape pipeline; also as a ShapeTemplate for the oracle.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "solver/geometry/convex.hpp"
#include "solver/shape/shape.hpp"

namespace talus::test_local {

// Owns the arrays a ConvexView<Real> points to. Built from vertices about the centroid and face
// loops; loops are reoriented counter-clockwise seen from outside.
template <class Real>
struct LocalShape {
  std::vector<Vec3<Real>> vertices;
  std::vector<Vec3<Real>> face_normals;
  std::vector<Real> face_offsets;
  std::vector<int> edges;
  std::vector<int> triangles;
  std::vector<std::vector<int>> loops;
  Real volume = 0;
  Real bounding_radius = 0;

  ConvexView<Real> view() const {
    ConvexView<Real> v;
    v.vertices = vertices.data();
    v.face_normals = face_normals.data();
    v.face_offsets = face_offsets.data();
    v.edges = edges.data();
    v.triangles = triangles.data();
    v.n_vertices = static_cast<int>(vertices.size());
    v.n_faces = static_cast<int>(face_normals.size());
    v.n_edges = static_cast<int>(edges.size() / 2);
    v.n_triangles = static_cast<int>(triangles.size() / 3);
    v.volume = volume;
    v.bounding_radius = bounding_radius;
    return v;
  }

  // The same shape as a ShapeTemplate (body frame = this frame), for the long-double oracle.
  ShapeTemplate to_template() const {
    ShapeTemplate t;
    t.name = "local";
    for (const auto& p : vertices) t.vertices.push_back(Vec3d(p));
    for (std::size_t k = 0; k < triangles.size(); k += 3) {
      t.triangles.push_back({triangles[k], triangles[k + 1], triangles[k + 2]});
    }
    for (std::size_t f = 0; f < loops.size(); ++f) {
      Face face;
      face.normal = Vec3d(face_normals[f]);
      face.offset = double(face_offsets[f]);
      face.loop = loops[f];
      t.faces.push_back(face);
    }
    for (std::size_t k = 0; k < edges.size(); k += 2) t.edges.push_back({edges[k], edges[k + 1]});
    t.volume = double(volume);
    t.bounding_radius = double(bounding_radius);
    return t;
  }
};

// Builds in double, then stores in Real, so float and double shapes hold the same rounded numbers.
template <class Real>
LocalShape<Real> make_from_loops(const std::vector<Vec3d>& points,
                                 std::vector<std::vector<int>> loops) {
  LocalShape<Real> s;
  std::set<std::pair<int, int>> edge_set;
  double six_volume = 0;
  for (auto& loop : loops) {
    Vec3d newell, center;  // Newell's normal is robust for planar loops
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec3d& p = points[loop[k]];
      const Vec3d& q = points[loop[(k + 1) % loop.size()]];
      newell += cross(p, q);
      center += p;
    }
    if (dot(newell, center) < 0) {
      std::reverse(loop.begin(), loop.end());
      newell = -newell;
    }
    const Vec3d normal = newell / norm(newell);
    s.face_normals.push_back(Vec3<Real>(normal));
    s.face_offsets.push_back(Real(dot(normal, points[loop[0]])));
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      s.triangles.insert(s.triangles.end(), {loop[0], loop[k], loop[k + 1]});
      six_volume += triple(points[loop[0]], points[loop[k]], points[loop[k + 1]]);
    }
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int i = loop[k], j = loop[(k + 1) % loop.size()];
      edge_set.insert({std::min(i, j), std::max(i, j)});
    }
  }
  for (const auto& e : edge_set) s.edges.insert(s.edges.end(), {e.first, e.second});
  double radius = 0;
  for (const auto& p : points) {
    s.vertices.push_back(Vec3<Real>(p));
    radius = std::max(radius, norm(p));
  }
  s.loops = loops;
  s.volume = Real(six_volume / 6);
  s.bounding_radius = Real(radius);
  return s;
}

// Box with half-extents (hx, hy, hz) about the origin. Vertex i has signs (bit0: x, bit1: y,
// bit2: z), a set bit meaning +.
template <class Real>
LocalShape<Real> make_box(double hx, double hy, double hz) {
  std::vector<Vec3d> p;
  for (int i = 0; i < 8; ++i) {
    p.push_back({(i & 1) ? hx : -hx, (i & 2) ? hy : -hy, (i & 4) ? hz : -hz});
  }
  return make_from_loops<Real>(
      p, {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}});
}

template <class Real>
LocalShape<Real> make_cube(double side) {
  return make_box<Real>(side / 2, side / 2, side / 2);
}

// Regular tetrahedron with the given edge length, centroid at the origin.
template <class Real>
LocalShape<Real> make_tetrahedron(double edge) {
  const double h = edge / (2 * std::sqrt(2.0));  // (±h, ±h, ±h) with an even number of minuses
  std::vector<Vec3d> p = {{h, h, h}, {h, -h, -h}, {-h, h, -h}, {-h, -h, h}};
  return make_from_loops<Real>(p, {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}});
}

}  // namespace talus::test_local
