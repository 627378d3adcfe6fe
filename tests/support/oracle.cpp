// Primal half-space clipping of a polyhedron held as a list of polygons (3-D Sutherland–Hodgman:
// each face polygon is clipped by the plane, and the cut points close the hole as a new face).
#include "tests/support/oracle.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>

namespace talus {
namespace {

using Real = long double;
using Quatl = Quat<long double>;

enum class Origin { a, b };

// One planar face of the polyhedron being clipped: vertices counter-clockwise seen from outside,
// the unit outward normal of the surface it came from, and which body that surface belongs to.
struct ClipFace {
  std::vector<Vec3l> vertices;
  Vec3l normal;
  Origin origin;
};
using Polyhedron = std::vector<ClipFace>;

Vec3l widen(const Vec3d& v) {
  return Vec3l(v);
}

// The template's faces, posed: x = shift + rotate(q, body). The shift is the body's position
// relative to the clipping frame's origin, so coordinates stay small.
Polyhedron posed_polyhedron(const ShapeTemplate& body, const Quatl& q, const Vec3l& shift,
                            Origin origin) {
  std::vector<Vec3l> posed(body.vertices.size());
  for (size_t i = 0; i < posed.size(); ++i) posed[i] = shift + rotate(q, widen(body.vertices[i]));
  Polyhedron poly;
  for (const Face& face : body.faces) {
    ClipFace clip_face{{}, rotate(q, widen(face.normal)), origin};
    clip_face.normal = clip_face.normal / norm(clip_face.normal);
    for (int index : face.loop) clip_face.vertices.push_back(posed[index]);
    poly.push_back(std::move(clip_face));
  }
  return poly;
}

// Distances within this band of a plane count as on it: far above long double round-off, far
// below anything a test resolves (the templates' planes and vertices agree to double round-off).
Real on_plane_tolerance(const Polyhedron& poly) {
  Real extent = 0;
  for (const ClipFace& f : poly)
    for (const Vec3l& v : f.vertices) extent = std::max(extent, norm(v));
  return 64 * Real(DBL_EPSILON) * extent;
}

// Orders points of the plane with unit normal n counter-clockwise seen from +n, dropping exact
// duplicates (a vertex or cut point shared by two faces is computed identically in both).
std::vector<Vec3l> ordered_on_plane(std::vector<Vec3l> points, const Vec3l& n) {
  if (points.size() < 3) return {};
  Vec3l mean;
  for (const Vec3l& p : points) mean += p;
  mean = mean / Real(points.size());
  // (u, w, n) right-handed, so increasing atan2 angle is counter-clockwise about n.
  const Vec3l helper = std::fabs(n.x) < 0.6L ? Vec3l(1, 0, 0) : Vec3l(0, 1, 0);
  Vec3l u = cross(helper, n);
  u = u / norm(u);
  const Vec3l w = cross(n, u);
  std::vector<std::pair<Real, Vec3l>> by_angle;
  for (const Vec3l& p : points) {
    const Vec3l r = p - mean;
    by_angle.emplace_back(std::atan2(dot(r, w), dot(r, u)), p);
  }
  std::sort(by_angle.begin(), by_angle.end(),
            [](const auto& l, const auto& r) { return l.first < r.first; });
  std::vector<Vec3l> loop;
  auto same = [](const Vec3l& p, const Vec3l& q) { return p.x == q.x && p.y == q.y && p.z == q.z; };
  for (const auto& entry : by_angle)
    if (loop.empty() || !same(loop.back(), entry.second)) loop.push_back(entry.second);
  while (loop.size() > 1 && same(loop.front(), loop.back())) loop.pop_back();
  if (loop.size() < 3) return {};
  return loop;
}

enum class ClipOutcome { unchanged, emptied, cut };

// Keeps the part of poly with dot(n, x) <= d (n unit) and closes it with a cap face of the given
// origin, appended last. Vertices within tolerance of the plane are projected onto it.
ClipOutcome clip(Polyhedron& poly, const Vec3l& n, Real d, Origin cap_origin, Real tolerance) {
  Real s_min = 0, s_max = 0;
  bool first = true;
  for (const ClipFace& f : poly)
    for (const Vec3l& v : f.vertices) {
      const Real s = dot(n, v) - d;
      s_min = first ? s : std::min(s_min, s);
      s_max = first ? s : std::max(s_max, s);
      first = false;
    }
  if (first || s_max <= tolerance) return ClipOutcome::unchanged;
  if (s_min >= -tolerance) {
    poly.clear();  // at most a face, edge or vertex of contact: no volume
    return ClipOutcome::emptied;
  }
  auto snapped_distance = [&](const Vec3l& v) {
    const Real s = dot(n, v) - d;
    return std::fabs(s) <= tolerance ? Real(0) : s;
  };
  std::vector<Vec3l> cap_points;
  Polyhedron clipped;
  for (const ClipFace& f : poly) {
    ClipFace kept{{}, f.normal, f.origin};
    const size_t count = f.vertices.size();
    for (size_t i = 0; i < count; ++i) {
      const Vec3l& current = f.vertices[i];
      const Vec3l& next = f.vertices[(i + 1) % count];
      const Real s_current = snapped_distance(current);
      const Real s_next = snapped_distance(next);
      if (s_current == 0) {
        const Vec3l projected = current - n * (dot(n, current) - d);
        kept.vertices.push_back(projected);
        cap_points.push_back(projected);
      } else if (s_current < 0) {
        kept.vertices.push_back(current);
      }
      if ((s_current < 0 && s_next > 0) || (s_current > 0 && s_next < 0)) {
        // Always interpolate from the inside end so that the two faces sharing this edge produce
        // the bit-identical point.
        const Vec3l& inside = s_current < 0 ? current : next;
        const Vec3l& outside = s_current < 0 ? next : current;
        const Real s_in = s_current < 0 ? s_current : s_next;
        const Real s_out = s_current < 0 ? s_next : s_current;
        const Vec3l cut = inside + (outside - inside) * (s_in / (s_in - s_out));
        kept.vertices.push_back(cut);
        cap_points.push_back(cut);
      }
    }
    if (kept.vertices.size() >= 3) clipped.push_back(std::move(kept));
  }
  std::vector<Vec3l> cap = ordered_on_plane(std::move(cap_points), n);
  if (!cap.empty()) clipped.push_back(ClipFace{std::move(cap), n, cap_origin});
  poly = std::move(clipped);
  return ClipOutcome::cut;
}

// Vector area of a planar polygon (fan of cross products): its area times its unit normal.
Vec3l polygon_vector_area(const std::vector<Vec3l>& vertices) {
  Vec3l sum;
  for (size_t i = 1; i + 1 < vertices.size(); ++i)
    sum += cross(vertices[i] - vertices[0], vertices[i + 1] - vertices[0]);
  return sum * 0.5L;
}

// Volume and centroid by tetrahedra from an interior point (divergence theorem), vector areas by
// origin. Coordinates are relative to origin_shift, which is added back to the centroid.
OracleResult measure(const Polyhedron& poly, const Vec3d& origin_shift) {
  OracleResult result;
  if (poly.size() < 4) return result;
  Vec3l apex;
  int vertex_count = 0;
  for (const ClipFace& f : poly)
    for (const Vec3l& v : f.vertices) {
      apex += v;
      ++vertex_count;
    }
  apex = apex / Real(vertex_count);
  Real volume = 0;
  Vec3l moment;  // sum of tetrahedron volume * (its centroid - apex)
  for (const ClipFace& f : poly) {
    const Vec3l p0 = f.vertices[0] - apex;
    for (size_t i = 1; i + 1 < f.vertices.size(); ++i) {
      const Vec3l p1 = f.vertices[i] - apex, p2 = f.vertices[i + 1] - apex;
      const Real tet = triple(p0, p1, p2) / 6;
      volume += tet;
      moment += (p0 + p1 + p2) * (tet / 4);
    }
    const Real area = dot(polygon_vector_area(f.vertices), f.normal);
    (f.origin == Origin::a ? result.vector_area_a : result.vector_area_b) += f.normal * area;
    result.boundary_area += area;
  }
  if (!(volume > 0)) return OracleResult{};
  result.volume = volume;
  result.centroid = widen(origin_shift) + apex + moment / volume;
  result.n_faces = int(poly.size());
  return result;
}

Vec3l unit(const Vec3l& v) {
  return v / norm(v);
}

}  // namespace

OracleResult oracle_overlap(const ShapeTemplate& a, const Posed& pose_a, const ShapeTemplate& b,
                            const Posed& pose_b) {
  // Work relative to A's position: A sits at the origin, B at b_shift.
  Polyhedron poly = posed_polyhedron(a, Quatl(pose_a.orientation), Vec3l(), Origin::a);
  const Real tolerance = on_plane_tolerance(poly);
  const Quatl qb(pose_b.orientation);
  const Vec3l b_shift = widen(pose_b.position) - widen(pose_a.position);
  for (const Face& face : b.faces) {
    const Vec3l rotated = rotate(qb, widen(face.normal));
    // dot(R n_b, x - b_shift) = offset_b, rescaled to a unit normal.
    const Real length = norm(rotated);
    const Vec3l n = rotated / length;
    const Real d = (Real(face.offset) + dot(rotated, b_shift)) / length;
    if (clip(poly, n, d, Origin::b, tolerance) == ClipOutcome::emptied) return OracleResult{};
  }
  return measure(poly, pose_a.position);
}

OracleResult oracle_clip_by_plane(const ShapeTemplate& body, const Posed& pose, Vec3l plane_normal,
                                  long double plane_offset) {
  Polyhedron poly = posed_polyhedron(body, Quatl(pose.orientation), Vec3l(), Origin::a);
  const Real length = norm(plane_normal);
  const Vec3l n = plane_normal / length;
  const Real d = plane_offset / length - dot(n, widen(pose.position));
  if (clip(poly, n, d, Origin::b, on_plane_tolerance(poly)) == ClipOutcome::emptied) return {};
  return measure(poly, pose.position);
}

long double oracle_volume_below_plane(const ShapeTemplate& body, const Posed& pose,
                                      Vec3l plane_normal, long double plane_offset) {
  return oracle_clip_by_plane(body, pose, plane_normal, plane_offset).volume;
}

std::vector<Vec3l> oracle_section_polygon(const ShapeTemplate& body, const Posed& pose,
                                          Vec3l plane_normal, long double plane_offset) {
  Polyhedron poly = posed_polyhedron(body, Quatl(pose.orientation), Vec3l(), Origin::a);
  const Real tolerance = on_plane_tolerance(poly);
  const Vec3l n = unit(plane_normal);
  const Vec3l position = widen(pose.position);
  const Real d = plane_offset / norm(plane_normal) - dot(n, position);
  std::vector<Vec3l> section;
  // A face lying on the plane is the section (the clip would see the body on one side only).
  for (const ClipFace& f : poly) {
    const bool on_plane = std::all_of(f.vertices.begin(), f.vertices.end(), [&](const Vec3l& v) {
      return std::fabs(dot(n, v) - d) <= tolerance;
    });
    if (on_plane) {
      for (const Vec3l& v : f.vertices) section.push_back(v - n * (dot(n, v) - d));
      if (dot(f.normal, n) < 0) std::reverse(section.begin(), section.end());
      break;
    }
  }
  if (section.empty() && clip(poly, n, d, Origin::b, tolerance) == ClipOutcome::cut &&
      !poly.empty() && poly.back().origin == Origin::b)
    section = poly.back().vertices;
  for (Vec3l& v : section) v += position;
  return section;
}

}  // namespace talus
