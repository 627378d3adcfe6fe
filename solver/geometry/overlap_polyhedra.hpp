// The overlap of two posed convex polyhedra (paper §2.3) in five steps:
//  1. bounding spheres (Fig. 4) and the face planes in a frame centred on A (small numbers);
//  2. plane culling: a face plane whose half-space holds every vertex of the other body strictly
//     inside cannot bound the intersection and is dropped, and so is one whose face polygon lies
//     outside the other body (face_outside); a plane with every vertex of the other body outside
//     is a separating plane (docs/geometry.md gives the argument); steps 1 and 2 are in
//     overlap_culling.hpp;
//  (2b. with at most 8 kept planes, the vertex enumeration of vertex_enumeration.hpp answers
//      instead of steps 3-5 whenever it can certify its result;)
//  3. the reference point x_o: the Chebyshev centre of the kept planes (chebyshev_lp.hpp), which
//     also decides separate / touching;
//  4. the polar transform about x_o (Algorithm II, Eqs. 4-5) and the dual hull (Algs. III-V);
//  5. unpolarisation (Alg. VI, Eqs. 6-8): each dual face is a vertex p = x_o + n/w of the
//     intersection; each dual vertex (a kept plane) is a face of it, whose polygon is the ring of
//     the dual faces around that vertex. The volume is summed as cones from x_o over each face's
//     fan from one of its corners (Eq. 9 with o = x_o, interior, so every cone is positive up to
//     round-off), and the same fans give each face's area, hence the vector area S on A's
//     surface and the centroid.
// Coincident planes of A and B ("twins", e.g. the side faces of two aligned stacked cubes, or
// planes whose dual points are closer than round-off can separate) enter the hull once; the face
// they bound lies on both surfaces and counts half to each, which makes S the mean of the two
// one-sided gradients of V.
#pragma once

#include "solver/geometry/analytic_centre.hpp"
#include "solver/geometry/chebyshev_lp.hpp"
#include "solver/geometry/dual_hull.hpp"
#include "solver/geometry/overlap.hpp"
#include "solver/geometry/overlap_culling.hpp"
#include "solver/geometry/vertex_enumeration.hpp"

namespace talus {

// One pair's scratch. On the GPU it lives in the thread's local memory, whose latency bounds the
// polytope kernels (benchmarks/README.md), so nothing in it is kept twice: the plane normals are
// the hull's (its dual points are n / s, kept as n and 1 / s), a face's round-off scale is an
// index, and scratch that is dead in a later step holds that step's arrays.
template <class Real, int MaxPlanes>
struct OverlapWorkspace {
  static constexpr int kMaxPlanes = MaxPlanes;
  // Planes in the frame centred on A. Their unit normals, outward of the owning body, are
  // hull.plane_normal. dot(n, x) <= offset inside; from step 4 on, the plane's slack at x_o
  // (offset - dot(n, x_o)).
  Real plane_offset[MaxPlanes];
  // Also holds each dual face's primal vertex (relative to x_o) in place of its normal once the
  // hull is built (step 5), and in point_face, whose conflicts are then all resolved, each dual
  // vertex's fan apex: a dual face around it (-1: not on the hull).
  DualHullWorkspace<Real, MaxPlanes> hull;
  signed char plane_owner[MaxPlanes];  // 0: A, 1: B
  signed char plane_twin[MaxPlanes];   // 1 when a coincident plane of the other body was merged
};

// The workspace for `planes` face planes in all (the sum over both templates), rounded up to the
// instantiated capacities. Kernels pick the instantiation once per template pair.
TALUS_HD constexpr int overlap_capacity_for(int planes) {
  return planes <= 32 ? 32 : (planes <= 64 ? 64 : (planes <= 128 ? 128 : 256));
}

// Relative distance of two dual points below which they are one plane (twins): sqrt(eps).
template <class Real>
struct TwinTolerance {
  static constexpr Real value = SqrtEps<Real>::value;
};

namespace overlap_detail {

// A slab below the dual transform's resolution. When the dual hull cannot be built even from the
// analytic centre in rounded coordinates (step 4's retry) and the overlap's inradius (the
// Chebyshev LP's depth) is at most kThinSlab * sqrt(eps) of the smaller bounding radius, the
// overlap is a face resting on a face within round-off of the planes themselves, and it is
// reported as touching (no volume, no force) rather than degenerate, which stops a run. Face-to-
// face pairs of every built-in shape, sampled over depths from 1e-15 to 1e-6 of the radius and
// tilts from 0 to 1e-2 (tests/geometry/test_overlap_thin_slabs.cpp), failed the hull in 1 to 5 %
// of the samples, all with an inradius below 6.8e-9 of the radius (under sqrt(eps) = 1.5e-8 in
// double): 8 sqrt(eps) leaves a factor of 17 above the worst seen. What is left out is at most
// the slab's volume, its face (within pi R^2) times its thickness (twice the inradius): in double
// at most 16 pi sqrt(eps) R^3 = 7.5e-7 R^3, under a millionth of the bounding sphere's volume
// (docs/geometry.md, "Thin slabs"). A failure with a deeper inradius, or a workspace overrun,
// stays degenerate.
constexpr int kThinSlab = 8;

template <class Real>
TALUS_HD inline bool below_dual_resolution(Real inradius, Real radius) {
  return inradius <= Real(kThinSlab) * SqrtEps<Real>::value * radius;
}

// The status of an overlap whose hull failed (or gave what no overlap of the two bodies can be,
// overlap_is_possible): touching for a slab below the dual's resolution, else degenerate.
template <class Real>
TALUS_HD inline OverlapStatus failed_hull_status(bool overrun, Real inradius, Real radius) {
  return !overrun && below_dual_resolution(inradius, radius) ? OverlapStatus::touching
                                                             : OverlapStatus::degenerate;
}

// Whether a hull's volume V, centroid c (in the frame of A's centroid) and vector area S can be
// an overlap of inradius r (the Chebyshev LP's) of bodies of bounding radii R_a, R_b about
// centres 0 and d: a convex body of inradius r is at most 2 sqrt(3) r wide (Steinhagen's
// inequality in three dimensions) and its sections lie in the smaller bounding sphere, so
// V <= 2 sqrt(3) r pi R^2 (R = min(R_a, R_b)); c lies in both spheres; |S| is at most the
// smaller sphere's area 4 pi R^2. A thin slab (a face resting on a face, ~1e-10 R deep) can fold
// the dual hull through round-off into any number while every face keeps its sign: two 1 cm
// cubes face to face 9e-13 m deep gave V = 7.8e9 m^3, a force to throw them out of the scene
// (tests/geometry/test_overlap_thin_slabs.cpp). A real overlap passes with room: a slab of
// depth 2 r over a section of at most pi R^2 is sqrt(3) below the bound; 1e-3 of it and the
// round-off's margins keep the bound from cutting one.
template <class Real>
TALUS_HD inline bool overlap_is_possible(Real volume, const Vec3<Real>& centroid,
                                         const Vec3<Real>& vector_area, Real inradius,
                                         Real radius_a, Real radius_b, const Vec3<Real>& centre_b,
                                         Real round_off) {
  const Real pi = Real(3.14159265358979323846);
  const Real radius = min_of(radius_a, radius_b);
  const Real width = Real(2 * 1.7320508075688772) * (max_of(inradius, Real(0)) + round_off);
  const Real margin = Real(1.001);
  if (!(volume <= margin * width * pi * radius * radius)) return false;
  if (!(norm(vector_area) <= margin * Real(4) * pi * radius * radius)) return false;
  const Real reach_a = margin * radius_a + round_off, reach_b = margin * radius_b + round_off;
  return norm(centroid) <= reach_a && norm(centroid - centre_b) <= reach_b;
}

// The vertex of the intersection dual to hull face f. Eq. 8 gives it as n_f / w_f, whose relative
// error grows like |y|/w ~ L/t (the dual points of a shallow overlap are long, ~1/t, while
// w ~ 1/L): in float that is 1e-3 of the depth for t = L/100. The same point is the meet of the
// face's three primal planes, dot(n_i, p) = s_i (p relative to x_o), whose Cramer solution
// p = (s_1 n_2 x n_3 + s_2 n_3 x n_1 + s_3 n_1 x n_2) / det(n_1, n_2, n_3) is conditioned by the
// angles between the planes instead. It is used unless the three normals are nearly dependent,
// where Eq. 8 is the better-conditioned form.
template <class Real, class Workspace>
TALUS_HD inline Vec3<Real> primal_vertex_of(const Workspace& ws, int f, Real w) {
  const auto& hull = ws.hull;
  const int i = hull.face_vertex[f][0], j = hull.face_vertex[f][1], k = hull.face_vertex[f][2];
  const Vec3<Real>& n1 = hull.plane_normal[i];
  const Vec3<Real>& n2 = hull.plane_normal[j];
  const Vec3<Real>& n3 = hull.plane_normal[k];
  const Vec3<Real> c23 = cross(n2, n3), c31 = cross(n3, n1), c12 = cross(n1, n2);
  const Real det = dot(n1, c23);
  if (abs_of(det) > Real(1e-3)) {
    // The slacks s_i are kept in plane_offset from step 4 on: one division, not twelve.
    return (c23 * ws.plane_offset[i] + c31 * ws.plane_offset[j] + c12 * ws.plane_offset[k]) *
           (Real(1) / det);
  }
  return hull.face_normal[f] / w;
}

// The planes of `mask` (A's faces first, then B's) in the frame, each handed to
// put(index, n, h, owner) in that order: their count, or -1 (none handed) when there are more
// than `capacity`. A's planes and B's are taken in loops of their own, so that no rotation is
// chosen at run time (on the GPU that would put the frame in the thread's local memory). Every
// caller with a mask takes its planes from here: one code for the planes of every kernel (the
// kernels' results agree bit for bit, GpuOverlap.PhasedAndWholePathsGiveIdenticalResults; what had
// made them differ was the rotation's fused products, see rounded_product in core/quat.hpp).
template <class Real, class Put>
TALUS_HD inline int mask_planes(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                const OverlapFrame<Real>& frame, unsigned long long mask,
                                int capacity, Put&& put) {
  if (bit_count(mask) > capacity) return -1;
  const int n_a = a.n_faces;
  const unsigned long long a_bits = n_a >= 64 ? mask : mask & ((1ull << n_a) - 1);
  int m = 0;
  for (unsigned long long bits = a_bits; bits != 0; ++m) {
    Vec3<Real> n;
    Real h;
    frame_plane(a, frame, 0, pop_lowest_bit(bits), n, h);
    put(m, n, h, 0);
  }
  for (unsigned long long bits = mask & ~a_bits; bits != 0; ++m) {
    Vec3<Real> n;
    Real h;
    frame_plane(b, frame, 1, pop_lowest_bit(bits) - n_a, n, h);
    put(m, n, h, 1);
  }
  return m;
}

// The planes of `mask` into ws (mask_planes): their count, or -1 when more than the workspace
// holds.
template <class Real, class Workspace>
TALUS_HD inline int planes_from_mask(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                     const OverlapFrame<Real>& frame, unsigned long long mask,
                                     Workspace& ws) {
  return mask_planes(a, b, frame, mask, Workspace::kMaxPlanes,
                     [&ws](int m, const Vec3<Real>& n, Real h, int owner) {
                       ws.hull.plane_normal[m] = n;
                       ws.plane_offset[m] = h;
                       ws.plane_owner[m] = static_cast<signed char>(owner);
                       ws.plane_twin[m] = 0;
                     });
}

// Steps 3-5 on the m planes in ws (hull.plane_normal, plane_offset, plane_owner; twins cleared).
template <class Real, class Workspace>
TALUS_HD inline OverlapResult<Real> overlap_finish(const ConvexView<Real>& a,
                                                   const Pose<Real>& pose_a,
                                                   const ConvexView<Real>& b,
                                                   const Pose<Real>& pose_b,
                                                   const OverlapFrame<Real>& frame, Workspace& ws,
                                                   int m, OverlapOptions options) {
  OverlapResult<Real> result;
  const Vec3<Real>* center = frame.center;
  const Mat3<Real>* rot = frame.rot;
  const Real round_off = frame.round_off;
  const ConvexView<Real>* body[2] = {&a, &b};
  auto& hull = ws.hull;
  Vec3<Real>* plane_normal = hull.plane_normal;
  // The fast path for a few planes (vertex_enumeration.hpp); what it declines goes on below.
  if (options.enumerate && m <= kEnumerationPlanes) {
    EnumerationPlane<Real> planes[kEnumerationPlanes];
    unsigned b_planes = 0;
    for (int i = 0; i < m; ++i) {
      planes[i] = {plane_normal[i], ws.plane_offset[i]};
      if (ws.plane_owner[i] != 0) b_planes |= 1u << i;
    }
    const EnumerationBodies<Real> bodies{
        a, b, pose_a.position, pose_a.orientation, pose_b.position, pose_b.orientation, round_off};
    if (enumerate_overlap(bodies, planes, 1, b_planes, m, result)) return result;
  }
  // Step 3. Reference point: the Chebyshev centre of the kept planes.
  const Real radius_sum = a.bounding_radius + b.bounding_radius;
  const Vec3<Real> start = center[1] * (a.bounding_radius / radius_sum);
  const ChebyshevResult<Real> lp =
      chebyshev_center(plane_normal, ws.plane_offset, m, start,
                       min_of(a.bounding_radius, b.bounding_radius), 8 * m + 32);
  result.depth_hint = lp.depth;
  if (lp.depth <= round_off) {
    result.status = lp.depth >= -round_off ? OverlapStatus::touching : OverlapStatus::separate;
    return result;
  }
  Vec3<Real> x_o = lp.center;
  const Real thin_radius = min_of(a.bounding_radius, b.bounding_radius);
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
  // Twins: a plane of B whose dual point lies within kTwin (relative) of one of A's is merged
  // into A's (see the header comment). Their separation is the relative difference of the two
  // planes seen from x_o; below ~sqrt(eps) the direction between the two points is lost in
  // round-off, so every hull face through both would be a sliver with a meaningless normal. The
  // volume lost by merging is a wedge of relative size ~kTwin * (face area * width / V), far
  // below the round-off budget of the test tolerances (1e-9 double, 1e-4 float).
  const Real twin_tolerance = TwinTolerance<Real>::value;
  int n_points = 0;
  for (int i = 0; i < m; ++i) {
    const Real slack = ws.plane_offset[i] - dot(plane_normal[i], x_o);
    const Real y_norm = Real(1) / slack;
    const Vec3<Real> y = plane_normal[i] * y_norm;
    bool merged = false;
    if (ws.plane_owner[i] == 1) {
      for (int j = 0; j < n_points && !merged; ++j) {
        if (ws.plane_owner[j] != 0) continue;
        if (norm(y - hull.point(j)) <= twin_tolerance * max_of(y_norm, hull.point_norm[j])) {
          ws.plane_twin[j] = 1;
          merged = true;
        }
      }
    }
    if (merged) continue;
    plane_normal[n_points] = plane_normal[i];  // the dual point is y = n * y_norm
    ws.plane_offset[n_points] = slack;         // from here on the slack at x_o
    ws.plane_owner[n_points] = ws.plane_owner[i];
    ws.plane_twin[n_points] = 0;
    hull.point_norm[n_points] = y_norm;
    ++n_points;
  }
  hull.n_points = n_points;
  m = n_points;
  // A thin overlap (a face resting on a face: a slab ~1e-8 deep under faces of millimetres) has
  // many Chebyshev centres, and the LP returns one at the slab's rim, within the depth of its side
  // faces too: then those dual points are as far out as the slab's large faces, two nearly
  // coplanar side faces of A and B (two stacked cubes a little misaligned) are nearly coincident
  // far out, and the hull fails or, through round-off, leaves the origin outside. Once, x_o then
  // moves to the analytic centre of the planes (analytic_centre_shift), deep inside in every
  // direction the polytope allows, and the hull is built again in rounded coordinates.
  //
  // Rounded: even from the analytic centre, the dual of a slab of depth d under faces of width w
  // has its two large faces' points at ~1/d and the side faces' at ~1/w; when the slab is a
  // wedge (two faces a microradian apart, their planes crossing inside the overlap) the hull's
  // faces between the far pair and the ring of near points are decided in the round-off of
  // ~1/d. So the retry also maps x' = L^T x, where L L^T = H is the barrier's Hessian at the
  // analytic centre: the ellipsoid x^T H x <= 1 (Dikin's) lies inside the polytope and m times
  // it contains the polytope, so in x' the polytope lies between the unit ball and the ball of
  // radius m and every dual point's norm is between 1/m and 1 (n_i^T H^-1 n_i <= s_i^2, as
  // H >= n_i n_i^T / s_i^2). The volume, centroid and vector area are mapped back at the end.
  bool rounded = false;
  Real rounding[6] = {1, 0, 1, 0, 0, 1};  // L, lower triangular (cholesky3); I until set
  for (int attempt = 0;; ++attempt) {
    bool built = build_dual_hull<Real>(hull);
    for (int f = 0; built && f < hull.n_slots; ++f)
      built = hull.face_stamp[f] < 0 || hull.face_offset[f] > Real(0);
    if (built) break;
    if (attempt > 0 || hull.overrun || !analytic_centre_shift<Real>(ws, m, x_o)) {
      result.workspace_overrun = hull.overrun;
      result.status = failed_hull_status(hull.overrun, lp.depth, thin_radius);
      result.thin_slab = result.status == OverlapStatus::touching;
      return result;
    }
    Vec3<Real> g;
    Real h[6];
    barrier_derivatives(ws, m, g, h);
    rounded = cholesky3(h, rounding);
    for (int i = 0; rounded && i < m; ++i) {
      const Vec3<Real> n = lower_solve(rounding, plane_normal[i]);  // n . x = (L^-1 n) . x'
      const Real length = norm(n);
      plane_normal[i] = n / length;
      ws.plane_offset[i] /= length;
    }
    for (int i = 0; i < m; ++i) hull.point_norm[i] = Real(1) / ws.plane_offset[i];
  }

  // Step 5. Unpolarise (Eqs. 6-8): dual face (n, w) -> primal vertex x_o + n / w. Each dual
  // vertex (a face of the polytope) remembers one dual face around it; that face's primal vertex,
  // a corner of the polygon, is the apex of the polygon's fan.
  auto* fan_apex = hull.point_face;  // free now: every point is on or inside the hull
  for (int i = 0; i < m; ++i) fan_apex[i] = -1;
  for (int f = 0; f < hull.n_slots; ++f) {
    if (hull.face_stamp[f] < 0) continue;
    const Real w = hull.face_offset[f];
    if (!(w > Real(0))) {  // the origin left the dual hull: only possible through round-off
      result.status = failed_hull_status(false, lp.depth, thin_radius);
      result.thin_slab = result.status == OverlapStatus::touching;
      return result;
    }
    // In place of the face's normal, which primal_vertex_of reads first.
    hull.face_normal[f] = overlap_detail::primal_vertex_of<Real>(ws, f, w);
    for (int k = 0; k < 3; ++k) fan_apex[hull.face_vertex[f][k]] = f;
  }
  // Cones from x_o over the fan of each face (Eq. 9): the primal edge between the vertices of
  // dual faces f and g lies on the faces of both dual vertices of their shared edge; the directed
  // edge (v0, v1) of f contributes its fan triangle to face v0 only, the twin edge of g to v1.
  Real volume = 0;
  Vec3<Real> moment, vector_area, surface_moment;  // the last about x_o (rounded: in x)
  for (int f = 0; f < hull.n_slots; ++f) {
    if (hull.face_stamp[f] < 0) continue;
    const Vec3<Real>& p_f = hull.face_normal[f];  // the primal vertex from here on
    for (int e = 0; e < 3; ++e) {
      const int v = hull.face_vertex[f][e];
      const int g = hull.face_neighbor[f][e];
      const int apex = fan_apex[v];
      if (apex == f || apex == g) continue;  // a triangle of the fan with no area
      const Vec3<Real>& p_g = hull.face_normal[g];
      const Vec3<Real>& c = hull.face_normal[apex];
      // Signed along the face's outward normal (the ring runs clockwise seen from outside):
      // a fan triangle flipped by round-off, where a primal vertex sits almost on the segment
      // of its neighbours, then subtracts instead of adding. Taking |area| cost float 1e-3.
      const Real area = dot(cross(p_g - c, p_f - c), plane_normal[v]) / Real(2);
      // area * distance / 3, the distance from x_o being the slack.
      const Real cone = area * ws.plane_offset[v] * (Real(1) / Real(3));
      volume += cone;
      moment += (c + p_f + p_g) * (cone / Real(4));
      const Real share =
          ws.plane_twin[v] ? Real(0.5) : (ws.plane_owner[v] == 0 ? Real(1) : Real(0));
      const Vec3<Real> shared_area = plane_normal[v] * (area * share);
      vector_area += shared_area;
      // The fan triangle's moment r x n dA, r its centroid; in rounded coordinates both mapped
      // back to x first (the moment is not linear in the map).
      const Vec3<Real> centre = (c + p_f + p_g) * (Real(1) / Real(3));
      if (rounded) {
        surface_moment += cross(upper_solve(rounding, centre), lower_times(rounding, shared_area)) /
                          (rounding[0] * rounding[2] * rounding[5]);
      } else {
        surface_moment += cross(centre, shared_area);
      }
    }
  }
  int on_hull = 0;
  for (int i = 0; i < m; ++i) on_hull += fan_apex[i] >= 0;
  result.hull_points = on_hull;
  Vec3<Real> centroid = volume > Real(0) ? moment / volume : Vec3<Real>();
  if (rounded) {  // back from x' = L^T x: V = V' / det L, c = L^-T c', S = L S' / det L
    const Real det = rounding[0] * rounding[2] * rounding[5];
    volume /= det;
    centroid = upper_solve(rounding, centroid);
    vector_area = lower_times(rounding, vector_area) / det;
  }
  if (!overlap_is_possible(volume, x_o + centroid, vector_area, lp.depth, a.bounding_radius,
                           b.bounding_radius, center[1], round_off)) {
    result.status = failed_hull_status(false, lp.depth, thin_radius);
    result.thin_slab = result.status == OverlapStatus::touching;
    return result;
  }
  result.volume = volume;
  result.vector_area = vector_area;
  result.centroid = pose_a.position + x_o + centroid;
  result.surface_moment = surface_moment - cross(centroid, vector_area);  // about the centroid
  result.status = volume > Real(0) ? OverlapStatus::overlapping : OverlapStatus::touching;
  return result;
}

// Steps 3-5 for the planes of `mask` (planes_from_mask), or workspace_overrun when the workspace
// cannot hold them.
template <class Real, class Workspace>
TALUS_HD inline OverlapResult<Real> finish_from_mask(
    const ConvexView<Real>& a, const Pose<Real>& pose_a, const ConvexView<Real>& b,
    const Pose<Real>& pose_b, const OverlapFrame<Real>& frame, unsigned long long mask,
    Workspace& ws, OverlapOptions options) {
  const int m = planes_from_mask(a, b, frame, mask, ws);
  if (m < 0) {
    OverlapResult<Real> result;
    result.workspace_overrun = true;
    result.status = OverlapStatus::degenerate;
    return result;
  }
  return overlap_finish(a, pose_a, b, pose_b, frame, ws, m, options);
}

}  // namespace overlap_detail

template <class Real, class Workspace>
TALUS_HD inline OverlapResult<Real> overlap_polyhedra(const ConvexView<Real>& a,
                                                      const Pose<Real>& pose_a,
                                                      const ConvexView<Real>& b,
                                                      const Pose<Real>& pose_b, Workspace& ws,
                                                      OverlapOptions options = OverlapOptions()) {
  using namespace overlap_detail;
  OverlapResult<Real> result;
  OverlapFrame<Real> frame;
  if (!overlap_frame(a, pose_a, b, pose_b, frame, result)) return result;
  const ConvexView<Real>* body[2] = {&a, &b};

  // Step 2. Planes of both bodies, culled against the other body's vertices and, where the
  // templates carry their face loops, by the face-polygon test (face_outside); by vertex masks
  // where they apply (cull_by_masks, the same decisions).
  if (culls_by_masks(a, b, options)) {
    unsigned long long kept = 0;
    if (cull_by_masks(a, b, frame, kept, result) < 0) return result;
    return finish_from_mask(a, pose_a, b, pose_b, frame, kept, ws, options);
  }
  const CullFrame<Real> cf = cull_frame(frame);
  int m = 0;
  for (int owner = 0; owner < 2; ++owner) {
    const ConvexView<Real>& self = *body[owner];
    const bool face_test = uses_face_test(self, options);
    const FaceTestFrame<Real> face_frame = face_test_frame(frame, owner);
    for (int f = 0; f < self.n_faces; ++f) {
      Vec3<Real> n;
      Real h;
      frame_plane(self, frame, owner, f, n, h);
      if (options.cull_planes) {
        Real lowest = 0;
        const PlaneCull cull =
            cull_plane(self, *body[1 - owner], frame, cf, owner, f, face_test, face_frame, lowest);
        if (cull == PlaneCull::beyond) {  // the other body lies beyond the plane
          result.status = beyond_status(lowest, frame.round_off);
          return result;
        }
        if (cull == PlaneCull::dropped) continue;
      }
      if (m >= Workspace::kMaxPlanes) {
        result.workspace_overrun = true;
        result.status = OverlapStatus::degenerate;
        return result;
      }
      ws.hull.plane_normal[m] = n;
      ws.plane_offset[m] = h;
      ws.plane_owner[m] = static_cast<signed char>(owner);
      ws.plane_twin[m] = 0;
      ++m;
    }
  }
  return overlap_finish(a, pose_a, b, pose_b, frame, ws, m, options);
}

// Step 2 alone, for a batch that culls in one kernel and builds the polytope in another: bit
// p of `mask` is set when plane p is kept (A's faces first, then B's; at most 64 planes in
// all). Returns the number of kept planes, or -1 when `result` is already final (bounding
// spheres apart, a separating plane). Same decisions as overlap_polyhedra's step 2.
template <class Real>
TALUS_HD inline int overlap_cull_mask(const ConvexView<Real>& a, const Pose<Real>& pose_a,
                                      const ConvexView<Real>& b, const Pose<Real>& pose_b,
                                      OverlapOptions options, unsigned long long& mask,
                                      OverlapResult<Real>& result) {
  using namespace overlap_detail;
  mask = 0;
  OverlapFrame<Real> frame;
  if (!overlap_frame(a, pose_a, b, pose_b, frame, result)) return -1;
  if (culls_by_masks(a, b, options)) return cull_by_masks(a, b, frame, mask, result);
  const ConvexView<Real>* body[2] = {&a, &b};
  const CullFrame<Real> cf = cull_frame(frame);
  int m = 0;
  for (int owner = 0; owner < 2; ++owner) {
    const ConvexView<Real>& self = *body[owner];
    const int first = owner == 0 ? 0 : a.n_faces;
    const bool face_test = uses_face_test(self, options);
    const FaceTestFrame<Real> face_frame = face_test_frame(frame, owner);
    for (int f = 0; f < self.n_faces; ++f) {
      if (options.cull_planes) {
        Real lowest = 0;
        const PlaneCull cull =
            cull_plane(self, *body[1 - owner], frame, cf, owner, f, face_test, face_frame, lowest);
        if (cull == PlaneCull::beyond) {
          result.status = beyond_status(lowest, frame.round_off);
          return -1;
        }
        if (cull == PlaneCull::dropped) continue;
      }
      mask |= 1ull << (first + f);
      ++m;
    }
  }
  return m;
}

// Steps 3-5 for the planes of `mask` (overlap_cull_mask), which must not number more than the
// workspace holds (else workspace_overrun, as overlap_polyhedra). Gives overlap_polyhedra's
// result bit for bit: the same planes in the same order through the same arithmetic.
template <class Real, class Workspace>
TALUS_HD inline OverlapResult<Real> overlap_from_mask(const ConvexView<Real>& a,
                                                      const Pose<Real>& pose_a,
                                                      const ConvexView<Real>& b,
                                                      const Pose<Real>& pose_b,
                                                      unsigned long long mask, Workspace& ws,
                                                      OverlapOptions options = OverlapOptions()) {
  using namespace overlap_detail;
  OverlapResult<Real> result;
  OverlapFrame<Real> frame;
  if (!overlap_frame(a, pose_a, b, pose_b, frame, result)) return result;
  return finish_from_mask(a, pose_a, b, pose_b, frame, mask, ws, options);
}

// The vertex enumeration alone for the planes of `mask` (overlap_cull_mask), with no workspace:
// true with `result` as overlap_from_mask gives it (bit for bit: the same planes in the same
// order through the same function) when the enumeration answers; false when it declines (more
// than kEnumerationPlanes planes, or a case it cannot certify), for the caller to run
// overlap_polyhedra or overlap_from_mask. For a GPU kernel over the pairs with few kept planes:
// its threads then hold neither the LP nor the hull. The planes are written to
// plane[p * stride], p < kEnumerationPlanes (a GPU kernel gives each thread its slice of an
// array in shared memory, interleaved with the other threads' slices, so that nothing of the
// pair goes through the thread's local memory); `bodies.round_off` is set here.
template <class Real>
TALUS_HD inline bool overlap_enumerate_from_mask(overlap_detail::EnumerationBodies<Real> bodies,
                                                 unsigned long long mask,
                                                 overlap_detail::EnumerationPlane<Real>* plane,
                                                 int stride, OverlapResult<Real>& result) {
  using namespace overlap_detail;
  OverlapFrame<Real> frame;
  OverlapResult<Real> scratch;
  const Pose<Real> pose_a{bodies.position_a, bodies.orientation_a};
  const Pose<Real> pose_b{bodies.position_b, bodies.orientation_b};
  if (!overlap_frame(bodies.a, pose_a, bodies.b, pose_b, frame, scratch)) return false;
  unsigned b_planes = 0;
  const int m =
      mask_planes(bodies.a, bodies.b, frame, mask, kEnumerationPlanes,
                  [plane, stride, &b_planes](int k, const Vec3<Real>& n, Real h, int owner) {
                    plane[k * stride] = {n, h};
                    if (owner != 0) b_planes |= 1u << k;
                  });
  if (m < 0) return false;
  bodies.round_off = frame.round_off;
  return enumerate_overlap(bodies, plane, stride, b_planes, m, result);
}

// The same with the planes in a local array.
template <class Real>
TALUS_HD inline bool overlap_enumerate_from_mask(const ConvexView<Real>& a,
                                                 const Pose<Real>& pose_a,
                                                 const ConvexView<Real>& b,
                                                 const Pose<Real>& pose_b, unsigned long long mask,
                                                 OverlapResult<Real>& result) {
  overlap_detail::EnumerationPlane<Real> planes[kEnumerationPlanes];
  const overlap_detail::EnumerationBodies<Real> bodies{
      a, b, pose_a.position, pose_a.orientation, pose_b.position, pose_b.orientation, Real(0)};
  return overlap_enumerate_from_mask(bodies, mask, planes, 1, result);
}

}  // namespace talus
