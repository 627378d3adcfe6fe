// The simple contact of BLAZE-DEM (§2.3, §3.1): one contact point, a penetration depth δ and a
// unit normal per touching pair, for the linear-spring model F_N = K_N δ n (BLAZE-DEM Eqs. 2–4).
// Sphere–sphere, sphere–polyhedron (exact closest point) and polyhedron–polyhedron (separating
// axis test: exact minimum translation distance of two convex polyhedra).
#pragma once

#include <cmath>

#include "solver/core/math.hpp"
#include "solver/geometry/convex.hpp"
#include "solver/geometry/separating_axes.hpp"

namespace talus {

template <class Real>
struct SimpleContact {
  bool touching = false;  // the bodies share a point (depth >= 0); false also for non-finite input
  Real depth = 0;         // m, >= 0; 0 when not touching
  Vec3<Real> normal{Real(0), Real(0), Real(1)};  // unit, from the first body to the second
  Vec3<Real> point;                              // world; between the bodies when not touching
};

namespace simple_detail {

template <class Real>
TALUS_HD inline Real clamp01(Real x) {
  return min_of(max_of(x, Real(0)), Real(1));
}

// Result for bodies that do not touch: the normal along the centre line (+z when the centres
// coincide), the point midway between the centres.
template <class Real>
TALUS_HD inline SimpleContact<Real> apart(const Vec3<Real>& center_a, const Vec3<Real>& center_b,
                                          Real length_scale) {
  SimpleContact<Real> r;
  if (!is_finite(center_a) || !is_finite(center_b)) return r;
  const Vec3<Real> d = center_b - center_a;
  const Real dist = norm(d);
  if (dist > Eps<Real>::value * length_scale) r.normal = d / dist;
  r.point = center_a + d * Real(0.5);
  return r;
}

// Closest points of segments [p1, q1] and [p2, q2] (Ericson, Real-Time Collision Detection
// §5.1.9), with the divisions guarded for zero-length and parallel segments.
template <class Real>
TALUS_HD inline void closest_points_of_segments(const Vec3<Real>& p1, const Vec3<Real>& q1,
                                                const Vec3<Real>& p2, const Vec3<Real>& q2,
                                                Vec3<Real>& c1, Vec3<Real>& c2) {
  const Vec3<Real> d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const Real a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  Real s = 0, t = 0;
  if (a > Real(0) && e > Real(0)) {
    const Real b = dot(d1, d2), c = dot(d1, r);
    const Real denom = a * e - b * b;  // >= 0; 0 for parallel segments
    s = denom > Real(0) ? clamp01((b * f - c * e) / denom) : Real(0);
    t = (b * s + f) / e;
    if (t < Real(0)) {
      t = 0;
      s = clamp01(-c / a);
    } else if (t > Real(1)) {
      t = 1;
      s = clamp01((b - c) / a);
    }
  } else if (a > Real(0)) {
    s = clamp01(-dot(d1, r) / a);
  } else if (e > Real(0)) {
    t = clamp01(f / e);
  }
  c1 = p1 + d1 * s;
  c2 = p2 + d2 * t;
}

}  // namespace simple_detail

// (a) Sphere–sphere. The point is the middle of the overlap along the centre line, halfway between
// the deepest points c_a + n r_a and c_b - n r_b.
template <class Real>
TALUS_HD inline SimpleContact<Real> sphere_sphere_contact(const Vec3<Real>& center_a, Real radius_a,
                                                          const Vec3<Real>& center_b,
                                                          Real radius_b) {
  SimpleContact<Real> r =
      simple_detail::apart(center_a, center_b, abs_of(radius_a) + abs_of(radius_b));
  if (!is_finite(center_a) || !is_finite(center_b) || !is_finite(radius_a) || !is_finite(radius_b))
    return r;
  const Real depth = radius_a + radius_b - norm(center_b - center_a);
  r.point = ((center_a + r.normal * radius_a) + (center_b - r.normal * radius_b)) * Real(0.5);
  r.touching = depth >= Real(0);
  r.depth = r.touching ? depth : Real(0);
  return r;
}

// Closest point of triangle (a, b, c) to p (Ericson §5.1.5, Voronoi regions), with the divisions
// guarded so that a zero-area triangle gives a finite point.
template <class Real>
TALUS_HD inline Vec3<Real> closest_point_on_triangle(const Vec3<Real>& p, const Vec3<Real>& a,
                                                     const Vec3<Real>& b, const Vec3<Real>& c) {
  const Vec3<Real> ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= Real(0) && d2 <= Real(0)) return a;
  const Vec3<Real> bp = p - b;
  const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= Real(0) && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= Real(0) && d1 >= Real(0) && d3 <= Real(0)) {
    return d1 - d3 > Real(0) ? a + ab * (d1 / (d1 - d3)) : a;
  }
  const Vec3<Real> cp = p - c;
  const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= Real(0) && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= Real(0) && d2 >= Real(0) && d6 <= Real(0)) {
    return d2 - d6 > Real(0) ? a + ac * (d2 / (d2 - d6)) : a;
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= Real(0) && d4 - d3 >= Real(0) && d5 - d6 >= Real(0)) {
    const Real sum = (d4 - d3) + (d5 - d6);
    return sum > Real(0) ? b + (c - b) * ((d4 - d3) / sum) : b;
  }
  const Real sum = va + vb + vc;  // (twice the area)^2 > 0 in the face region
  if (!(sum > Real(0))) return a;
  return a + ab * (vb / sum) + ac * (vc / sum);
}

// (b) Sphere (first) against a posed convex polyhedron (second). Centre outside: the exact closest
// point q on the polyhedron's triangles, depth = r - |c - q|. Centre inside: the nearest face
// plane, depth = r + (distance to it); its foot lies on that face (for any other face g,
// n_g . q - h_g <= s_g - s_f <= 0). The point is halfway between q and the sphere's deepest point.
template <class Real>
TALUS_HD inline SimpleContact<Real> sphere_polyhedron_contact(const Vec3<Real>& center, Real radius,
                                                              const ConvexView<Real>& shape,
                                                              const Pose<Real>& pose) {
  const Real scale = abs_of(radius) + shape.bounding_radius;
  SimpleContact<Real> r = simple_detail::apart(center, pose.position, scale);
  if (!is_finite(center) || !is_finite(radius) || !is_finite(pose.orientation) ||
      shape.n_faces <= 0 || shape.n_triangles <= 0 || norm(pose.position - center) > scale) {
    return r;
  }
  const Mat3<Real> rot = rotation_matrix(pose.orientation);
  const Vec3<Real> c_body = rot.transpose_times(center - pose.position);

  // Largest signed distance to a face plane: > 0 outside.
  int nearest_face = 0;
  Real face_distance = dot(shape.face_normals[0], c_body) - shape.face_offsets[0];
  for (int f = 1; f < shape.n_faces; ++f) {
    const Real s = dot(shape.face_normals[f], c_body) - shape.face_offsets[f];
    if (s > face_distance) {
      face_distance = s;
      nearest_face = f;
    }
  }
  Vec3<Real> surface_point, normal_body;  // normal from the sphere into the polyhedron
  Real depth;
  const Real round_off = Real(16) * Eps<Real>::value * scale;
  if (face_distance > Real(0)) {
    Real best2 = -1;
    for (int t = 0; t < shape.n_triangles; ++t) {
      const Vec3<Real> q = closest_point_on_triangle(c_body, shape.vertices[shape.triangles[3 * t]],
                                                     shape.vertices[shape.triangles[3 * t + 1]],
                                                     shape.vertices[shape.triangles[3 * t + 2]]);
      const Real d2 = norm2(q - c_body);
      if (best2 < Real(0) || d2 < best2) {
        best2 = d2;
        surface_point = q;
      }
    }
    const Real dist = std::sqrt(best2);
    // A centre on the surface has no direction to q: the nearest face's normal serves.
    normal_body =
        dist > round_off ? (surface_point - c_body) / dist : -shape.face_normals[nearest_face];
    depth = radius - dist;
  } else {
    normal_body = -shape.face_normals[nearest_face];
    surface_point = c_body - shape.face_normals[nearest_face] * face_distance;
    depth = radius - face_distance;
  }
  const Vec3<Real> deepest = c_body + normal_body * radius;
  const Vec3<Real> point_body = (surface_point + deepest) * Real(0.5);
  if (!is_finite(depth) || !is_finite(point_body)) return r;
  r.normal = rot * normal_body;
  r.point = pose.position + rot * point_body;
  r.touching = depth >= Real(0);
  r.depth = r.touching ? depth : Real(0);
  return r;
}

// (b') The same contact seen from the polyhedron: the normal flips.
template <class Real>
TALUS_HD inline SimpleContact<Real> polyhedron_sphere_contact(const ConvexView<Real>& shape,
                                                              const Pose<Real>& pose,
                                                              const Vec3<Real>& center,
                                                              Real radius) {
  SimpleContact<Real> r = sphere_polyhedron_contact(center, radius, shape, pose);
  r.normal = -r.normal;
  return r;
}

// Vertices within this fraction of (r_A + r_B) of a support plane count as one supporting
// feature (vertex, edge or face) for the contact point.
constexpr double kFeatureTolerance = 1e-4;

// (c) Two posed convex polyhedra by the separating axis test. Candidate axes: the face normals of
// both bodies and the cross products of the edge pairs (all of them, or with edge_faces only those
// that span a face of the Minkowski difference, see below); for convex polyhedra the minimum
// overlap over these axes is the exact penetration depth (minimum translation distance): the
// Minkowski difference's faces have exactly these normals. Each axis is projected on all vertices
// of both bodies, rotated once into B's frame. With both shapes' edge_faces (ShapeArrays,
// DeviceShape) the search also skips the axes whose overlap provably cannot change the result,
// by cheap lower bounds (separating_axes.hpp); without, every axis is projected. Edge pairs with
// sin(angle) < sqrt(eps) are skipped: exactly parallel pairs add no face to the Minkowski
// difference, and for nearly parallel ones the sliver face they add is O(sin(angle) x edge length)
// away from its neighbours, which is the error of skipping it, balanced against the round-off of
// normalising their cross product.
//
// Contact point, taken on the mid-plane between the two support planes along the normal:
//  - the mean of the supporting-feature vertices of each body that lie inside the other body
//    (vertex-face: the vertex; face-face: the corners of the common patch, e.g. the patch centre
//    for two offset equal squares and the small face's centre for a small face on a large one);
//  - else, when both features are edges, the midpoint of the edges' closest points;
//  - else, the mean of the two features' vertex centroids.
template <class Real>
TALUS_HD inline SimpleContact<Real> polyhedron_polyhedron_contact(const ConvexView<Real>& shape_a,
                                                                  const Pose<Real>& pose_a,
                                                                  const ConvexView<Real>& shape_b,
                                                                  const Pose<Real>& pose_b) {
  const Real scale = shape_a.bounding_radius + shape_b.bounding_radius;
  SimpleContact<Real> r = simple_detail::apart(pose_a.position, pose_b.position, scale);
  if (!is_finite(pose_a.position) || !is_finite(pose_b.position) ||
      !is_finite(pose_a.orientation) || !is_finite(pose_b.orientation) || shape_a.n_vertices <= 0 ||
      shape_b.n_vertices <= 0 || norm(pose_b.position - pose_a.position) > scale) {
    return r;
  }
  sat_detail::SatSearch<Real> sat;
  sat.a = &shape_a;
  sat.b = &shape_b;
  sat.rot_a = rotation_matrix(pose_a.orientation);
  sat.rel = rotation_matrix(pose_a.orientation.conjugate() * pose_b.orientation);
  sat.offset = sat.rot_a.transpose_times(pose_b.position - pose_a.position);
  sat.scale = scale;
  sat.tie_tolerance = Real(16) * Eps<Real>::value * scale;

  if (shape_a.edge_faces != nullptr && shape_b.edge_faces != nullptr) {
    sat_detail::test_pruned_axes(sat);
  } else {
    sat_detail::test_all_axes(sat);
  }
  if (sat.separated || !sat.found || !is_finite(sat.depth)) return r;

  // Supporting features along n (A frame) and the contact point.
  const Vec3<Real> n = sat.normal;
  Real lo_a, hi_a, lo_b, hi_b;
  sat_detail::project(shape_a, n, lo_a, hi_a);
  sat_detail::project(shape_b, sat.rel.transpose_times(n), lo_b, hi_b);
  lo_b += dot(sat.offset, n);
  const Real feature_tolerance = Real(kFeatureTolerance) * scale;
  Vec3<Real> sum_a, sum_b, sum_inside, edge_a[2], edge_b[2];
  int count_a = 0, count_b = 0, count_inside = 0;
  for (int i = 0; i < shape_a.n_vertices; ++i) {
    const Vec3<Real>& x = shape_a.vertices[i];
    if (dot(x, n) < hi_a - feature_tolerance) continue;
    if (count_a < 2) edge_a[count_a] = x;
    sum_a += x;
    ++count_a;
    const Vec3<Real> x_b = sat.rel.transpose_times(x - sat.offset);
    bool inside = true;
    for (int g = 0; g < shape_b.n_faces && inside; ++g) {
      inside = dot(shape_b.face_normals[g], x_b) - shape_b.face_offsets[g] <= feature_tolerance;
    }
    if (inside) {
      sum_inside += x;
      ++count_inside;
    }
  }
  for (int i = 0; i < shape_b.n_vertices; ++i) {
    const Vec3<Real> x = sat.offset + sat.rel * shape_b.vertices[i];
    if (dot(x, n) > lo_b + feature_tolerance) continue;
    if (count_b < 2) edge_b[count_b] = x;
    sum_b += x;
    ++count_b;
    bool inside = true;
    for (int f = 0; f < shape_a.n_faces && inside; ++f) {
      inside = dot(shape_a.face_normals[f], x) - shape_a.face_offsets[f] <= feature_tolerance;
    }
    if (inside) {
      sum_inside += x;
      ++count_inside;
    }
  }
  Vec3<Real> point;
  if (count_inside > 0) {
    point = sum_inside / Real(count_inside);
  } else if (count_a == 2 && count_b == 2) {
    Vec3<Real> on_a, on_b;
    simple_detail::closest_points_of_segments(edge_a[0], edge_a[1], edge_b[0], edge_b[1], on_a,
                                              on_b);
    point = (on_a + on_b) * Real(0.5);
  } else {
    point = (sum_a / Real(max_of(count_a, 1)) + sum_b / Real(max_of(count_b, 1))) * Real(0.5);
  }
  point += n * (Real(0.5) * (hi_a + lo_b) - dot(point, n));  // onto the mid-plane
  if (!is_finite(point)) return r;

  r.touching = true;
  r.depth = max_of(sat.depth, Real(0));
  r.normal = sat.rot_a * n;
  r.point = pose_a.position + sat.rot_a * point;
  return r;
}

}  // namespace talus
