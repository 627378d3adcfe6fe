// Flat host arrays of one template in the real type the solver runs in, and the ConvexView over
// them (the layout that is copied to the device).
#pragma once

#include <map>
#include <type_traits>
#include <utility>
#include <vector>

#include "solver/geometry/convex.hpp"
#include "solver/shape/shape.hpp"

namespace talus {

template <class Real>
struct ShapeArrays {
  std::vector<Vec3<Real>> vertices, face_normals;
  std::vector<Real> face_offsets;
  std::vector<int> edges, triangles;                       // 2 and 3 vertex indices each, flattened
  std::vector<int> face_loop_offsets, face_loop_vertices;  // compressed rows, see ConvexView
  std::vector<int> edge_faces;  // 2 faces per edge, see ConvexView; empty if the loops disagree
  std::vector<VertexRecord<Real>> vertex_records;  // see ConvexView; empty above 64 of either
  std::vector<FilterVertex> filter_vertices;       // see ConvexView; double, at most 32 faces
  Real bounding_radius = 0, volume = 0;

  explicit ShapeArrays(const ShapeTemplate& shape)
      : bounding_radius(Real(shape.bounding_radius)), volume(Real(shape.volume)) {
    for (const Vec3d& v : shape.vertices) {
      vertices.push_back(Vec3<Real>(v));
      // Rounded vertices must stay inside the bounding sphere the broad phase uses.
      const Real r = norm(vertices.back());
      if (r > bounding_radius) bounding_radius = r;
    }
    for (const Face& face : shape.faces) {
      const Vec3<Real> normal(face.normal);
      // The offset is taken again in Real arithmetic from the rounded vertices, so that each
      // face's own vertices satisfy dot(normal, x) <= offset in that precision too.
      Real offset = Real(face.offset);
      for (int v : face.loop) {
        const Real d = dot(normal, vertices[v]);
        if (d > offset) offset = d;
      }
      face_normals.push_back(normal);
      face_offsets.push_back(offset);
    }
    face_loop_offsets.push_back(0);
    for (const Face& face : shape.faces) {
      face_loop_vertices.insert(face_loop_vertices.end(), face.loop.begin(), face.loop.end());
      face_loop_offsets.push_back(int(face_loop_vertices.size()));
    }
    if (vertices.size() <= 64 && shape.faces.size() <= 64) {
      for (const Vec3<Real>& v : vertices) vertex_records.push_back({v, 0});
      for (std::size_t f = 0; f < shape.faces.size(); ++f)
        for (int v : shape.faces[f].loop) vertex_records[v].faces |= 1ull << f;
      if (std::is_same_v<Real, double> && shape.faces.size() <= 32) {
        for (const VertexRecord<Real>& r : vertex_records)
          filter_vertices.push_back(
              {float(r.position.x), float(r.position.y), float(r.position.z), unsigned(r.faces)});
      }
    }
    for (const auto& e : shape.edges) edges.insert(edges.end(), {e[0], e[1]});
    fill_edge_faces(shape);
    for (const auto& t : shape.triangles) triangles.insert(triangles.end(), {t[0], t[1], t[2]});
  }

  // Each edge's two faces from the face loops: the face running edges[2 e] -> edges[2 e + 1]
  // first. Left empty (no pruning, see ConvexView) unless every edge has exactly one face on
  // each side.
  void fill_edge_faces(const ShapeTemplate& shape) {
    std::map<std::pair<int, int>, int> edge_index;
    for (std::size_t e = 0; e < shape.edges.size(); ++e)
      edge_index[{shape.edges[e][0], shape.edges[e][1]}] = int(e);
    std::vector<int> sides(2 * shape.edges.size(), -1);
    for (std::size_t f = 0; f < shape.faces.size(); ++f) {
      const std::vector<int>& loop = shape.faces[f].loop;
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const int from = loop[k], to = loop[(k + 1) % loop.size()];
        auto it = edge_index.find({from, to});
        int side = 0;
        if (it == edge_index.end()) {
          it = edge_index.find({to, from});
          side = 1;
        }
        if (it == edge_index.end()) return;  // a loop side that is no edge
        int& slot = sides[2 * it->second + side];
        if (slot >= 0) return;  // two faces on one side
        slot = int(f);
      }
    }
    for (int face : sides)
      if (face < 0) return;
    edge_faces = std::move(sides);
  }

  // Valid while this object lives and is not modified.
  ConvexView<Real> view() const {
    ConvexView<Real> view;
    view.vertices = vertices.data();
    view.face_normals = face_normals.data();
    view.face_offsets = face_offsets.data();
    view.edges = edges.data();
    view.edge_faces = edge_faces.empty() ? nullptr : edge_faces.data();
    view.triangles = triangles.data();
    view.face_loop_offsets = face_loop_offsets.data();
    view.face_loop_vertices = face_loop_vertices.data();
    view.vertex_records = vertex_records.empty() ? nullptr : vertex_records.data();
    view.filter_vertices = filter_vertices.empty() ? nullptr : filter_vertices.data();
    view.n_vertices = int(vertices.size());
    view.n_faces = int(face_normals.size());
    view.n_edges = int(edges.size() / 2);
    view.n_triangles = int(triangles.size() / 3);
    view.volume = volume;
    view.bounding_radius = bounding_radius;
    return view;
  }
};

}  // namespace talus
