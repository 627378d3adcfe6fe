// Particle against one wall triangle (paper §2.4): the particle's cross-section with the
// triangle's plane, clipped to the triangle by Sutherland–Hodgman (Algorithm VII, Eqs. 10–11), for
// the area-weighted wall force; plus the penetration depth and the exact volume below the plane.
#pragma once

#include <cmath>

#include "solver/core/math.hpp"
#include "solver/geometry/convex.hpp"

namespace talus {

enum class WallContactStatus : int {
  none = 0,         // the particle does not reach the plane, or its section misses the triangle
  touching = 1,     // the section meets the triangle, but no vertex is below the plane (depth 0 up
                    // to round-off) or the common part has zero area
  overlapping = 2,  // a vertex is below the plane and the clipped section has positive area
  degenerate = 3,   // zero-area triangle, non-finite input, empty shape or a capacity overrun;
                    // every number of the result is zero
};

TALUS_HD inline const char* to_string(WallContactStatus s) {
  switch (s) {
    case WallContactStatus::none:
      return "none";
    case WallContactStatus::touching:
      return "touching";
    case WallContactStatus::overlapping:
      return "overlapping";
    default:
      return "degenerate";
  }
}

// Section points held per call. A plane section of a convex polyhedron has at most one point per
// face, so 128 covers the 80-facet cylinder; a caller with larger shapes raises it.
constexpr int kWallSectionCapacity = 128;

template <class Real>
struct WallContact {
  WallContactStatus status = WallContactStatus::none;
  Vec3<Real> normal;      // the triangle's unit normal, pointing to the side where particles live
  Real overlap_area = 0;  // m^2: the section clipped to the triangle
  Vec3<Real> overlap_centroid;  // world; the mean of the clipped points when its area is zero
  Real section_area = 0;        // m^2: the whole section of the particle by the plane
  // Plane quantities, filled whenever the particle reaches the plane, even where its section
  // misses this triangle: weight them with area_fraction() (§2.4 area-weighted force).
  Real depth = 0;         // m, >= 0: max over vertices of -dot(normal, x - a)
  Real volume_below = 0;  // m^3: the part of the particle with dot(normal, x - a) <= 0
  // World, in the plane: the centroid of volume_below less the area centroid of the section (both
  // projected onto the plane). A tilted face resting on the plane has its volume below deeper on
  // one side: this shift is what makes the volume laws' wall contact point restore the tilt.
  Vec3<Real> volume_offset;
  int section_points = 0;  // points of the (unclipped) section polygon
  bool overrun = false;    // the section had more points than the capacity: status degenerate

  // The share of the particle's section that lies on this triangle (0 when there is no section).
  TALUS_HD Real area_fraction() const {
    return section_area > Real(0) ? min_of(overlap_area / section_area, Real(1)) : Real(0);
  }
};

namespace wall_detail {

// Shoelace area and area centroid of a closed 2-D polygon (x[i], y[i]). Coordinates are taken
// relative to the first point so that a far-away origin costs no precision.
template <class Real>
TALUS_HD inline Real polygon_area_centroid(const Real* x, const Real* y, int count, Real& cx,
                                           Real& cy) {
  Real twice_area = 0, sx = 0, sy = 0, mean_x = 0, mean_y = 0;
  for (int k = 0; k < count; ++k) {
    const int next = (k + 1 == count) ? 0 : k + 1;
    const Real x0 = x[k] - x[0], y0 = y[k] - y[0];
    const Real x1 = x[next] - x[0], y1 = y[next] - y[0];
    const Real w = x0 * y1 - x1 * y0;
    twice_area += w;
    sx += (x0 + x1) * w;
    sy += (y0 + y1) * w;
    mean_x += x0;
    mean_y += y0;
  }
  if (count > 0 && abs_of(twice_area) > Real(0)) {
    cx = x[0] + sx / (Real(3) * twice_area);
    cy = y[0] + sy / (Real(3) * twice_area);
  } else if (count > 0) {
    cx = x[0] + mean_x / Real(count);
    cy = y[0] + mean_y / Real(count);
  } else {
    cx = cy = Real(0);
  }
  return Real(0.5) * twice_area;
}

// A number in [0, 4) that increases with the angle of (dx, dy) from +x, as atan2 does, without
// its cost ("diamond angle"); 0 for the zero vector.
template <class Real>
TALUS_HD inline Real pseudo_angle(Real dx, Real dy) {
  const Real l1 = abs_of(dx) + abs_of(dy);
  if (!(l1 > Real(0))) return Real(0);
  const Real p = dx / l1;
  return dy >= Real(0) ? Real(1) - p : Real(3) + p;
}

// One Sutherland–Hodgman pass (Algorithm VII, lines 4–21): keep the part of the polygon (in_x,
// in_y) on the left of the directed line v0 -> v1. Our triangle is counter-clockwise in the plane
// basis, so "left is inside" is the paper's "right is inside" for its clockwise clip polygon.
// Returns the output count, or -1 when the output would exceed `capacity`.
template <class Real>
TALUS_HD inline int clip_polygon_by_edge(const Real* in_x, const Real* in_y, int in_count, Real v0x,
                                         Real v0y, Real v1x, Real v1y, Real* out_x, Real* out_y,
                                         int capacity) {
  const Real edge_x = v1x - v0x, edge_y = v1y - v0y;
  int out_count = 0;
  if (in_count == 0) return 0;
  // side = cross2D(edgeDir, v - v0) >= 0: inside.
  Real prev_x = in_x[in_count - 1], prev_y = in_y[in_count - 1];
  Real prev_side = edge_x * (prev_y - v0y) - edge_y * (prev_x - v0x);
  for (int k = 0; k < in_count; ++k) {
    const Real cur_x = in_x[k], cur_y = in_y[k];
    const Real cur_side = edge_x * (cur_y - v0y) - edge_y * (cur_x - v0x);
    const bool cur_in = cur_side >= Real(0), prev_in = prev_side >= Real(0);
    if (cur_in != prev_in) {
      // Eqs. 10–11: I = v2 + (v3 - v2) t with t = cross2D(e, v0 - v2) / cross2D(e, v3 - v2),
      // written with the side values already at hand; the sides differ in sign, so the
      // denominator is not zero.
      Real t = prev_side / (prev_side - cur_side);
      t = min_of(max_of(t, Real(0)), Real(1));
      if (out_count >= capacity) return -1;
      out_x[out_count] = prev_x + (cur_x - prev_x) * t;
      out_y[out_count] = prev_y + (cur_y - prev_y) * t;
      ++out_count;
    }
    if (cur_in) {
      if (out_count >= capacity) return -1;
      out_x[out_count] = cur_x;
      out_y[out_count] = cur_y;
      ++out_count;
    }
    prev_x = cur_x;
    prev_y = cur_y;
    prev_side = cur_side;
  }
  return out_count;
}

}  // namespace wall_detail

// Clip a posed convex particle against the wall triangle (a, b, c). The triangle's normal
// n = unit((b - a) x (c - a)) points to the side where particles live; "below" means
// dot(n, x - a) < 0. SectionCapacity bounds the section polygon (see kWallSectionCapacity).
template <class Real, int SectionCapacity = kWallSectionCapacity>
TALUS_HD inline WallContact<Real> clip_against_triangle(const ConvexView<Real>& shape,
                                                        const Pose<Real>& pose, const Vec3<Real>& a,
                                                        const Vec3<Real>& b, const Vec3<Real>& c) {
  WallContact<Real> result;
  WallContact<Real> degenerate;
  degenerate.status = WallContactStatus::degenerate;
  const Quat<Real>& q = pose.orientation;
  if (shape.n_vertices <= 0 || shape.n_edges <= 0 || shape.n_triangles <= 0 ||
      !is_finite(pose.position) || !is_finite(a) || !is_finite(b) || !is_finite(c) ||
      !is_finite(q.w + q.x + q.y + q.z)) {
    return degenerate;
  }

  // Triangle frame. A triangle whose area is at round-off level of its edges has no normal.
  const Vec3<Real> edge_ab = b - a, edge_ac = c - a;
  const Vec3<Real> area_vector = cross(edge_ab, edge_ac);
  const Real twice_triangle_area = norm(area_vector);
  const Real longest2 = max_of(max_of(norm2(edge_ab), norm2(edge_ac)), norm2(c - b));
  if (!(twice_triangle_area > Real(64) * Eps<Real>::value * longest2)) return degenerate;
  const Vec3<Real> n = area_vector / twice_triangle_area;
  const Vec3<Real> u = edge_ab / norm(edge_ab);  // in-plane basis (u, v, n), right-handed
  const Vec3<Real> v = cross(n, u);
  result.normal = n;

  // Work in the body frame: a vertex's signed distance is d_center + dot(n_body, vertex) and its
  // in-plane coordinates about o (the centre projected onto the plane) are dot(u_body, vertex),
  // dot(v_body, vertex). Coordinates stay of the particle's size wherever the wall is.
  const Mat3<Real> rot = rotation_matrix(q);
  const Vec3<Real> center_rel = pose.position - a;
  const Real d_center = dot(n, center_rel);
  const Vec3<Real> n_body = rot.transpose_times(n);
  const Vec3<Real> u_body = rot.transpose_times(u);
  const Vec3<Real> v_body = rot.transpose_times(v);
  const Real radius = shape.bounding_radius;
  // Distances within on_tolerance of zero count as "on the plane" for the section (round-off of
  // d_center + dot(n_body, vertex)).
  const Real on_tolerance = Real(32) * Eps<Real>::value * (radius + abs_of(d_center));
  if (d_center > radius + on_tolerance) return result;  // bounding sphere above the plane

  Real min_distance = d_center + dot(n_body, shape.vertices[0]);
  for (int i = 1; i < shape.n_vertices; ++i) {
    min_distance = min_of(min_distance, d_center + dot(n_body, shape.vertices[i]));
  }
  if (!is_finite(min_distance)) return degenerate;
  if (min_distance > on_tolerance) return result;  // the particle does not reach the plane
  result.depth = max_of(-min_distance, Real(0));

  // Volume below the plane. Each surface triangle is clipped to the half-space d <= 0 and
  // contributes the signed cone from an apex ON the plane (divergence theorem). The cut face (the
  // section, lying in the plane) would contribute a cone of zero height from that apex, so the
  // closed surface of the part below needs no explicit cap, and the sum is exact up to round-off.
  const Vec3<Real> apex = n_body * (-d_center);  // o in the body frame
  Real six_volume = 0;
  Vec3<Real> moment24;  // 24 times the first moment about the apex
  for (int t = 0; t < shape.n_triangles; ++t) {
    Vec3<Real> corner[3];
    Real dist[3];
    for (int k = 0; k < 3; ++k) {
      corner[k] = shape.vertices[shape.triangles[3 * t + k]] - apex;
      dist[k] = d_center + dot(n_body, shape.vertices[shape.triangles[3 * t + k]]);
    }
    Vec3<Real> clipped[4];  // a triangle cut by a plane keeps at most 4 corners
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const int next = (k + 1) % 3;
      const bool in_k = dist[k] <= Real(0), in_next = dist[next] <= Real(0);
      if (in_k) clipped[count++] = corner[k];
      if (in_k != in_next) {
        const Real s = dist[k] / (dist[k] - dist[next]);  // signs differ: nonzero denominator
        clipped[count++] = corner[k] + (corner[next] - corner[k]) * s;
      }
    }
    for (int k = 1; k + 1 < count; ++k) {
      const Real cone = triple(clipped[0], clipped[k], clipped[k + 1]);
      six_volume += cone;
      moment24 += (clipped[0] + clipped[k] + clipped[k + 1]) * cone;  // centroid (0 + ...) / 4
    }
  }
  result.volume_below = max_of(six_volume / Real(6), Real(0));

  // Section polygon: vertices on the plane, and the crossing points of edges whose ends lie
  // strictly on opposite sides (an edge touching the plane at an end is represented by that end).
  Real px[SectionCapacity + 3], py[SectionCapacity + 3];
  Real angle[SectionCapacity];
  int count = 0;
  for (int i = 0; i < shape.n_vertices; ++i) {
    const Vec3<Real>& p = shape.vertices[i];
    if (abs_of(d_center + dot(n_body, p)) > on_tolerance) continue;
    if (count >= SectionCapacity) {
      WallContact<Real> r = degenerate;
      r.overrun = true;
      return r;
    }
    px[count] = dot(u_body, p);
    py[count] = dot(v_body, p);
    ++count;
  }
  for (int e = 0; e < shape.n_edges; ++e) {
    const Vec3<Real>& p0 = shape.vertices[shape.edges[2 * e]];
    const Vec3<Real>& p1 = shape.vertices[shape.edges[2 * e + 1]];
    const Real d0 = d_center + dot(n_body, p0), d1 = d_center + dot(n_body, p1);
    const bool crosses =
        (d0 < -on_tolerance && d1 > on_tolerance) || (d0 > on_tolerance && d1 < -on_tolerance);
    if (!crosses) continue;
    if (count >= SectionCapacity) {
      WallContact<Real> r = degenerate;
      r.overrun = true;
      return r;
    }
    const Vec3<Real> p = p0 + (p1 - p0) * (d0 / (d0 - d1));
    px[count] = dot(u_body, p);
    py[count] = dot(v_body, p);
    ++count;
  }
  result.section_points = count;
  if (count == 0) return result;  // the particle lies wholly below the plane: no section

  // Order the section by angle about its mean (the points are in convex position): insertion sort.
  Real mean_x = 0, mean_y = 0;
  for (int k = 0; k < count; ++k) {
    mean_x += px[k];
    mean_y += py[k];
  }
  mean_x /= Real(count);
  mean_y /= Real(count);
  for (int k = 0; k < count; ++k) {
    angle[k] = wall_detail::pseudo_angle(px[k] - mean_x, py[k] - mean_y);
  }
  for (int k = 1; k < count; ++k) {
    const Real ak = angle[k], xk = px[k], yk = py[k];
    int j = k - 1;
    while (j >= 0 && angle[j] > ak) {
      angle[j + 1] = angle[j];
      px[j + 1] = px[j];
      py[j + 1] = py[j];
      --j;
    }
    angle[j + 1] = ak;
    px[j + 1] = xk;
    py[j + 1] = yk;
  }
  Real section_x, section_y;
  result.section_area =
      max_of(wall_detail::polygon_area_centroid(px, py, count, section_x, section_y), Real(0));
  if (six_volume > Real(0) && result.section_area > Real(0)) {
    const Vec3<Real> below = moment24 / (Real(4) * six_volume);  // about o, body frame
    result.volume_offset =
        u * (dot(u_body, below) - section_x) + v * (dot(v_body, below) - section_y);
  }

  // The triangle in the same 2-D frame (origin o), counter-clockwise since (u, v, n) is
  // right-handed and n = (b - a) x (c - a).
  const Vec3<Real> o_rel = center_rel - n * d_center;  // o - a
  const Real ax = -dot(o_rel, u), ay = -dot(o_rel, v);
  const Real tri_x[3] = {ax, ax + dot(edge_ab, u), ax + dot(edge_ac, u)};
  const Real tri_y[3] = {ay, ay + dot(edge_ab, v), ay + dot(edge_ac, v)};

  // Algorithm VII: clip by the three oriented edges, ping-ponging between two buffers.
  Real qx[SectionCapacity + 3], qy[SectionCapacity + 3];
  Real* in_x = px;
  Real* in_y = py;
  Real* out_x = qx;
  Real* out_y = qy;
  int clipped = count;
  for (int k = 0; k < 3 && clipped > 0; ++k) {
    const int next = (k + 1) % 3;
    clipped =
        wall_detail::clip_polygon_by_edge(in_x, in_y, clipped, tri_x[k], tri_y[k], tri_x[next],
                                          tri_y[next], out_x, out_y, SectionCapacity + 3);
    if (clipped < 0) {  // cannot happen (one clip adds at most one point); kept as a guard
      WallContact<Real> r = degenerate;
      r.overrun = true;
      return r;
    }
    swap_of(in_x, out_x);
    swap_of(in_y, out_y);
  }
  if (clipped == 0) return result;  // the section misses the triangle

  Real cx, cy;
  result.overlap_area =
      max_of(wall_detail::polygon_area_centroid(in_x, in_y, clipped, cx, cy), Real(0));
  result.overlap_centroid = a + (o_rel + u * cx + v * cy);
  // Area below this is round-off of coordinates of the particle's size.
  const Real area_tolerance = Real(64) * Eps<Real>::value * radius * radius;
  result.status = (result.depth > on_tolerance && result.overlap_area > area_tolerance)
                      ? WallContactStatus::overlapping
                      : WallContactStatus::touching;
  return result;
}

// clip_against_triangle with the smallest section capacity the shape allows: a plane section of
// a convex polyhedron has at most one point per face (twice that is kept, for points that
// round-off puts on both sides of a vertex), so a dodecahedron's fits 32. The local arrays (four
// of capacity + 3 reals) then take a quarter of the memory, which on the GPU is local memory that
// a thread's latency waits on; the arithmetic and results are the same as with any larger
// capacity.
template <class Real>
TALUS_HD inline WallContact<Real> clip_against_triangle_sized(const ConvexView<Real>& shape,
                                                              const Pose<Real>& pose,
                                                              const Vec3<Real>& a,
                                                              const Vec3<Real>& b,
                                                              const Vec3<Real>& c) {
  if (2 * shape.n_faces <= 32) return clip_against_triangle<Real, 32>(shape, pose, a, b, c);
  if (2 * shape.n_faces <= 64) return clip_against_triangle<Real, 64>(shape, pose, a, b, c);
  return clip_against_triangle<Real, kWallSectionCapacity>(shape, pose, a, b, c);
}

}  // namespace talus
