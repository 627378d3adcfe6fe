// The overlap polytope of a few kept planes by vertex enumeration: the fast path of the overlap's
// steps 3-5 (overlap_polyhedra.hpp) for a shallow contact, whose culled plane set is small (5.45
// planes bound a shallow dodecahedron overlap on average, benchmarks/README.md).
//
// Every vertex of a simple polytope is the meet of exactly three of its planes. With m <= 8
// planes the C(m, 3) <= 56 triples are few: each is solved by Cramer's rule and kept when every
// other plane holds it strictly. A face is then the set of vertices on its plane, its edges the
// pairs of those vertices that share one more plane, and the polygon's area the fan of triangles
// from the mean of its corners (inside a convex polygon, so every triangle counts positively).
// The volume is Eq. 9 with the reference point o = the mean of the vertices: a cone from o over
// each fan triangle. No LP, no polar transform and no hull: the same arithmetic runs for every
// pair, which suits one GPU thread per pair.
//
// The path only answers when the result is certain; otherwise it declines and the caller runs
// the LP and the dual hull (Algorithms II-VI), which handle every case:
//  - a vertex with another plane within its round-off (a vertex where four planes meet, twin
//    planes of A and B, a face that is nearly an edge): declined;
//  - the topology must be that of a simple polytope: every face at least 3 corners, every corner
//    of a face exactly 2 neighbours on it, Euler's F = 2 + V / 2, and the faces' vector areas
//    closing to sqrt(eps) of their sum (a lost vertex breaks one of these);
//  - the mean of the vertices must lie strictly inside both bodies (every face of both, not only
//    the kept ones): the culled planes are redundant only when the intersection has an interior
//    (overlap_finish makes the same check at its x_o), and a point strictly inside both proves it.
// So a separate, touching or degenerate pair always declines here: only `overlapping` is given.
#pragma once

#include "solver/geometry/overlap_culling.hpp"

namespace talus {

// The most planes the fast path takes; C(8, 3) = 56 triples.
constexpr int kEnumerationPlanes = 8;
// A simple polytope with F faces has 2F - 4 vertices (Euler, three faces at each vertex).
constexpr int kEnumerationVertices = 2 * kEnumerationPlanes - 4;

namespace overlap_detail {

// True when exactly two bits of x are set.
TALUS_HD constexpr bool exactly_two_bits(unsigned x) {
  const unsigned rest = x & (x - 1);
  return rest != 0 && (rest & (rest - 1)) == 0;
}

// True when p (frame coordinates) lies inside every face plane of the posed body by more than
// `margin`.
template <class Real>
TALUS_HD inline bool strictly_inside(const ConvexView<Real>& body, const Mat3<Real>& rot,
                                     const Vec3<Real>& center, const Vec3<Real>& p, Real margin) {
  const Vec3<Real> q = rot.transpose_times(p - center);
  for (int f = 0; f < body.n_faces; ++f)
    if (!(dot(body.face_normals[f], q) < body.face_offsets[f] - margin)) return false;
  return true;
}

// A kept plane: dot(n, x) <= h inside, in the pair's frame. Four reals aligned to two, so that a
// GPU thread reads one in two 16-byte loads.
template <class Real>
struct alignas(2 * sizeof(Real)) EnumerationPlane {
  Vec3<Real> n;
  Real h;
};

// The fast path. Planes i < m (in the pair's frame, centred on A), bit i of `b_planes` set when
// plane i is B's; `origin`: A's world position. Returns true with `result` filled (status
// overlapping), or false (declined; `result` untouched).
template <class Real>
TALUS_HD inline bool enumerate_overlap(const ConvexView<Real>& a, const ConvexView<Real>& b,
                                       const OverlapFrame<Real>& frame,
                                       const EnumerationPlane<Real>* plane, unsigned b_planes,
                                       int m, const Vec3<Real>& origin,
                                       OverlapResult<Real>& result) {
  const Real round_off = frame.round_off;
  if (m < 4 || m > kEnumerationPlanes) return false;
  Vec3<Real> vertex[kEnumerationVertices];
  unsigned char on[kEnumerationVertices];  // bit i: the vertex is the meet of plane i
  int n_vertices = 0;
  // Every intersection point lies in A, within its bounding sphere about the frame's origin; a
  // triple meeting farther (nearly parallel planes), or at a non-finite point, is no vertex.
  const Real reach = a.bounding_radius * Real(1.01);
  const Real reach2 = reach * reach;
  for (int i = 0; i + 2 < m; ++i) {
    for (int j = i + 1; j + 1 < m; ++j) {
      const Vec3<Real> c_ij = cross(plane[i].n, plane[j].n);
      for (int k = j + 1; k < m; ++k) {
        const Real det = dot(c_ij, plane[k].n);  // det(n_i, n_j, n_k)
        if (det == Real(0)) continue;           // parallel: no single meeting point
        // Cramer: v = w / det with w = h_i n_j x n_k + h_j n_k x n_i + h_k n_i x n_j. The tests
        // below run on w, scaled by |det|, so that only the vertices kept (fewer than half of
        // the triples) pay for a division.
        const Vec3<Real> w = cross(plane[j].n, plane[k].n) * plane[i].h +
                             cross(plane[k].n, plane[i].n) * plane[j].h + c_ij * plane[k].h;
        const Real det2 = det * det;
        if (!(dot(w, w) <= reach2 * det2)) continue;
        // The offsets carry round_off; Cramer's rule amplifies it by up to ~1 / |det| in v: the
        // tolerance of a slack is round_off (1 + 4 / |det|), here times |det|.
        const Real abs_det = abs_of(det);
        const Real tolerance = round_off * (abs_det + Real(4));
        bool outside = false, ambiguous = false;
        for (int l = 0; l < m && !outside; ++l) {
          if (l == i || l == j || l == k) continue;
          // |det| (offset_l - dot(n_l, v)), the slack of plane l at the vertex times |det|.
          const Real slack = plane[l].h * det - dot(plane[l].n, w);
          const Real scaled = det > Real(0) ? slack : -slack;
          if (scaled < -tolerance)
            outside = true;
          else if (!(scaled > tolerance))
            ambiguous = true;  // a fourth plane through the vertex, within round-off
        }
        if (outside) continue;
        if (ambiguous || n_vertices == kEnumerationVertices) return false;
        vertex[n_vertices] = w * (Real(1) / det);
        on[n_vertices] = static_cast<unsigned char>((1u << i) | (1u << j) | (1u << k));
        ++n_vertices;
      }
    }
  }
  if (n_vertices < 4) return false;
  // The reference point o: the mean of the vertices, inside the polytope.
  Vec3<Real> o;
  for (int v = 0; v < n_vertices; ++v) o += vertex[v];
  o = o * (Real(1) / Real(n_vertices));
  if (!strictly_inside(a, frame.rot[0], frame.center[0], o, round_off) ||
      !strictly_inside(b, frame.rot[1], frame.center[1], o, round_off))
    return false;
  for (int v = 0; v < n_vertices; ++v) vertex[v] = vertex[v] - o;  // relative to o from here on

  Real volume = 0, area_sum = 0, least_height = 0;
  Vec3<Real> moment, vector_area, closure;
  int faces = 0;
  for (int f = 0; f < m; ++f) {
    const unsigned bit = 1u << f;
    int corner[kEnumerationVertices];
    int corners = 0;
    Vec3<Real> q;
    for (int v = 0; v < n_vertices; ++v) {
      if (on[v] & bit) {
        corner[corners++] = v;
        q += vertex[v];
      }
    }
    if (corners == 0) continue;                         // a plane that bounds nothing
    if (corners < 3) return false;                      // not a polygon: a degenerate face
    q = q * (Real(1) / Real(corners));                  // inside the convex polygon
    const Real height = plane[f].h - dot(plane[f].n, o);  // o's distance from the plane
    if (!(height > round_off)) return false;
    // Each corner has exactly two neighbours on the face: the corners sharing one more plane.
    Real area = 0;
    Vec3<Real> face_moment;
    for (int s = 0; s < corners; ++s) {
      const int u = corner[s];
      int neighbours = 0;
      for (int t = 0; t < corners; ++t) {
        const int w = corner[t];
        if (t == s || !exactly_two_bits(on[u] & on[w])) continue;
        ++neighbours;
        if (t < s) continue;  // each edge once
        // The fan triangle (q, u, w), lying in the plane: its area along the normal.
        const Real triangle =
            abs_of(dot(cross(vertex[u] - q, vertex[w] - q), plane[f].n)) * Real(0.5);
        area += triangle;
        face_moment += (q + vertex[u] + vertex[w]) * triangle;
      }
      if (neighbours != 2) return false;
    }
    // Cones from o (Eq. 9): each fan triangle's tetrahedron (o, q, u, w) has volume
    // triangle * height / 3 and centroid (q + u + w) / 4 relative to o.
    const Real cone = area * height * (Real(1) / Real(3));
    volume += cone;
    moment += face_moment * (height * (Real(1) / Real(12)));
    const Vec3<Real> face_area = plane[f].n * area;
    if (!(b_planes & bit)) vector_area += face_area;
    closure += face_area;
    area_sum += area;
    least_height = faces == 0 ? height : min_of(least_height, height);
    ++faces;
  }
  // Euler for a simple polytope: V - E + F = 2 with E = 3V / 2.
  if (2 * faces != 4 + n_vertices) return false;
  if (!(norm(closure) <= SqrtEps<Real>::value * area_sum) || !(volume > Real(0))) return false;
  result.status = OverlapStatus::overlapping;
  result.volume = volume;
  result.vector_area = vector_area;
  result.centroid = origin + o + moment * (Real(1) / volume);
  result.depth_hint = least_height;  // a ball about o of this radius lies inside: <= inradius
  result.hull_points = faces;
  result.workspace_overrun = false;
  result.enumerated = true;
  return true;
}

}  // namespace overlap_detail

}  // namespace talus
