// The overlap of two posed convex polyhedra (paper §2.3) in five steps:
//  1. bounding spheres (Fig. 4) and the face planes in a frame centred on A (small numbers);
//  2. plane culling: a face plane whose half-space holds every vertex of the other body strictly
//     inside cannot bound the intersection (DESIGN.md) and is dropped; a plane with every vertex
//     of the other body outside is a separating plane;
//  3. the reference point x_o: the Chebyshev centre of the kept planes (chebyshev_lp.hpp), which
//     also decides separate / touching;
//  4. the polar transform about x_o (Algorithm II, Eqs. 4-5) and the dual hull (Algs. III-V);
//  5. unpolarisation (Alg. VI, Eqs. 6-8): each dual face is a vertex p = x_o + n/w of the
//     intersection; each dual vertex (a kept plane) is a face of it, whose polygon is the ring of
//     the dual faces around that vertex. The volume is summed as cones from x_o over each face's
//     fan (Eq. 9 with o = x_o: every cone is non-negative because x_o is interior), and the same
//     fans give each face's area, hence the vector area S on A's surface and the centroid.
// Coincident planes of A and B ("twins", e.g. the side faces of two aligned stacked cubes) enter
// the hull once; the face they bound lies on both surfaces and counts half to each, which makes S
// the mean of the two one-sided gradients of V.
#pragma once

#include "solver/geometry/chebyshev_lp.hpp"
#include "solver/geometry/dual_hull.hpp"
#include "solver/geometry/overlap.hpp"

namespace talus {

template <class Real, int MaxPlanes>
struct OverlapWorkspace {
  static constexpr int kMaxPlanes = MaxPlanes;
  Vec3<Real> plane_normal[MaxPlanes];  // unit, outward of the owning body, frame centred on A
  Real plane_offset[MaxPlanes];        // dot(n, x) <= offset inside
  signed char plane_owner[MaxPlanes];  // 0: A, 1: B
  signed char plane_twin[MaxPlanes];   // 1 when a coincident plane of the other body was merged
  DualHullWorkspace<Real, MaxPlanes> hull;
  Vec3<Real> primal_vertex[2 * MaxPlanes];  // per dual face, relative to x_o
  Vec3<Real> ring_sum[MaxPlanes];           // per dual vertex: sum of its ring of primal vertices
  int ring_count[MaxPlanes];
};

// The workspace for `planes` face planes in all (the sum over both templates), rounded up to the
// instantiated capacities. Kernels pick the instantiation once per template pair.
TALUS_HD constexpr int overlap_capacity_for(int planes) {
  return planes <= 32 ? 32 : (planes <= 64 ? 64 : (planes <= 128 ? 128 : 256));
}

namespace overlap_detail {

// Range of signed heights of the vertices of `other` above the plane (n, h) of the frame centred
// on A; `other` sits at `other_center` with rotation `other_rot`.
template <class Real>
TALUS_HD inline void height_range(const ConvexView<Real>& other, const Mat3<Real>& other_rot,
                                  const Vec3<Real>& other_center, const Vec3<Real>& n, Real h,
                                  Real& lowest, Real& highest) {
  const Vec3<Real> n_body = other_rot.transpose_times(n);
  const Real h_body = h - dot(n, other_center);
  lowest = highest = dot(n_body, other.vertices[0]);
  for (int i = 1; i < other.n_vertices; ++i) {
    const Real s = dot(n_body, other.vertices[i]);
    lowest = min_of(lowest, s);
    highest = max_of(highest, s);
  }
  lowest -= h_body;
  highest -= h_body;
}

}  // namespace overlap_detail

template <class Real, class Workspace>
TALUS_HD inline OverlapResult<Real> overlap_polyhedra(const ConvexView<Real>& a,
                                                      const Pose<Real>& pose_a,
                                                      const ConvexView<Real>& b,
                                                      const Pose<Real>& pose_b, Workspace& ws,
                                                      OverlapOptions options = OverlapOptions()) {
  OverlapResult<Real> result;
  const Real eps = Eps<Real>::value;
  // Step 1. Frame centred on A: positions far from the world origin lose no digits.
  const Vec3<Real> center[2] = {Vec3<Real>(), pose_b.position - pose_a.position};
  const Real distance = norm(center[1]);
  if (!(distance <= a.bounding_radius + b.bounding_radius)) {
    if (!(distance == distance)) result.status = OverlapStatus::degenerate;  // NaN input
    return result;
  }
  // Absolute round-off of a plane offset or a vertex height in this frame.
  const Real round_off = Real(64) * eps * (max_of(a.bounding_radius, b.bounding_radius) + distance);
  const Mat3<Real> rot[2] = {rotation_matrix(pose_a.orientation),
                             rotation_matrix(pose_b.orientation)};
  const ConvexView<Real>* body[2] = {&a, &b};

  // Step 2. Planes of both bodies, culled against the other body's vertices.
  int m = 0;
  for (int owner = 0; owner < 2; ++owner) {
    const ConvexView<Real>& self = *body[owner];
    const int other = 1 - owner;
    for (int f = 0; f < self.n_faces; ++f) {
      const Vec3<Real> n = rot[owner] * self.face_normals[f];
      const Real h = self.face_offsets[f] + dot(n, center[owner]);
      if (options.cull_planes) {
        Real lowest, highest;
        overlap_detail::height_range(*body[other], rot[other], center[other], n, h, lowest,
                                     highest);
        if (lowest > -round_off) {  // the other body lies beyond this plane: a separating plane
          result.status = lowest > round_off ? OverlapStatus::separate : OverlapStatus::touching;
          return result;
        }
        if (highest < -round_off) continue;  // strictly inside: this plane bounds nothing
      }
      if (m >= Workspace::kMaxPlanes) {
        result.workspace_overrun = true;
        result.status = OverlapStatus::degenerate;
        return result;
      }
      ws.plane_normal[m] = n;
      ws.plane_offset[m] = h;
      ws.plane_owner[m] = static_cast<signed char>(owner);
      ws.plane_twin[m] = 0;
      ++m;
    }
  }
  // Twins: a plane of B coincident with a plane of A (same normal and offset within round-off)
  // is merged into A's (see the header comment).
  {
    int kept = 0;
    for (int i = 0; i < m; ++i) {
      bool merged = false;
      if (ws.plane_owner[i] == 1) {
        for (int j = 0; j < kept && !merged; ++j) {
          if (ws.plane_owner[j] != 0) continue;
          if (dot(ws.plane_normal[i], ws.plane_normal[j]) >= Real(1) - Real(64) * eps &&
              abs_of(ws.plane_offset[i] - ws.plane_offset[j]) <= round_off) {
            ws.plane_twin[j] = 1;
            merged = true;
          }
        }
      }
      if (merged) continue;
      ws.plane_normal[kept] = ws.plane_normal[i];
      ws.plane_offset[kept] = ws.plane_offset[i];
      ws.plane_owner[kept] = ws.plane_owner[i];
      ws.plane_twin[kept] = ws.plane_twin[i];
      ++kept;
    }
    m = kept;
  }

  // Step 3. Reference point: the Chebyshev centre of the kept planes.
  const Real radius_sum = a.bounding_radius + b.bounding_radius;
  const Vec3<Real> start = center[1] * (a.bounding_radius / radius_sum);
  const ChebyshevResult<Real> lp =
      chebyshev_center(ws.plane_normal, ws.plane_offset, m, start,
                       min_of(a.bounding_radius, b.bounding_radius), 8 * m + 32);
  result.depth_hint = lp.depth;
  if (lp.depth <= round_off) {
    result.status = lp.depth >= -round_off ? OverlapStatus::touching : OverlapStatus::separate;
    return result;
  }
  const Vec3<Real> x_o = lp.center;
  if (options.cull_planes) {
    // The culled planes are redundant only when the intersection has an interior; when it has
    // none the kept planes may still enclose a region, which must not pass as overlap.
    for (int owner = 0; owner < 2; ++owner)
      for (int f = 0; f < body[owner]->n_faces; ++f) {
        const Vec3<Real> n = rot[owner] * body[owner]->face_normals[f];
        const Real slack = body[owner]->face_offsets[f] + dot(n, center[owner] - x_o);
        if (slack < lp.depth - round_off) {
          result.status = slack >= -round_off ? OverlapStatus::touching : OverlapStatus::separate;
          return result;
        }
      }
  }

  // Step 4. Polar transform about x_o (Eqs. 4-5): y = n / (h - n.x_o), |y| = 1 / distance.
  auto& hull = ws.hull;
  hull.n_points = m;
  for (int i = 0; i < m; ++i) {
    const Real slack = ws.plane_offset[i] - dot(ws.plane_normal[i], x_o);
    hull.point[i] = ws.plane_normal[i] / slack;
    hull.point_norm[i] = Real(1) / slack;
  }
  if (!build_dual_hull<Real>(hull)) {
    result.workspace_overrun = hull.overrun;
    result.status = OverlapStatus::degenerate;
    return result;
  }

  // Step 5. Unpolarise (Eqs. 6-8): dual face (n, w) -> primal vertex x_o + n / w.
  for (int i = 0; i < m; ++i) {
    ws.ring_sum[i] = Vec3<Real>();
    ws.ring_count[i] = 0;
  }
  for (int f = 0; f < hull.n_slots; ++f) {
    if (hull.face_stamp[f] < 0) continue;
    const Real w = hull.face_offset[f];
    if (!(w > Real(0))) {  // the origin left the dual hull: only possible through round-off
      result.status = OverlapStatus::degenerate;
      return result;
    }
    ws.primal_vertex[f] = hull.face_normal[f] / w;
    for (int k = 0; k < 3; ++k) {
      ws.ring_sum[hull.face_vertex[f][k]] += ws.primal_vertex[f];
      ++ws.ring_count[hull.face_vertex[f][k]];
    }
  }
  // Cones from x_o over the fan of each face (Eq. 9): the primal edge between the vertices of
  // dual faces f and g lies on the faces of both dual vertices of their shared edge; the directed
  // edge (v0, v1) of f contributes its fan triangle to face v0 only, the twin edge of g to v1.
  Real volume = 0;
  Vec3<Real> moment, vector_area;
  for (int f = 0; f < hull.n_slots; ++f) {
    if (hull.face_stamp[f] < 0) continue;
    const Vec3<Real>& p_f = ws.primal_vertex[f];
    for (int e = 0; e < 3; ++e) {
      const int v = hull.face_vertex[f][e];
      const Vec3<Real>& p_g = ws.primal_vertex[hull.face_neighbor[f][e]];
      const Vec3<Real> c = ws.ring_sum[v] / Real(ws.ring_count[v]);
      const Real area = norm(cross(p_f - c, p_g - c)) / Real(2);
      const Real cone = area / (Real(3) * hull.point_norm[v]);  // area * distance / 3
      volume += cone;
      moment += (c + p_f + p_g) * (cone / Real(4));
      const Real share = ws.plane_twin[v] ? Real(0.5) : (ws.plane_owner[v] == 0 ? Real(1) : Real(0));
      vector_area += ws.plane_normal[v] * (area * share);
    }
  }
  int on_hull = 0;
  for (int i = 0; i < m; ++i) on_hull += ws.ring_count[i] > 0;
  result.hull_points = on_hull;
  result.volume = volume;
  result.vector_area = vector_area;
  result.centroid = pose_a.position + x_o + (volume > Real(0) ? moment / volume : Vec3<Real>());
  result.status = volume > Real(0) ? OverlapStatus::overlapping : OverlapStatus::touching;
  return result;
}

}  // namespace talus
