// GJK intersection test of two posed convex polyhedra (paper §2.2, Algorithm I, Eqs. 1-3).
// The narrow-phase filter before the overlap volume: it must never call an overlapping pair
// separate. "UpdateSimplex" is done as in the distance form of GJK: the simplex is reduced to the
// smallest sub-simplex holding its point nearest the origin (Voronoi-region tests, Ericson,
// Real-Time Collision Detection §5.1), and the next search direction points from that point to
// the origin. The direction form is the one with a proven stopping rule: the loop ends when a
// support point shows a separating plane (line 7), when the origin is enclosed, or when a support
// point adds nothing (the nearest point is then within round-off of the origin: touching). The
// boolean region form cycled on near-touching pairs. A pair undecided after max_iterations is
// reported as intersecting, so the exact overlap (which detects separation itself) decides.
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

// Nearest point to the origin on segment (p, q); keeps in s the vertices it needs.
template <class Real>
TALUS_HD inline Vec3<Real> nearest_on_segment(Vec3<Real>* s, int& n) {
  const Vec3<Real> p = s[0], q = s[1], pq = q - p;
  const Real t = -dot(p, pq);
  if (t <= 0) {
    n = 1;
    return p;
  }
  const Real len2 = dot(pq, pq);
  if (t >= len2) {
    s[0] = q;
    n = 1;
    return q;
  }
  return p + pq * (t / len2);
}

// Nearest point to the origin on triangle (a, b, c) (Ericson §5.1.5, with the point at the
// origin); reduces s to the vertices of the feature that holds it.
template <class Real>
TALUS_HD inline Vec3<Real> nearest_on_triangle(Vec3<Real>* s, int& n) {
  const Vec3<Real> a = s[0], b = s[1], c = s[2];
  const Vec3<Real> ab = b - a, ac = c - a, ap = -a;
  const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) {
    n = 1;
    return a;
  }
  const Vec3<Real> bp = -b;
  const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) {
    s[0] = b;
    n = 1;
    return b;
  }
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    n = 2;
    return a + ab * (d1 / (d1 - d3));
  }
  const Vec3<Real> cp = -c;
  const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) {
    s[0] = c;
    n = 1;
    return c;
  }
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    s[1] = c;
    n = 2;
    return a + ac * (d2 / (d2 - d6));
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    s[0] = b;
    s[1] = c;
    n = 2;
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const Real denom = Real(1) / (va + vb + vc);
  n = 3;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Nearest point to the origin on tetrahedron s[0..3]: the origin itself when inside (returns
// true), else the nearest point over the faces the origin lies outside of.
template <class Real>
TALUS_HD inline bool nearest_on_tetrahedron(Vec3<Real>* s, int& n, Vec3<Real>& nearest) {
  const int faces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
  Real best = Real(-1);
  Vec3<Real> best_simplex[3];
  int best_n = 0;
  for (int f = 0; f < 4; ++f) {
    const Vec3<Real>& a = s[faces[f][0]];
    const Vec3<Real>& b = s[faces[f][1]];
    const Vec3<Real>& c = s[faces[f][2]];
    const Vec3<Real>& d = s[faces[f][3]];
    const Vec3<Real> normal = cross(b - a, c - a);
    // Origin and the fourth vertex on opposite sides of this face: the origin is outside it.
    if (dot(-a, normal) * dot(d - a, normal) >= 0) continue;
    Vec3<Real> tri[3] = {a, b, c};
    int m = 3;
    const Vec3<Real> p = nearest_on_triangle(tri, m);
    const Real dist2 = dot(p, p);
    if (best < 0 || dist2 < best) {
      best = dist2;
      nearest = p;
      best_n = m;
      for (int k = 0; k < m; ++k) best_simplex[k] = tri[k];
    }
  }
  if (best < 0) return true;  // inside every face
  n = best_n;
  for (int k = 0; k < n; ++k) s[k] = best_simplex[k];
  return false;
}

}  // namespace gjk_detail

// Algorithm I. `max_iterations` bounds the loop; each iteration adds a support point that moves
// the nearest point strictly closer, and polytopes have finitely many, so the default is ample
// for templates of up to a few hundred vertices.
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
  const Real scale = a.bounding_radius + b.bounding_radius;
  const Real tolerance = Real(64) * Eps<Real>::value * scale;  // touching within round-off

  GjkResult<Real> result;
  Vec3<Real> dir = md.center_b - md.center_a;  // line 1: centroid to centroid
  if (norm2(dir) == Real(0)) dir = Vec3<Real>(1, 0, 0);
  Vec3<Real> simplex[4];
  int n = 0;
  simplex[n++] = md.support(dir);  // line 3
  Vec3<Real> nearest = simplex[0];
  for (int it = 0; it < max_iterations; ++it) {
    result.iterations = it + 1;
    if (norm(nearest) <= tolerance) {  // the origin is on the simplex: touching
      result.intersecting = true;
      return result;
    }
    dir = -nearest;                        // line 4: towards the origin
    const Vec3<Real> s = md.support(dir);  // line 6
    // Line 7: the support plane normal to dir leaves the origin outside: separate.
    if (dot(s, dir) < 0) return result;
    // No progress: s lies no further along dir than the nearest point itself, so the nearest
    // point of the whole difference is within round-off of it, and it is at most `tolerance`
    // further from the origin than the plane through the origin: touching.
    if (dot(s - nearest, dir) <= tolerance * norm(dir)) {
      result.intersecting = true;
      return result;
    }
    simplex[n++] = s;  // line 10
    // Line 11: UpdateSimplex, reduce to the feature nearest the origin.
    if (n == 2) {
      nearest = gjk_detail::nearest_on_segment(simplex, n);
    } else if (n == 3) {
      nearest = gjk_detail::nearest_on_triangle(simplex, n);
    } else if (gjk_detail::nearest_on_tetrahedron(simplex, n, nearest)) {
      result.intersecting = true;  // line 13: the origin is enclosed
      return result;
    }
  }
  result.iteration_limit_hit = true;
  result.intersecting = true;  // undecided: let the exact overlap decide
  return result;
}

}  // namespace talus
