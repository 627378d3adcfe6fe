// Device copy of one template's arrays and the ConvexView that points into them (CUDA builds).
#pragma once

#include <cstddef>

#include "solver/core/device_buffer.hpp"
#include "solver/geometry/convex.hpp"

namespace talus {

template <class Real>
struct DeviceShape {
  DeviceBuffer<Vec3<Real>> vertices, face_normals;
  DeviceBuffer<Real> face_offsets;
  DeviceBuffer<int> edges, edge_faces, triangles, loop_offsets, loop_vertices;
  DeviceBuffer<VertexRecord<Real>> vertex_records;
  DeviceBuffer<FilterVertex> filter_vertices;
  ConvexView<Real> view;

  explicit DeviceShape(const ConvexView<Real>& host) {
    vertices.upload(host.vertices, host.n_vertices);
    face_normals.upload(host.face_normals, host.n_faces);
    face_offsets.upload(host.face_offsets, host.n_faces);
    if (host.edges) edges.upload(host.edges, 2 * host.n_edges);
    if (host.edge_faces) edge_faces.upload(host.edge_faces, 2 * host.n_edges);
    if (host.triangles) triangles.upload(host.triangles, 3 * host.n_triangles);
    if (host.face_loop_offsets) {
      loop_offsets.upload(host.face_loop_offsets, host.n_faces + 1);
      loop_vertices.upload(host.face_loop_vertices, host.face_loop_offsets[host.n_faces]);
    }
    if (host.vertex_records) vertex_records.upload(host.vertex_records, host.n_vertices);
    if (host.filter_vertices) filter_vertices.upload(host.filter_vertices, host.n_vertices);
    view = host;
    view.vertices = vertices.data();
    view.face_normals = face_normals.data();
    view.face_offsets = face_offsets.data();
    view.edges = host.edges ? edges.data() : nullptr;
    view.edge_faces = host.edge_faces ? edge_faces.data() : nullptr;
    view.triangles = host.triangles ? triangles.data() : nullptr;
    view.face_loop_offsets = host.face_loop_offsets ? loop_offsets.data() : nullptr;
    view.face_loop_vertices = host.face_loop_offsets ? loop_vertices.data() : nullptr;
    view.vertex_records = host.vertex_records ? vertex_records.data() : nullptr;
    view.filter_vertices = host.filter_vertices ? filter_vertices.data() : nullptr;
  }

  std::size_t bytes() const {
    return (vertices.size() + face_normals.size()) * sizeof(Vec3<Real>) +
           face_offsets.size() * sizeof(Real) +
           (edges.size() + edge_faces.size() + triangles.size() + loop_offsets.size() +
            loop_vertices.size()) *
               sizeof(int) +
           vertex_records.size() * sizeof(VertexRecord<Real>) +
           filter_vertices.size() * sizeof(FilterVertex);
  }
};

}  // namespace talus
