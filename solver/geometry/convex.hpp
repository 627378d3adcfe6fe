// Non-owning view of a convex polyhedron template in its body frame, readable on host and device.
// The arrays live in host memory, device global memory or constant memory; the view does not care.
#pragma once

#include "solver/core/quat.hpp"

namespace talus {

// A vertex and the faces it is a corner of (bit f: face f), in one 32-byte record, so that a GPU
// thread reads it in two 16-byte loads: the mask culling's pass over a body's vertices
// (overlap_culling.hpp) reads nothing else.
template <class Real>
struct alignas(32) VertexRecord {
  Vec3<Real> position;
  unsigned long long faces;
};

// A vertex rounded to float, with its faces (bit f: face f; templates of at most 32 faces), in
// 16 bytes: the mask culling's float pass in double on the GPU (filtered_pass in
// overlap_culling.hpp), which decides a plane from these unless some vertex lies within the
// float round-off of it.
struct alignas(16) FilterVertex {
  float x, y, z;
  unsigned faces;
};

template <class Real>
struct ConvexView {
  const Vec3<Real>* vertices = nullptr;      // body frame, centroid at the origin
  const Vec3<Real>* face_normals = nullptr;  // unit, outward; one per merged face (§2.1)
  const Real* face_offsets = nullptr;        // face plane: dot(face_normal, x) = face_offset (> 0)
  const int* edges = nullptr;                // 2 vertex indices per edge
  // The 2 merged faces that meet at each edge, in the order of `edges`: edge_faces[2 e] is the
  // face whose loop runs edges[2 e] -> edges[2 e + 1], edge_faces[2 e + 1] the other. Optional:
  // without them the simple contact's SAT projects on every face normal and edge pair.
  const int* edge_faces = nullptr;
  const int* triangles = nullptr;  // 3 vertex indices per triangle, counter-clockwise from outside
  // Each merged face's vertex loop (counter-clockwise from outside), in compressed rows: face f's
  // vertices are face_loop_vertices[face_loop_offsets[f] .. face_loop_offsets[f + 1]). Optional:
  // without them the overlap skips its face-polygon culling test.
  const int* face_loop_offsets = nullptr;
  const int* face_loop_vertices = nullptr;
  // The vertices again, each with its faces (VertexRecord), for the mask culling. Optional: only
  // for templates of at most 64 vertices and 64 faces with face loops.
  const VertexRecord<Real>* vertex_records = nullptr;
  // The vertices rounded to float, each with its faces (FilterVertex), for the mask culling's
  // float pass (GPU code only). Optional: only for double templates with vertex records and at
  // most 32 faces.
  const FilterVertex* filter_vertices = nullptr;
  int n_vertices = 0;
  int n_faces = 0;
  int n_edges = 0;
  int n_triangles = 0;
  Real volume = 0;
  Real bounding_radius = 0;  // max |vertex| about the centroid (Fig. 4)
};

// Index of the vertex of largest projection on a body-frame direction (the support, Eq. 2).
template <class Real>
TALUS_HD inline int support_vertex(const ConvexView<Real>& shape, const Vec3<Real>& dir_body) {
  int best = 0;
  Real best_dot = dot(shape.vertices[0], dir_body);
  for (int i = 1; i < shape.n_vertices; ++i) {
    const Real s = dot(shape.vertices[i], dir_body);
    if (s > best_dot) {
      best_dot = s;
      best = i;
    }
  }
  return best;
}

// Support point of a posed convex body in world direction dir (Eq. 2), relative to `origin`.
template <class Real>
TALUS_HD inline Vec3<Real> support_point(const ConvexView<Real>& shape, const Mat3<Real>& rot,
                                         const Vec3<Real>& center, const Vec3<Real>& dir) {
  return center + rot * shape.vertices[support_vertex(shape, rot.transpose_times(dir))];
}

}  // namespace talus
