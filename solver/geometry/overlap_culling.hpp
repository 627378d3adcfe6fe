// Steps 1 and 2 of the overlap of two posed convex polyhedra (overlap_polyhedra.hpp, paper
// §2.3): the pair's frame centred on A, and the culling of the face planes that cannot bound the
// intersection, with its separating-plane exit (docs/geometry.md, "Plane culling"): plane by
// plane (cull_plane) or, where the templates allow, by vertex masks (cull_by_masks).
#pragma once

#include "solver/geometry/convex.hpp"
#include "solver/geometry/overlap.hpp"

namespace talus {

// A pair's frame (step 1): both centres in the frame centred on A, their distance, the absolute
// round-off of an offset or height in that frame, and both rotations. The steps below share it;
// the GPU batch computes it once per kernel that handles the pair.
template <class Real>
struct OverlapFrame {
  Vec3<Real> center[2];
  Real distance = 0;
  Real round_off = 0;
  Mat3<Real> rot[2];
};

namespace overlap_detail {

// Where the plane (n, h) of the frame centred on A leaves `other` (at `other_center`, rotated by
// `other_rot`), from the signed heights of its vertices above the plane, with `round_off` the
// absolute round-off of a height. The loop stops as soon as one vertex lies below -round_off and
// one at or above it: the plane then cuts the body, and the rest of the vertices cannot change
// that. Only a separating plane needs every height, for `lowest`.
enum class PlaneSide { cuts, below, beyond };

template <class Real>
TALUS_HD inline PlaneSide plane_side(const ConvexView<Real>& other, const Mat3<Real>& other_rot,
                                     const Vec3<Real>& other_center, const Vec3<Real>& n, Real h,
                                     Real round_off, Real& lowest) {
  const Vec3<Real> n_body = other_rot.transpose_times(n);
  const Real h_body = h - dot(n, other_center);
  Real low = dot(n_body, other.vertices[0]), high = low;
  for (int i = 1; i < other.n_vertices; ++i) {
    const Real s = dot(n_body, other.vertices[i]);
    low = min_of(low, s);
    high = max_of(high, s);
    // Rounding is monotone, so min_i(s_i) - h_body rounds to the least of the rounded
    // differences: the test reads the same as on the full range.
    if (low - h_body <= -round_off && !(high - h_body < -round_off)) return PlaneSide::cuts;
  }
  lowest = low - h_body;
  if (lowest > -round_off) return PlaneSide::beyond;        // a separating plane
  if (high - h_body < -round_off) return PlaneSide::below;  // strictly inside: bounds nothing
  return PlaneSide::cuts;
}

// True when face f of `self` (its polygon, not its plane) lies strictly outside `other`: some
// plane of `other` has every vertex of the face above it by more than `margin`. The other body's
// planes are taken to self's body frame as they are needed: normal `to_self * n`, offset
// `h + dot(n, shift)` (to_self = R_self^T R_other, shift = R_other^T (c_other - c_self)), which
// costs a few multiplications instead of a table per pair in memory. Such a face cannot bound
// the intersection: were its plane needed, removing it would let the intersection grow past the
// plane, and the segment from an interior point to the new part would cross the plane inside
// both bodies, i.e. on the face and inside `other`.
template <class Real>
TALUS_HD inline bool face_outside(const ConvexView<Real>& self, int f,
                                  const ConvexView<Real>& other, const Mat3<Real>& to_self,
                                  const Vec3<Real>& shift, Real margin) {
  const int begin = self.face_loop_offsets[f], end = self.face_loop_offsets[f + 1];
  for (int g = 0; g < other.n_faces; ++g) {
    const Vec3<Real> n_other = other.face_normals[g];
    const Vec3<Real> n = to_self * n_other;
    const Real h = other.face_offsets[g] + dot(n_other, shift) + margin;
    bool all_above = true;
    for (int k = begin; k < end && all_above; ++k)
      all_above = dot(n, self.vertices[self.face_loop_vertices[k]]) > h;
    if (all_above) return true;
  }
  return false;
}

// Step 1. Frame centred on A: positions far from the world origin lose no digits. False when the
// bounding spheres are apart (or the input is NaN), with `result` final.
template <class Real>
TALUS_HD inline bool overlap_frame(const ConvexView<Real>& a, const Pose<Real>& pose_a,
                                   const ConvexView<Real>& b, const Pose<Real>& pose_b,
                                   OverlapFrame<Real>& frame, OverlapResult<Real>& result) {
  const Real eps = Eps<Real>::value;
  frame.center[0] = Vec3<Real>();
  frame.center[1] = pose_b.position - pose_a.position;
  const Real distance = norm(frame.center[1]);
  frame.distance = distance;
  if (!(distance <= a.bounding_radius + b.bounding_radius)) {
    if (!(distance == distance)) result.status = OverlapStatus::degenerate;  // NaN input
    return false;
  }
  // Absolute round-off of a plane offset or a vertex height in this frame, whose points lie
  // within `reach` of its origin.
  const Real reach = max_of(a.bounding_radius, b.bounding_radius) + distance;
  frame.round_off = Real(64) * eps * reach;
  frame.rot[0] = rotation_matrix(pose_a.orientation);
  frame.rot[1] = rotation_matrix(pose_b.orientation);
  return true;
}

// What the face test of body `owner` needs: R_self^T R_other (the other body's frame to self's)
// and the other centre in self's frame (face_outside).
template <class Real>
struct FaceTestFrame {
  Mat3<Real> to_self;
  Vec3<Real> shift;
};

template <class Real>
TALUS_HD inline FaceTestFrame<Real> face_test_frame(const OverlapFrame<Real>& frame, int owner) {
  const int other = 1 - owner;
  const Mat3<Real>* rot = frame.rot;
  FaceTestFrame<Real> t;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      t.to_self.m[i][j] = rot[owner].m[0][i] * rot[other].m[0][j] +
                          rot[owner].m[1][i] * rot[other].m[1][j] +
                          rot[owner].m[2][i] * rot[other].m[2][j];
  t.shift = rot[other].transpose_times(frame.center[other] - frame.center[owner]);
  return t;
}

// The plane of face f of body `owner` in the frame: dot(n, x) <= h inside.
template <class Real>
TALUS_HD inline void frame_plane(const ConvexView<Real>& self, const OverlapFrame<Real>& frame,
                                 int owner, int f, Vec3<Real>& n, Real& h) {
  n = frame.rot[owner] * self.face_normals[f];
  h = self.face_offsets[f] + dot(n, frame.center[owner]);
}

enum class PlaneCull { kept, dropped, beyond };

// Step 2 for the plane (n, h) of face f of `self` (body `owner`) against `other`: kept, dropped
// (it cannot bound the intersection), or beyond (the other body lies beyond it: a separating
// plane, with `lowest` the other body's least height above it).
template <class Real>
TALUS_HD inline PlaneCull cull_plane(const ConvexView<Real>& self, const ConvexView<Real>& other,
                                     const OverlapFrame<Real>& frame, int owner, int f,
                                     const Vec3<Real>& n, Real h, bool face_test,
                                     const FaceTestFrame<Real>& face_frame, Real& lowest) {
  const int o = 1 - owner;
  // The other body's bounding sphere decides most planes without visiting its vertices.
  const Real sphere_height = dot(n, frame.center[o]) - h;
  if (sphere_height + other.bounding_radius < -frame.round_off) return PlaneCull::dropped;
  const PlaneSide side =
      plane_side(other, frame.rot[o], frame.center[o], n, h, frame.round_off, lowest);
  if (side == PlaneSide::beyond) return PlaneCull::beyond;
  if (side == PlaneSide::below) return PlaneCull::dropped;  // strictly inside: bounds nothing
  if (face_test &&
      face_outside(self, f, other, face_frame.to_self, face_frame.shift, frame.round_off))
    return PlaneCull::dropped;
  return PlaneCull::kept;
}

// The verdict of a separating plane whose far side holds the other body `lowest` above it.
template <class Real>
TALUS_HD inline OverlapStatus beyond_status(Real lowest, Real round_off) {
  return lowest > round_off ? OverlapStatus::separate : OverlapStatus::touching;
}

template <class Real>
TALUS_HD inline bool uses_face_test(const ConvexView<Real>& self, OverlapOptions options) {
  return options.cull_planes && options.cull_faces && self.face_loop_offsets != nullptr;
}

// The index of the lowest set bit of a non-zero mask, cleared from it.
TALUS_HD inline int pop_lowest_bit(unsigned long long& mask) {
#ifdef __CUDA_ARCH__
  const int p = __ffsll(static_cast<long long>(mask)) - 1;
#else
  const int p = __builtin_ctzll(mask);
#endif
  mask &= mask - 1;
  return p;
}

// Step 2 by vertex masks, for templates of at most 64 vertices and 64 faces together, both with
// their face loops: the decisions of cull_plane (the same sphere test and the same vertex
// heights in the other body's frame: dropped, beyond or kept), with the face test read from bit
// masks instead of a loop over the other body's planes per face. Each plane's pass over the
// other body's vertices records which of them lie above it by more than the round-off; face f
// of `self` lies outside `other` when some plane of `other` has every corner of f in its mask.
// Every plane costs one pass over the other body's vertices with no early exit, so the threads
// of a warp run the same loops (the GPU's culling kernel), and the face test, which re-posed the
// other body's planes for every face, becomes a few AND operations.
template <class Real>
TALUS_HD inline bool culls_by_masks(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                    OverlapOptions options) {
  return uses_face_test(a, options) && uses_face_test(b, options) && a.n_faces + b.n_faces <= 64 &&
         a.n_vertices <= 64 && b.n_vertices <= 64;
}

// Returns the number of kept planes with bit p of `kept` set for each (A's faces first, then
// B's), or -1 when `result` is final (a separating plane: the first in that order, as
// overlap_polyhedra's loop finds it).
template <class Real>
TALUS_HD inline int cull_by_masks(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                  const OverlapFrame<Real>& frame, unsigned long long& kept,
                                  OverlapResult<Real>& result) {
  const ConvexView<Real>* body[2] = {&a, &b};
  const Real round_off = frame.round_off;
  // above[p]: the other body's vertices more than round_off above plane p (0 when dropped).
  unsigned long long above[64];
  unsigned long long candidates = 0;
  for (int owner = 0; owner < 2; ++owner) {
    const ConvexView<Real>& self = *body[owner];
    const ConvexView<Real>& other = *body[1 - owner];
    const int o = 1 - owner, first = owner == 0 ? 0 : a.n_faces;
    for (int f = 0; f < self.n_faces; ++f) {
      const int p = first + f;
      above[p] = 0;
      Vec3<Real> n;
      Real h;
      frame_plane(self, frame, owner, f, n, h);
      // The bounding sphere first, as cull_plane.
      if (dot(n, frame.center[o]) - h + other.bounding_radius < -round_off) continue;
      // The heights as plane_side computes them.
      const Vec3<Real> n_body = frame.rot[o].transpose_times(n);
      const Real h_body = h - dot(n, frame.center[o]);
      Real low = dot(n_body, other.vertices[0]), high = low;
      unsigned long long mask = low - h_body > round_off ? 1ull : 0ull;
      for (int v = 1; v < other.n_vertices; ++v) {
        const Real height = dot(n_body, other.vertices[v]);
        low = min_of(low, height);
        high = max_of(high, height);
        if (height - h_body > round_off) mask |= 1ull << v;
      }
      const Real lowest = low - h_body;
      if (lowest > -round_off) {  // the other body lies beyond: a separating plane
        result.status = beyond_status(lowest, round_off);
        return -1;
      }
      if (high - h_body < -round_off) continue;  // strictly inside: bounds nothing
      above[p] = mask;
      candidates |= 1ull << p;
    }
  }
  // The face test (face_outside's argument) on the planes that cut the other body.
  kept = 0;
  int m = 0;
  while (candidates != 0) {
    const int p = pop_lowest_bit(candidates);
    const int owner = p < a.n_faces ? 0 : 1;
    const ConvexView<Real>& self = *body[owner];
    const int f = owner == 0 ? p : p - a.n_faces;
    unsigned long long corners = 0;
    for (int k = self.face_loop_offsets[f]; k < self.face_loop_offsets[f + 1]; ++k)
      corners |= 1ull << self.face_loop_vertices[k];
    const int other_first = owner == 0 ? a.n_faces : 0;
    const int other_end = owner == 0 ? a.n_faces + b.n_faces : a.n_faces;
    bool outside = false;
    for (int q = other_first; q < other_end && !outside; ++q) outside = (corners & ~above[q]) == 0;
    if (outside) continue;
    kept |= 1ull << p;
    ++m;
  }
  return m;
}

}  // namespace overlap_detail

}  // namespace talus
