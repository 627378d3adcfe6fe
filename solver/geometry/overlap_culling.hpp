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

// Where the plane (n_body, h_body), in the other body's frame (plane_in_other), leaves `other`,
// from the signed heights of its vertices above the plane, with `round_off` the absolute
// round-off of a height. The loop stops as soon as one vertex lies below -round_off and one at or
// above it: the plane then cuts the body, and the rest of the vertices cannot change that. Only a
// separating plane needs every height, for `lowest`.
enum class PlaneSide { cuts, below, beyond };

template <class Real>
TALUS_HD inline PlaneSide plane_side(const ConvexView<Real>& other, const Vec3<Real>& n_body,
                                     Real h_body, Real round_off, Real& lowest) {
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

// The bodies placed relative to each other, for the culling: a_to_b = R_B^T R_A takes A's body
// frame to B's (its transpose, exactly, B's to A's), and shift_a = R_A^T (c_A - c_B),
// shift_b = R_B^T (c_B - c_A) are each centre relative to the other, in its own body frame. The
// plane of a face of body k (n_f . x <= d_f in k's frame) is then, in the other body's frame,
// n = R n_f with offset d_f + n_f . shift_k (plane_in_other): the other body's vertices are
// tested in their own frame, with no per-plane detour through the pair's frame, and the two
// culling paths (cull_plane and cull_by_masks) share this arithmetic, so they decide alike.
template <class Real>
struct CullFrame {
  Mat3<Real> a_to_b;
  Vec3<Real> shift_a, shift_b;
};

template <class Real>
TALUS_HD inline CullFrame<Real> cull_frame(const OverlapFrame<Real>& frame) {
  const Mat3<Real>& ra = frame.rot[0];
  const Mat3<Real>& rb = frame.rot[1];
  CullFrame<Real> c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c.a_to_b.m[i][j] =
          rb.m[0][i] * ra.m[0][j] + rb.m[1][i] * ra.m[1][j] + rb.m[2][i] * ra.m[2][j];
  // The frame is centred on A: c_A = 0.
  c.shift_a = ra.transpose_times(-frame.center[1]);
  c.shift_b = rb.transpose_times(frame.center[1]);
  return c;
}

// The plane of face f of `self` (body `owner`) in the other body's frame: dot(n_body, x) <=
// h_body inside.
template <class Real>
TALUS_HD inline void plane_in_other(const ConvexView<Real>& self, int owner, int f,
                                    const CullFrame<Real>& cf, Vec3<Real>& n_body, Real& h_body) {
  const Vec3<Real> n = self.face_normals[f];
  n_body = owner == 0 ? cf.a_to_b * n : cf.a_to_b.transpose_times(n);
  h_body = self.face_offsets[f] + dot(n, owner == 0 ? cf.shift_a : cf.shift_b);
}

enum class PlaneCull { kept, dropped, beyond };

// Step 2 for the plane of face f of `self` (body `owner`) against `other`: kept, dropped (it
// cannot bound the intersection), or beyond (the other body lies beyond it: a separating plane,
// with `lowest` the other body's least height above it).
template <class Real>
TALUS_HD inline PlaneCull cull_plane(const ConvexView<Real>& self, const ConvexView<Real>& other,
                                     const OverlapFrame<Real>& frame, const CullFrame<Real>& cf,
                                     int owner, int f, bool face_test,
                                     const FaceTestFrame<Real>& face_frame, Real& lowest) {
  Vec3<Real> n_body;
  Real h_body;
  plane_in_other(self, owner, f, cf, n_body, h_body);
  // The other body's bounding sphere (about its centre, the origin of its frame) decides most
  // planes without visiting its vertices.
  if (other.bounding_radius - h_body < -frame.round_off) return PlaneCull::dropped;
  const PlaneSide side = plane_side(other, n_body, h_body, frame.round_off, lowest);
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

// The number of set bits of a mask.
TALUS_HD inline int bit_count(unsigned long long mask) {
#ifdef __CUDA_ARCH__
  return __popcll(mask);
#else
  return __builtin_popcountll(mask);
#endif
}

// Step 2 by vertex masks, for templates with vertex records (ConvexView::vertex_records: at most
// 64 vertices and 64 faces) and face loops, 64 faces together: the decisions of cull_plane (the
// same sphere test and the same vertex heights in the other body's frame: dropped, beyond or
// kept), with the face test folded into each plane's pass over the other body's vertices instead
// of a loop over the other body's planes per face. A face of the other body whose corners all lie
// above the plane by more than the round-off is outside this plane's body, and so cannot bound
// the intersection (face_outside's argument, with the roles of the two bodies swapped): the pass
// collects the faces of the vertices that are not above, and the rest are outside.
template <class Real>
TALUS_HD inline bool culls_by_masks(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                    OverlapOptions options) {
  return uses_face_test(a, options) && uses_face_test(b, options) && a.n_faces + b.n_faces <= 64 &&
         a.vertex_records != nullptr && b.vertex_records != nullptr;
}

// The least height over the other body's vertices above the plane (plane_side's `lowest`):
// only a separating plane needs its value.
template <class Real>
TALUS_HD inline Real lowest_height(const ConvexView<Real>& other, const Vec3<Real>& n_body,
                                   Real h_body) {
  Real low = dot(n_body, other.vertices[0]);
  for (int v = 1; v < other.n_vertices; ++v) low = min_of(low, dot(n_body, other.vertices[v]));
  return low - h_body;
}

// What cull_by_masks learns of one plane (n_body, h_body) in the other body's frame from one pass
// over that body's vertices, with d = dot(n_body, x) - h_body the height of vertex x (as
// plane_side computes it): `beyond`, every d > -round_off (a separating plane: the body lies
// beyond it); `below`, every d < -round_off (the body lies strictly inside the half-space: the
// plane bounds nothing); else `outside`, the other body's faces (bit g for face g) whose corners
// all have d > round_off. Rounding is monotone, so these read as plane_side's tests on the least
// and greatest dot products.
struct PlanePass {
  unsigned long long outside = 0;
  bool beyond = false, below = false;
};

// The pass's verdict from the faces of the vertices not above the plane (`touched`) and whether
// some vertex has d <= -round_off (`any_low`) and some d >= -round_off (`any_high`).
template <class Real>
TALUS_HD inline PlanePass plane_pass_from(const ConvexView<Real>& other, unsigned long long touched,
                                          bool any_low, bool any_high) {
  const unsigned long long faces = other.n_faces >= 64 ? ~0ull : (1ull << other.n_faces) - 1;
  PlanePass pass;
  pass.outside = faces & ~touched;  // every corner above the plane
  pass.beyond = !any_low;
  pass.below = !any_high;
  return pass;
}

// `faces` where `take`, else none. A GPU predicates the branch (one instruction); a CPU would
// mispredict it about every other vertex, which made the host's culling much slower
// (benchmarks/history/README.md), so there it is arithmetic.
template <class FaceMask>
TALUS_HD inline FaceMask faces_if(bool take, FaceMask faces) {
#ifdef __CUDA_ARCH__
  return take ? faces : FaceMask(0);
#else
  return faces & (FaceMask(0) - FaceMask(take));
#endif
}

// The pass over the vertex records. `touched` collects the faces of the vertices with
// d <= round_off; every other face has all its corners above. FaceMask: an unsigned type of at
// least other.n_faces bits (32 where they suffice: half the integer work a vertex).
template <class FaceMask, class Real>
TALUS_HD inline PlanePass records_pass(const ConvexView<Real>& other, const Vec3<Real>& n_body,
                                       Real h_body, Real round_off) {
  FaceMask touched = 0;
  bool any_low = false, any_high = false;  // some d <= -round_off; some d >= -round_off
#ifdef __CUDA_ARCH__
#pragma unroll 4
#endif
  for (int v = 0; v < other.n_vertices; ++v) {
    const VertexRecord<Real> record = other.vertex_records[v];
    const Real d = dot(n_body, record.position) - h_body;
    touched |= faces_if(!(d > round_off), FaceMask(record.faces));
    any_low |= !(d > -round_off);
    any_high |= !(d < -round_off);
  }
  return plane_pass_from(other, touched, any_low, any_high);
}

// The same decisions from the vertices rounded to float (ConvexView::filter_vertices), for a
// double body: true with `pass` filled when every vertex's float height lies farther from 0 than
// `band`, a bound on its difference from the double height (plus the round-off), so that each
// test reads as it does in double; false (`pass` untouched) when some vertex lies within the band,
// or a value is not finite, for the caller to run the pass in double. The heights of the float
// pass: the rounded normal, vertex and offset (relative error 2^-24 each: 2 * 2^-24 * R on the
// dot product, with R >= |x| the bounding radius and |n| = 1, and 2^-24 |h|) and at most six
// roundings in the products and sums (fused or not; each at most 2^-24 (R + |h|)) differ from
// the exact height by less than 8 * 2^-24 * (R + |h|), and the double height from the exact one
// by about 1e-16 (R + |h|): the band takes 12 * 2^-24 * (R + |h|) + round_off. A GPU warp then
// reads 16 bytes a vertex instead of 32 and runs single-precision arithmetic, at twice the
// double rate.
template <class Real>
TALUS_HD inline bool filtered_pass(const ConvexView<Real>& other, const Vec3<Real>& n_body,
                                   Real h_body, Real round_off, PlanePass& pass) {
  constexpr Real kHalfUlp = Real(1) / Real(1 << 24);  // 2^-24, float's unit round-off
  const Real bound = Real(12) * kHalfUlp * (other.bounding_radius + abs_of(h_body)) + round_off;
  // Rounded to float upwards (the product's excess is far more than float's half ulp), with a
  // floor far below any vertex height a template meets, against underflow.
  const float band = static_cast<float>(bound * Real(1.000001)) + 1e-30f;
  const float nx = static_cast<float>(n_body.x), ny = static_cast<float>(n_body.y),
              nz = static_cast<float>(n_body.z), h = static_cast<float>(h_body);
  unsigned touched = 0;
  bool any_low = false, any_high = false, ambiguous = false;
#ifdef __CUDA_ARCH__
#pragma unroll 4
#endif
  for (int v = 0; v < other.n_vertices; ++v) {
    const FilterVertex vertex = other.filter_vertices[v];
    const float d = nx * vertex.x + ny * vertex.y + nz * vertex.z - h;
    ambiguous |= !(abs_of(d) > band);  // NaN too
    const bool up = d > 0.0f;          // d > band: above; d < -band: below -round_off
    touched |= faces_if(!up, vertex.faces);
    any_low |= !up;
    any_high |= up;
  }
  if (ambiguous) return false;
  pass = plane_pass_from(other, touched, any_low, any_high);
  return true;
}

template <class Real>
TALUS_HD inline PlanePass plane_pass(const ConvexView<Real>& other, const Vec3<Real>& n_body,
                                     Real h_body, Real round_off) {
#ifdef __CUDA_ARCH__
  // The float pass pays on the GPU only: a CPU core computes double as fast as float, so there
  // the pass is extra work that made the overlap slower (benchmarks/history/README.md).
  PlanePass pass;
  if (other.filter_vertices && filtered_pass(other, n_body, h_body, round_off, pass)) return pass;
#endif
  if (other.n_faces <= 32) return records_pass<unsigned>(other, n_body, h_body, round_off);
  return records_pass<unsigned long long>(other, n_body, h_body, round_off);
}

// Returns the number of kept planes with bit p of `kept` set for each (A's faces first, then
// B's), or -1 when `result` is final (a separating plane: the first in that order, as
// overlap_polyhedra's loop finds it).
// Two passes, so that the threads of a GPU warp loop together over few planes: the bounding
// sphere test of every plane first (cheap: most planes of a shallow contact face away from the
// other body and drop here), then, for each plane left, in the same order, one full pass over
// the other body's vertices (no early exit: the warp's threads run the same loop) with the face
// test of the other body's faces folded in (plane_pass: the faces of the vertices not above the
// plane, read from the vertex records; for a double body first in float). A plane dropped by
// the sphere or lying strictly inside marks no face (no corner lies above it), as the per-face
// test finds.
template <class Real>
TALUS_HD inline int cull_by_masks(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                  const OverlapFrame<Real>& frame, unsigned long long& kept,
                                  OverlapResult<Real>& result) {
  const ConvexView<Real>* body[2] = {&a, &b};
  const Real round_off = frame.round_off;
  const CullFrame<Real> cf = cull_frame(frame);
  // Pass 1: the planes the other body's bounding sphere does not leave strictly inside (the
  // offset of the plane in the other body's frame is the height of its centre below it).
  unsigned long long cutting = 0;
  for (int f = 0; f < a.n_faces; ++f)
    if (!(b.bounding_radius - (a.face_offsets[f] + dot(a.face_normals[f], cf.shift_a)) <
          -round_off))
      cutting |= 1ull << f;
  for (int f = 0; f < b.n_faces; ++f)
    if (!(a.bounding_radius - (b.face_offsets[f] + dot(b.face_normals[f], cf.shift_b)) <
          -round_off))
      cutting |= 1ull << (a.n_faces + f);
  // Pass 2: the vertex heights (as plane_side computes them) of each plane left.
  unsigned long long candidates = 0, outside = 0;
  while (cutting != 0) {
    const int p = pop_lowest_bit(cutting);
    const int owner = p < a.n_faces ? 0 : 1, o = 1 - owner;
    const ConvexView<Real>& self = *body[owner];
    const ConvexView<Real>& other = *body[o];
    Vec3<Real> n_body;
    Real h_body;
    plane_in_other(self, owner, owner == 0 ? p : p - a.n_faces, cf, n_body, h_body);
    const PlanePass pass = plane_pass(other, n_body, h_body, round_off);
    if (pass.beyond) {  // the other body lies beyond: a separating plane
      result.status = beyond_status(lowest_height(other, n_body, h_body), round_off);
      return -1;
    }
    if (pass.below) continue;  // strictly inside: bounds nothing
    candidates |= 1ull << p;
    outside |= pass.outside << (o == 0 ? 0 : a.n_faces);
  }
  kept = candidates & ~outside;
  return bit_count(kept);
}

}  // namespace overlap_detail

}  // namespace talus
