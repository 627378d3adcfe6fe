// GJK boolean intersection test of two posed convex polyhedra (paper §2.2, Algorithm I, Eqs. 1-3).
// The narrow-phase filter before the overlap volume: it must never call an overlapping pair
// separate. On polytopes GJK terminates in exact arithmetic; in floating point the iteration count
// is bounded and a pair that has not been decided by then is reported as intersecting, so the
// exact overlap computation (which detects separation itself) has the last word.
#pragma once

#include "solver/core/math.hpp"
#include "solver/geometry/convex.hpp"

namespace talus {

template <class Real>
struct GjkResult {
  bool intersecting = false;
  int iterations = 0;
  bool iteration_limit_hit = false;
};

namespace gjk_detail {

// Support point of the Minkowski difference A - B in direction dir (Eq. 3).
template <class Real>
struct MinkowskiDifference {
  const ConvexView<Real>* a;
  const ConvexView<Real>* b;
  Mat3<Real> rot_a, rot_b;
  Vec3<Real> center_a, center_b;  // relative to a common local origin (A's centre)

  TALUS_HD Vec3<Real> support(const Vec3<Real>& dir) const {
    return support_point(*a, rot_a, center_a, dir) - support_point(*b, rot_b, center_b, -dir);
  }
};

// The three cases of "UpdateSimplex" in Algorithm I: reduce the simplex to the feature nearest
// the origin and set the new search direction. The newest point is always s[n-1]. Returns true
// when the origin is enclosed (or lies on the simplex: touching counts as intersecting).
template <class Real>
TALUS_HD inline bool line_case(Vec3<Real>* s, int& n, Vec3<Real>& dir) {
  const Vec3<Real> a = s[1], b = s[0];
  const Vec3<Real> ab = b - a, ao = -a;
  if (dot(ab, ao) > 0) {
    dir = cross(cross(ab, ao), ab);
    if (norm2(dir) == Real(0)) return true;  // origin on the segment
  } else {
    s[0] = a;
    n = 1;
    dir = ao;
  }
  return false;
}

template <class Real>
TALUS_HD inline bool triangle_case(Vec3<Real>* s, int& n, Vec3<Real>& dir) {
  const Vec3<Real> a = s[2], b = s[1], c = s[0];
  const Vec3<Real> ab = b - a, ac = c - a, ao = -a;
  const Vec3<Real> abc = cross(ab, ac);
  if (dot(cross(abc, ac), ao) > 0) {
    if (dot(ac, ao) > 0) {
      s[0] = c;
      s[1] = a;
      n = 2;
      dir = cross(cross(ac, ao), ac);
      return norm2(dir) == Real(0);
    }
    s[0] = b;
    s[1] = a;
    n = 2;
    return line_case(s, n, dir);
  }
  if (dot(cross(ab, abc), ao) > 0) {
    s[0] = b;
    s[1] = a;
    n = 2;
    return line_case(s, n, dir);
  }
  const Real side = dot(abc, ao);
  if (side > 0) {
    dir = abc;  // keep the winding c, b, a: the origin is above
  } else if (side < 0) {
    s[0] = b;
    s[1] = c;  // flip the winding so the origin is above
    dir = -abc;
  } else {
    return true;  // origin inside the triangle
  }
  return false;
}

template <class Real>
TALUS_HD inline bool tetrahedron_case(Vec3<Real>* s, int& n, Vec3<Real>& dir) {
  // a is the newest point; the base (b, c, d) is wound so that the origin was on a's side.
  const Vec3<Real> a = s[3], b = s[2], c = s[1], d = s[0];
  const Vec3<Real> ao = -a;
  if (dot(cross(b - a, c - a), ao) > 0) {
    s[0] = c;
    s[1] = b;
    s[2] = a;
    n = 3;
    return triangle_case(s, n, dir);
  }
  if (dot(cross(c - a, d - a), ao) > 0) {
    s[0] = d;
    s[1] = c;
    s[2] = a;
    n = 3;
    return triangle_case(s, n, dir);
  }
  if (dot(cross(d - a, b - a), ao) > 0) {
    s[0] = b;
    s[1] = d;
    s[2] = a;
    n = 3;
    return triangle_case(s, n, dir);
  }
  return true;
}

template <class Real>
TALUS_HD inline bool update_simplex(Vec3<Real>* s, int& n, Vec3<Real>& dir) {
  if (n == 2) return line_case(s, n, dir);
  if (n == 3) return triangle_case(s, n, dir);
  return tetrahedron_case(s, n, dir);
}

}  // namespace gjk_detail

// Algorithm I. `max_iterations` bounds the loop; the default is ample for polytopes of up to a
// few hundred vertices (each iteration adds a support point not seen before, or stops).
template <class Real>
TALUS_HD inline GjkResult<Real> gjk_intersect(const ConvexView<Real>& a, const Pose<Real>& pose_a,
                                              const ConvexView<Real>& b, const Pose<Real>& pose_b,
                                              int max_iterations = 64) {
  gjk_detail::MinkowskiDifference<Real> md;
  md.a = &a;
  md.b = &b;
  md.rot_a = rotation_matrix(pose_a.orientation);
  md.rot_b = rotation_matrix(pose_b.orientation);
  md.center_a = Vec3<Real>();  // work relative to A's centre: small numbers, less round-off
  md.center_b = pose_b.position - pose_a.position;

  GjkResult<Real> result;
  Vec3<Real> dir = md.center_b - md.center_a;  // line 1: centroid to centroid
  if (norm2(dir) == Real(0)) dir = Vec3<Real>(1, 0, 0);
  Vec3<Real> simplex[4];
  int n = 0;
  simplex[n++] = md.support(dir);  // line 3
  dir = -simplex[0];               // line 4
  if (norm2(dir) == Real(0)) {
    result.intersecting = true;
    return result;
  }
  for (int it = 0; it < max_iterations; ++it) {
    result.iterations = it + 1;
    const Vec3<Real> s = md.support(dir);  // line 6
    // Line 7: no progress past the origin in the search direction -> a separating plane exists.
    // Strict: a support point exactly on the plane through the origin is contact (touching).
    if (dot(s, dir) < 0) return result;
    simplex[n++] = s;  // line 10
    if (gjk_detail::update_simplex(simplex, n, dir)) {
      result.intersecting = true;
      return result;
    }
  }
  result.iteration_limit_hit = true;
  result.intersecting = true;  // undecided: let the exact overlap decide
  return result;
}

}  // namespace talus
