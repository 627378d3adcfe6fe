// Incremental Quickhull of the dual points (paper §2.3, Algorithms III-V) in a fixed workspace.
// The origin of dual space is strictly inside the hull (the polar transform was taken about an
// interior point of the intersection), which gives every face a positive offset and lets each
// dual face be unpolarised into one vertex of the intersection polytope (Algorithm VI).
//
// Data: triangles with vertex indices and the neighbour across each edge; a free list recycles
// the slots of deleted faces so that at most 2V - 4 faces are ever alive (V = hull vertices).
// Conflicts: each point outside the hull remembers one face it is outside of; after an expansion
// only the orphaned points are reassigned, and only against the new faces.
#pragma once

#include "solver/core/math.hpp"
#include "solver/core/vec3.hpp"

#include <type_traits>

namespace talus {

// The smallest signed integer that holds every face index of a workspace with `faces` slots and
// the sentinels -1 and -2: indices take a byte up to 128 slots. The workspace lives in each GPU
// thread's local memory, whose traffic bounds the batch kernel (benchmarks/README.md); narrow
// indices keep the words a pair touches few.
template <int Faces>
using HullIndexFor = std::conditional_t<(Faces <= 128), signed char, short>;

template <class Real, int MaxPoints>
struct DualHullWorkspace {
  static_assert(MaxPoints >= 4, "a hull needs four points");
  static constexpr int kMaxPoints = MaxPoints;
  // A closed triangulated hull of V vertices has 2V - 4 faces (Euler), and an expansion frees
  // its visible faces before it allocates the new ones, so no more slots are ever in use. (The
  // expansion keeps V - E + F from falling below 2 even when round-off gives a horizon of
  // several loops; the overrun check stays as the guard.)
  static constexpr int kMaxFaces = 2 * MaxPoints - 4;
  static_assert(kMaxFaces <= 32767, "face indices are shorts");
  using Index = HullIndexFor<kMaxFaces>;  // a point or face index

  // The points are the polar duals of planes, y = n / s (Eq. 5): kept as the plane's unit normal
  // and |y| = 1 / s, since the overlap needs the normals too (one array instead of two); point()
  // gives y. The caller fills plane_normal, point_norm and n_points.
  Vec3<Real> plane_normal[MaxPoints];
  Real point_norm[MaxPoints];
  Real point_dist[MaxPoints];  // the distance above point_face
  // Unit, outward. Once the hull is built, overlap_polyhedra overwrites it with the face's
  // primal vertex (unpolarisation), which saves an array of the same size.
  Vec3<Real> face_normal[kMaxFaces];
  Real face_offset[kMaxFaces];  // dot(normal, y) = offset on the face, > 0
  int n_points = 0;
  int n_free = 0;
  int n_slots = 0;         // slots ever used
  int skipped_points = 0;  // outside points dropped because the visible region was not a disk

  Index point_face[MaxPoints];        // face the point is outside of; -1: inside or on the hull
  Index face_vertex[kMaxFaces][3];    // counter-clockwise seen from outside
  Index face_neighbor[kMaxFaces][3];  // across edge (vertex[e], vertex[e + 1])
  // The face's vertex of largest |y|, whose norm sets the face's round-off tolerance (a byte
  // where the norm itself took a Real).
  Index face_far[kMaxFaces];
  // < 0: free slot; else the last expansion that visited it (at most kMaxPoints, an Index).
  Index face_stamp[kMaxFaces];
  Index free_slots[kMaxFaces];

  // Scratch for one expansion. `stack` lists the visible faces, then, once they are freed, the
  // new ones.
  Index stack[kMaxFaces];
  Index horizon_face[kMaxFaces];   // the face kept beyond the horizon edge
  Index horizon_edge[kMaxFaces];   // the edge index in that face
  Index new_face_from[MaxPoints];  // horizon edge starting at a vertex -> new face
  Index orphans[MaxPoints];

  bool overrun = false;

  // The dual point p, rounded as the product n * |y| is: the bits of a stored point.
  TALUS_HD Vec3<Real> point(int p) const {
    const Vec3<Real>& n = plane_normal[p];
    const Real s = point_norm[p];
    return Vec3<Real>(product_rn(n.x, s), product_rn(n.y, s), product_rn(n.z, s));
  }
};

namespace dual_hull_detail {

// Distance tolerance of a point against a face: the plane test subtracts numbers of size
// |y| and the face's largest |vertex|, each carrying relative round-off of a few eps.
template <class Real, class W>
TALUS_HD inline Real tolerance(const W& ws, int face, Real point_norm) {
  return Real(32) * Eps<Real>::value * (point_norm + ws.point_norm[ws.face_far[face]]);
}

// The height of point y above the face's plane.
template <class Real, class W>
TALUS_HD inline Real distance(const W& ws, int face, const Vec3<Real>& y) {
  return dot(ws.face_normal[face], y) - ws.face_offset[face];
}

template <class Real, class W>
TALUS_HD inline int allocate_face(W& ws) {
  if (ws.n_free > 0) return ws.free_slots[--ws.n_free];
  if (ws.n_slots >= W::kMaxFaces) {
    ws.overrun = true;
    return -1;
  }
  return ws.n_slots++;
}

// Sets the face's vertices and plane. The winding (a, b, c) is trusted to be outward.
template <class Real, class W>
TALUS_HD inline void set_face(W& ws, int f, int a, int b, int c) {
  using Index = typename W::Index;
  ws.face_vertex[f][0] = Index(a);
  ws.face_vertex[f][1] = Index(b);
  ws.face_vertex[f][2] = Index(c);
  const Vec3<Real> pa = ws.point(a);
  const Vec3<Real> pb = ws.point(b);
  const Vec3<Real> pc = ws.point(c);
  Vec3<Real> n = cross(pb - pa, pc - pa);
  const Real len = norm(n);
  n = len > Real(0) ? n * (Real(1) / len) : Vec3<Real>(0, 0, 0);
  ws.face_normal[f] = n;
  // Eq. 7 takes one vertex's offset; the mean of the three halves the round-off.
  ws.face_offset[f] = (dot(n, pa) + dot(n, pb) + dot(n, pc)) * (Real(1) / Real(3));
  // The vertex whose norm max_of(|a|, max_of(|b|, |c|)) returns.
  const int far_bc = ws.point_norm[b] < ws.point_norm[c] ? c : b;
  ws.face_far[f] = Index(ws.point_norm[a] < ws.point_norm[far_bc] ? far_bc : a);
  ws.face_stamp[f] = 0;
}

// Assigns point p to the new face (among faces[0..count)) it is farthest outside of, if any.
template <class Real, class W>
TALUS_HD inline void assign_point(W& ws, int p, const typename W::Index* faces, int count) {
  ws.point_face[p] = -1;
  const Vec3<Real> y = ws.point(p);
  const Real y_norm = ws.point_norm[p];
  Real best = 0;
  for (int i = 0; i < count; ++i) {
    const int f = faces[i];
    const Real d = distance<Real>(ws, f, y);
    if (d > tolerance<Real>(ws, f, y_norm) && d > best) {
      best = d;
      ws.point_face[p] = typename W::Index(f);
    }
  }
  ws.point_dist[p] = best;
}

// Initial tetrahedron (Algorithm III, initSimplex) from extreme points. Returns false when the
// points are numerically flat (cannot happen for a bounded intersection with interior).
template <class Real, class W>
TALUS_HD inline bool init_simplex(W& ws) {
  const int n = ws.n_points;
  int extreme[6] = {0, 0, 0, 0, 0, 0};
  Vec3<Real> low = ws.point(0), high = low;  // the extremes' coordinates
  for (int p = 1; p < n; ++p) {
    const Vec3<Real> y = ws.point(p);
    for (int axis = 0; axis < 3; ++axis) {
      if (y[axis] < low[axis]) {
        extreme[2 * axis] = p;
        low[axis] = y[axis];
      }
      if (y[axis] > high[axis]) {
        extreme[2 * axis + 1] = p;
        high[axis] = y[axis];
      }
    }
  }
  Vec3<Real> extreme_point[6];
  for (int a = 0; a < 6; ++a) extreme_point[a] = ws.point(extreme[a]);
  int i0 = 0, i1 = 0;
  Real best = -1;
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b) {
      const Real d = norm2(extreme_point[a] - extreme_point[b]);
      if (d > best) {
        best = d;
        i0 = extreme[a];
        i1 = extreme[b];
      }
    }
  Real scale = 0;
  for (int p = 0; p < n; ++p) scale = max_of(scale, ws.point_norm[p]);
  const Real tiny = Real(64) * Eps<Real>::value * scale;
  const Vec3<Real> p0 = ws.point(i0);
  const Vec3<Real> axis = ws.point(i1) - p0;
  if (norm(axis) <= tiny) return false;
  int i2 = -1;
  best = 0;
  for (int p = 0; p < n; ++p) {
    if (p == i0 || p == i1) continue;
    const Real d = norm(cross(axis, ws.point(p) - p0));
    if (d > best) {
      best = d;
      i2 = p;
    }
  }
  if (i2 < 0 || best <= tiny * norm(axis)) return false;
  const Vec3<Real> normal = cross(axis, ws.point(i2) - p0);
  int i3 = -1;
  best = 0;
  Real side = 0;
  for (int p = 0; p < n; ++p) {
    // i0, i1 and i2 span the plane: their heights are round-off, and on a nearly flat set one of
    // them could win and enter the simplex twice, whose faces then find no neighbours.
    if (p == i0 || p == i1 || p == i2) continue;
    const Real d = dot(normal, ws.point(p) - p0);
    if (abs_of(d) > best) {
      best = abs_of(d);
      i3 = p;
      side = d;
    }
  }
  if (i3 < 0 || best <= tiny * norm(normal)) return false;
  // Orient so that the fourth vertex lies below the first face.
  if (side > 0) swap_of(i1, i2);
  const int v[4] = {i0, i1, i2, i3};
  // Faces (0,1,2), (0,3,1), (1,3,2), (2,3,0) are outward for the orientation above.
  const int tri[4][3] = {
      {v[0], v[1], v[2]}, {v[0], v[3], v[1]}, {v[1], v[3], v[2]}, {v[2], v[3], v[0]}};
  for (int f = 0; f < 4; ++f) {
    const int slot = allocate_face<Real>(ws);
    if (slot < 0) return false;
    set_face<Real>(ws, slot, tri[f][0], tri[f][1], tri[f][2]);
  }
  // Neighbours: the face sharing each directed edge reversed.
  for (int f = 0; f < 4; ++f)
    for (int e = 0; e < 3; ++e) {
      const int a = ws.face_vertex[f][e], b = ws.face_vertex[f][(e + 1) % 3];
      for (int g = 0; g < 4; ++g)
        for (int k = 0; k < 3; ++k)
          if (ws.face_vertex[g][k] == b && ws.face_vertex[g][(k + 1) % 3] == a)
            ws.face_neighbor[f][e] = typename W::Index(g);
    }
  const typename W::Index faces[4] = {0, 1, 2, 3};
  for (int p = 0; p < n; ++p) {
    if (p == i0 || p == i1 || p == i2 || p == i3) {
      ws.point_face[p] = -1;
      continue;
    }
    assign_point<Real>(ws, p, faces, 4);
  }
  return true;
}

// One expansion (Algorithm V) from apex p: the visible region grown from p's face by
// neighbour links (so it is connected), its horizon, new faces fanned from the apex.
template <class Real, class W>
TALUS_HD inline void expand_once(W& ws, int p, int stamp) {
  const int start = ws.point_face[p];
  ws.point_face[p] = -1;
  const Vec3<Real> apex = ws.point(p);
  const Real apex_norm = ws.point_norm[p];
  int n_stack = 0, n_horizon = 0;
  ws.stack[n_stack++] = start;
  ws.face_stamp[start] = stamp;
  // Depth-first walk over visible faces; `stack` doubles as the list of visible faces.
  int cursor = 0;
  while (cursor < n_stack) {
    const int f = ws.stack[cursor++];
    for (int e = 0; e < 3; ++e) {
      const int g = ws.face_neighbor[f][e];
      if (ws.face_stamp[g] == stamp) continue;
      if (distance<Real>(ws, g, apex) > tolerance<Real>(ws, g, apex_norm)) {
        ws.face_stamp[g] = stamp;
        ws.stack[n_stack++] = g;
      } else {
        int back = 0;
        while (back < 3 && ws.face_neighbor[g][back] != f) ++back;
        ws.horizon_face[n_horizon] = g;
        ws.horizon_edge[n_horizon] = back;
        ++n_horizon;
      }
    }
  }
  // The horizon must be one simple loop: every vertex starts at most one horizon edge. A
  // visible region with a hole (possible only within round-off of coplanarity) is refused and
  // the point dropped; it lies within the tolerance of the hull.
  for (int h = 0; h < n_horizon; ++h)
    ws.new_face_from[ws.face_vertex[ws.horizon_face[h]][(ws.horizon_edge[h] + 1) % 3]] = -1;
  for (int h = 0; h < n_horizon; ++h) {
    const int v = ws.face_vertex[ws.horizon_face[h]][(ws.horizon_edge[h] + 1) % 3];
    if (ws.new_face_from[v] != -1) {
      ++ws.skipped_points;
      return;  // visible faces keep their stamp, which is harmless: stamps only grow
    }
    ws.new_face_from[v] = -2;
  }
  // Free the visible faces and collect the orphaned points (those assigned to them) before the
  // slots are reused by the new faces.
  for (int i = 0; i < n_stack; ++i) {
    ws.face_stamp[ws.stack[i]] = -1;
    ws.free_slots[ws.n_free++] = ws.stack[i];
  }
  int n_orphans = 0;
  for (int q = 0; q < ws.n_points; ++q) {
    const int f = ws.point_face[q];
    if (f >= 0 && ws.face_stamp[f] < 0) ws.orphans[n_orphans++] = q;
  }
  // New faces: the horizon edge (a, b) as wound in the visible face, then the apex. They are
  // listed in `stack`, whose visible faces are freed.
  auto* new_faces = ws.stack;
  for (int h = 0; h < n_horizon; ++h) {
    const int g = ws.horizon_face[h], k = ws.horizon_edge[h];
    // In the kept face g the shared edge runs (vertex[k], vertex[k+1]); reversed for us.
    const int a = ws.face_vertex[g][(k + 1) % 3], b = ws.face_vertex[g][k];
    const int f = allocate_face<Real>(ws);
    if (f < 0) return;
    set_face<Real>(ws, f, a, b, p);
    ws.face_stamp[f] = stamp;
    ws.face_neighbor[f][0] = g;
    ws.face_neighbor[g][k] = f;
    ws.new_face_from[a] = f;
    new_faces[h] = f;
  }
  // Link the fan: face (a, b, p) meets face (b, c, p) across (b, p).
  for (int h = 0; h < n_horizon; ++h) {
    const int f = new_faces[h];
    const int next = ws.new_face_from[ws.face_vertex[f][1]];
    ws.face_neighbor[f][1] = next;
    ws.face_neighbor[next][2] = f;
  }
  for (int i = 0; i < n_orphans; ++i) assign_point<Real>(ws, ws.orphans[i], new_faces, n_horizon);
}

}  // namespace dual_hull_detail

// Builds the hull of ws.point[0..n_points) (point_norm filled by the caller). Returns false on a
// flat point set or a workspace overrun (ws.overrun).
template <class Real, class W>
TALUS_HD inline bool build_dual_hull(W& ws) {
  using namespace dual_hull_detail;
  ws.n_free = 0;
  ws.n_slots = 0;
  ws.overrun = false;
  ws.skipped_points = 0;
  if (ws.n_points < 4) return false;
  if (!init_simplex<Real>(ws)) return false;
  // Algorithm III: expand from the farthest outside point until none is left. Each expansion
  // retires one point, so at most n_points expansions happen.
  for (int stamp = 1; stamp <= ws.n_points; ++stamp) {
    int apex = -1;
    Real best = 0;
    for (int p = 0; p < ws.n_points; ++p)
      if (ws.point_face[p] >= 0 && ws.point_dist[p] > best) {
        best = ws.point_dist[p];
        apex = p;
      }
    if (apex < 0) return true;
    expand_once<Real>(ws, apex, stamp);
    if (ws.overrun) return false;
  }
  return true;
}

}  // namespace talus
