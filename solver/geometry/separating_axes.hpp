// The separating-axis search behind the simple contact's polyhedron-polyhedron case
// (simple_contact.hpp): the minimum over candidate axes of the projections' overlap, either over
// every face normal and edge pair, or pruned to the axes that can be facet normals of the
// Minkowski difference A - B and can still reach the depth (same result, far fewer projections).
#pragma once

#include <cmath>

#include "solver/core/math.hpp"
#include "solver/geometry/convex.hpp"

namespace talus {
namespace sat_detail {

// Interval [lo, hi] of a shape's body-frame vertices projected on a body-frame direction (all
// vertices: exact). Two independent min/max chains, since the loop is bound by their latency.
template <class Real>
TALUS_HD inline void project(const ConvexView<Real>& shape, const Vec3<Real>& dir, Real& lo,
                             Real& hi) {
  Real lo_even = dot(shape.vertices[0], dir), hi_even = lo_even;
  Real lo_odd = lo_even, hi_odd = lo_even;
  int i = 1;
  for (; i + 1 < shape.n_vertices; i += 2) {
    const Real s_even = dot(shape.vertices[i], dir), s_odd = dot(shape.vertices[i + 1], dir);
    lo_even = min_of(lo_even, s_even);
    hi_even = max_of(hi_even, s_even);
    lo_odd = min_of(lo_odd, s_odd);
    hi_odd = max_of(hi_odd, s_odd);
  }
  if (i < shape.n_vertices) {
    const Real s = dot(shape.vertices[i], dir);
    lo_even = min_of(lo_even, s);
    hi_even = max_of(hi_even, s);
  }
  lo = min_of(lo_even, lo_odd);
  hi = max_of(hi_even, hi_odd);
}

// Gauss-map arcs count as crossing within this band of their triple products (of unit vectors,
// ~16 eps round-off each), so that no crossing is lost to rounding.
template <class Real>
constexpr Real kArcTolerance = Real(64) * Eps<Real>::value;

// Radius of the largest ball about the origin inside the face planes (0 without faces).
template <class Real>
TALUS_HD inline Real least_face_offset(const ConvexView<Real>& shape) {
  Real least = shape.n_faces > 0 ? shape.face_offsets[0] : Real(0);
  for (int f = 1; f < shape.n_faces; ++f) least = min_of(least, shape.face_offsets[f]);
  return max_of(least, Real(0));
}

// The separating-axis search, all in A's body frame: B's body frame maps to it by
// x_A = offset + rel * x_B.
template <class Real>
struct SatSearch {
  const ConvexView<Real>* a;
  const ConvexView<Real>* b;
  Mat3<Real> rel;
  Vec3<Real> offset;
  Mat3<Real> rot_a;    // A's body frame -> world, for the tie-break key
  Real scale;          // r_A + r_B, m
  Real tie_tolerance;  // depths closer than this are ties (round-off of the projections)
  Real inradius_a = 0, inradius_b = 0;  // least face offsets: balls about the origins inside
  bool separated = false;
  bool found = false;
  Real depth = 0;
  Vec3<Real> normal;  // A frame, from A to B
  Real key = 0;

  // Test the unit axis L (A frame). The overlap along L is min(maxA - minB, maxB - minA); the
  // normal points from A to B: +L when B lies on A's +L side.
  TALUS_HD void test(const Vec3<Real>& axis) {
    Real lo_a, hi_a, lo_b, hi_b;
    project(*a, axis, lo_a, hi_a);
    project(*b, rel.transpose_times(axis), lo_b, hi_b);
    const Real shift = dot(offset, axis);
    lo_b += shift;
    hi_b += shift;
    const Real plus = hi_a - lo_b, minus = hi_b - lo_a;
    if (plus < Real(0) || minus < Real(0)) {
      separated = true;
      return;
    }
    const Real candidate = min_of(plus, minus);
    const Vec3<Real> n = plus <= minus ? axis : -axis;
    // Ties between different axes are broken by a key that is the same for n and -n and for the
    // swapped pair (B, A), so that normal(A, B) = -normal(B, A) holds in symmetric placements.
    const Vec3<Real> generic{Real(0.5257311121), Real(0.7236067977), Real(0.4472135955)};
    const Real candidate_key = abs_of(dot(rot_a * n, generic));
    if (!found || candidate < depth - tie_tolerance ||
        (candidate <= depth + tie_tolerance && candidate_key > key)) {
      found = true;
      depth = candidate;
      normal = n;
      key = candidate_key;
    }
  }

  // True when test(axis) would change nothing: the axis can neither separate the bodies nor
  // reach the depth found so far, by lower bounds of both overlaps. Each body holds the given
  // vertex (x_a in A's frame, x_b in B's) and the ball of its inradius about its origin, so e.g.
  // max_A >= max(L.x_a, inradius_a) and min_B <= min(L.x_b, -inradius_b). For an edge pair that
  // spans a face of the Minkowski difference the edges support the bodies along its normal, and
  // the bound on that side is the overlap itself. The margin past the tie band covers the
  // round-off of the bounds and of the projections (~10 eps scale each).
  TALUS_HD bool beyond_reach(const Vec3<Real>& axis, const Vec3<Real>& x_a,
                             const Vec3<Real>& x_b) const {
    if (!found) return false;
    const Real s_a = dot(x_a, axis), s_b = dot(x_b, rel.transpose_times(axis));
    const Real shift = dot(offset, axis);
    const Real plus_bound = max_of(s_a, inradius_a) - (min_of(s_b, -inradius_b) + shift);
    const Real minus_bound = (max_of(s_b, inradius_b) + shift) - min_of(s_a, -inradius_a);
    return min_of(plus_bound, minus_bound) > depth + Real(3) * tie_tolerance;
  }
};

// Edge pairs with sin(angle) below sqrt(eps) are skipped (see polyhedron_polyhedron_contact).
template <class Real>
TALUS_HD inline bool edge_pair_axis(const Vec3<Real>& edge_a, const Vec3<Real>& edge_b,
                                    Vec3<Real>& axis) {
  const Real min_sin2 = Eps<Real>::value;  // sin^2 of the smallest angle between edges kept
  axis = cross(edge_a, edge_b);
  const Real axis2 = norm2(axis);
  if (!(axis2 > min_sin2 * norm2(edge_a) * norm2(edge_b))) return false;
  axis = axis / std::sqrt(axis2);
  return true;
}

// A lower bound of dot(n, w) over the unit vectors n on the short great-circle arc from a to b
// (unit, not antipodal): n = alpha a + beta b with alpha, beta >= 0 and
// 1 <= alpha + beta <= 1 / cos(half the arc), so dot(n, w) >= min(a.w, b.w) times 1 or that
// factor. NaN for (nearly) antipodal a, b, which callers read as "no bound".
template <class Real>
TALUS_HD inline Real least_on_arc(const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& w) {
  const Real least = min_of(dot(a, w), dot(b, w));
  return least >= Real(0) ? least : least / std::sqrt((Real(1) + dot(a, b)) * Real(0.5));
}

// The vertex of largest projection on dir.
template <class Real>
TALUS_HD inline Vec3<Real> farthest_vertex(const ConvexView<Real>& shape, const Vec3<Real>& dir) {
  return shape.vertices[support_vertex(shape, dir)];
}

// Every candidate axis (shapes without edge_faces): the face normals of A, then of B, then
// every edge pair.
template <class Real>
TALUS_HD inline void test_all_axes(SatSearch<Real>& sat) {
  const ConvexView<Real>& shape_a = *sat.a;
  const ConvexView<Real>& shape_b = *sat.b;
  for (int f = 0; f < shape_a.n_faces && !sat.separated; ++f) sat.test(shape_a.face_normals[f]);
  for (int f = 0; f < shape_b.n_faces && !sat.separated; ++f) {
    sat.test(sat.rel * shape_b.face_normals[f]);
  }
  for (int i = 0; i < shape_a.n_edges && !sat.separated; ++i) {
    const Vec3<Real> edge_a =
        shape_a.vertices[shape_a.edges[2 * i + 1]] - shape_a.vertices[shape_a.edges[2 * i]];
    for (int j = 0; j < shape_b.n_edges && !sat.separated; ++j) {
      const Vec3<Real> edge_b = sat.rel * (shape_b.vertices[shape_b.edges[2 * j + 1]] -
                                           shape_b.vertices[shape_b.edges[2 * j]]);
      Vec3<Real> axis;
      if (edge_pair_axis(edge_a, edge_b, axis)) sat.test(axis);
    }
  }
}

// Points of each body near the other, for lower bounds of the overlap h(n) = max_A n.x -
// min_B n.x along a facet normal n of A - B: h(n) >= n.(p - q) for any p in A and q in B. The
// centroids (origins) with the inradius balls about them, and each body's vertex nearest the
// other's centroid, are such points; the caller supplies the supporting vertex or face of the
// facet's own body, which makes the bound tight on that side.
template <class Real>
struct NearPoints {
  Vec3<Real> center_b_in_a, near_b_in_a;  // B's centroid and its vertex nearest A, A frame
  Vec3<Real> center_a_in_b, near_a_in_b;  // the same for A, B frame
  Real margin;  // round-off of the bounds, of the projections and of arcs accepted in tolerance

  TALUS_HD explicit NearPoints(const SatSearch<Real>& sat) {
    center_b_in_a = sat.offset;
    center_a_in_b = -sat.rel.transpose_times(sat.offset);
    near_b_in_a = sat.offset + sat.rel * farthest_vertex(*sat.b, center_a_in_b);
    near_a_in_b = sat.rel.transpose_times(farthest_vertex(*sat.a, center_b_in_a) - sat.offset);
    margin = Real(3) * sat.tie_tolerance + Real(4) * kArcTolerance<Real> * sat.scale;
  }

  // Bound of h along A's face normal n (A frame) with face offset h_a (A's support there).
  TALUS_HD Real face_a(const SatSearch<Real>& sat, const Vec3<Real>& n, Real h_a) const {
    return h_a - min_of(dot(n, near_b_in_a), dot(n, center_b_in_a) - sat.inradius_b);
  }
  // Bound of h along minus B's face normal m (B frame) with face offset h_b.
  TALUS_HD Real face_b(const SatSearch<Real>& sat, const Vec3<Real>& m, Real h_b) const {
    return h_b - min_of(dot(m, near_a_in_b), dot(m, center_a_in_b) - sat.inradius_a);
  }
  // Bound of h over the facet normals on A's edge arc (normals n0, n1, vertex p; A frame).
  TALUS_HD Real edge_a(const SatSearch<Real>& sat, const Vec3<Real>& n0, const Vec3<Real>& n1,
                       const Vec3<Real>& p) const {
    return max_of(least_on_arc(n0, n1, p - center_b_in_a) + sat.inradius_b,
                  least_on_arc(n0, n1, p - near_b_in_a));
  }
  // The same for B's edge (B frame); the facet normals are minus its arc, rotated.
  TALUS_HD Real edge_b(const SatSearch<Real>& sat, const Vec3<Real>& m0, const Vec3<Real>& m1,
                       const Vec3<Real>& p) const {
    return max_of(least_on_arc(m0, m1, p - center_a_in_b) + sat.inradius_a,
                  least_on_arc(m0, m1, p - near_a_in_b));
  }
};

// The face axes first, the most promising by its bound (NearPoints) first of all, so that a
// depth is found early; then the others, in order, except those whose facet bound exceeds the
// depth found (a face axis n is a facet normal of A - B; only its facet side is bounded, since
// the other side's overlap h(-n) reaches the final depth only if -n is itself a minimising facet
// normal, tested on its own, up to ties within round-off).
template <class Real>
TALUS_HD inline void test_face_axes(SatSearch<Real>& sat, const NearPoints<Real>& near) {
  const ConvexView<Real>& shape_a = *sat.a;
  const ConvexView<Real>& shape_b = *sat.b;
  const int n_faces = shape_a.n_faces + shape_b.n_faces;
  int first = -1;  // face index, B's after A's
  Real first_bound = 0;
  for (int f = 0; f < n_faces; ++f) {
    const Real bound = f < shape_a.n_faces
                           ? near.face_a(sat, shape_a.face_normals[f], shape_a.face_offsets[f])
                           : near.face_b(sat, shape_b.face_normals[f - shape_a.n_faces],
                                         shape_b.face_offsets[f - shape_a.n_faces]);
    if (first < 0 || bound < first_bound) {
      first = f;
      first_bound = bound;
    }
  }
  if (first < 0) return;
  for (int k = -1; k < n_faces && !sat.separated; ++k) {
    const int f = k < 0 ? first : k;
    if (k >= 0 && f == first) continue;
    if (f < shape_a.n_faces) {
      const Vec3<Real>& n = shape_a.face_normals[f];
      if (k >= 0 && near.face_a(sat, n, shape_a.face_offsets[f]) > sat.depth + near.margin)
        continue;
      sat.test(n);
    } else {
      const Vec3<Real>& m = shape_b.face_normals[f - shape_a.n_faces];
      if (k >= 0 &&
          near.face_b(sat, m, shape_b.face_offsets[f - shape_a.n_faces]) > sat.depth + near.margin)
        continue;
      sat.test(sat.rel * m);
    }
  }
}

// The axes of the edge pairs that span a face of the Minkowski difference A - B (Gregorius, "The
// Separating Axis Test between Convex Polyhedra", GDC 2013): the Gauss-map arc of A's edge,
// between its faces' normals a and b, must cross the arc of -B's edge, between -c and -d (c, d:
// the normals of B's edge's faces). The other pairs' axes are no face normal of A - B, so they
// can neither give a smaller depth (the depth is the least support value h of A - B over its
// facet normals, and h on any other direction exceeds it) nor be the only separating axis (the
// facet planes bound A - B). The crossing test runs in B's frame (B's normals are read as
// stored) and accepts the round-off band around zero (triple products of unit vectors, ~16 eps
// each), so that no facet is lost to rounding: an extra axis never changes the minimum.
// Edges whose facets all lie beyond the depth found are dropped first (NearPoints: an edge's
// vertex supports its body along each of its facet normals; facet side only, as for the faces),
// and a surviving pair is projected only if beyond_reach does not rule its axis out.
template <class Real>
TALUS_HD inline void test_minkowski_edge_pairs(SatSearch<Real>& sat, const NearPoints<Real>& near) {
  const ConvexView<Real>& shape_a = *sat.a;
  const ConvexView<Real>& shape_b = *sat.b;
  const Real arc_tolerance = kArcTolerance<Real>;
  // B's edges that may still reach the depth, listed (for up to kListed edges; beyond, all).
  constexpr int kListed = 64;
  int listed_b[kListed];
  int n_listed_b = 0;
  const bool list_b = sat.found && shape_b.n_edges <= kListed;
  if (list_b) {
    for (int j = 0; j < shape_b.n_edges; ++j) {
      const Real bound = near.edge_b(sat, shape_b.face_normals[shape_b.edge_faces[2 * j]],
                                     shape_b.face_normals[shape_b.edge_faces[2 * j + 1]],
                                     shape_b.vertices[shape_b.edges[2 * j]]);
      if (!(bound > sat.depth + near.margin)) listed_b[n_listed_b++] = j;
    }
  }
  const int n_b = list_b ? n_listed_b : shape_b.n_edges;

  for (int i = 0; i < shape_a.n_edges; ++i) {
    const Vec3<Real>& face_a = shape_a.face_normals[shape_a.edge_faces[2 * i]];
    const Vec3<Real>& face_b = shape_a.face_normals[shape_a.edge_faces[2 * i + 1]];
    const Vec3<Real>& vertex_a = shape_a.vertices[shape_a.edges[2 * i]];
    if (sat.found && near.edge_a(sat, face_a, face_b, vertex_a) > sat.depth + near.margin) continue;
    const Vec3<Real> a = sat.rel.transpose_times(face_a), b = sat.rel.transpose_times(face_b);
    const Vec3<Real> b_x_a = cross(b, a);  // B frame
    const Vec3<Real> edge_a = shape_a.vertices[shape_a.edges[2 * i + 1]] - vertex_a;
    for (int k = 0; k < n_b; ++k) {
      const int j = list_b ? listed_b[k] : k;
      const Vec3<Real> c = -shape_b.face_normals[shape_b.edge_faces[2 * j]];
      const Vec3<Real> d = -shape_b.face_normals[shape_b.edge_faces[2 * j + 1]];
      // -c and -d on opposite sides of the great circle through a and b, ...
      const Real cba = dot(c, b_x_a), dba = dot(d, b_x_a);
      if (!(cba * dba < arc_tolerance)) continue;
      // ... a and b on opposite sides of the one through -c and -d, ...
      const Vec3<Real> d_x_c = cross(d, c);
      const Real adc = dot(a, d_x_c), bdc = dot(b, d_x_c);
      if (!(adc * bdc < arc_tolerance)) continue;
      // ... and the crossing in the same hemisphere for both arcs (not the antipodal one).
      if (!(cba * bdc > -arc_tolerance)) continue;

      const Vec3<Real>& vertex_b = shape_b.vertices[shape_b.edges[2 * j]];
      const Vec3<Real> edge_b = sat.rel * (shape_b.vertices[shape_b.edges[2 * j + 1]] - vertex_b);
      Vec3<Real> axis;
      if (!edge_pair_axis(edge_a, edge_b, axis) || sat.beyond_reach(axis, vertex_a, vertex_b))
        continue;
      sat.test(axis);
      if (sat.separated) return;
    }
  }
}

// The pruned search (both shapes with edge_faces): the same minimum over fewer axes.
template <class Real>
TALUS_HD inline void test_pruned_axes(SatSearch<Real>& sat) {
  sat.inradius_a = least_face_offset(*sat.a);
  sat.inradius_b = least_face_offset(*sat.b);
  const NearPoints<Real> near(sat);
  test_face_axes(sat, near);
  if (!sat.separated) test_minkowski_edge_pairs(sat, near);
}

}  // namespace sat_detail
}  // namespace talus
