// The overlap polytope of a few kept planes by vertex enumeration: the fast path of the overlap's
// steps 3-5 (overlap_polyhedra.hpp) for a shallow contact, whose culled plane set is small (5.45
// planes bound a shallow dodecahedron overlap on average, benchmarks/README.md).
//
// Every vertex of a simple polytope is the meet of exactly three of its planes. With m <= 8
// planes the C(m, 3) <= 56 triples are few: each is solved by Cramer's rule and kept when every
// other plane holds it strictly. An edge is a pair of vertices sharing exactly two planes, and a
// side of both their faces; one pass over the pairs finds them all. A face's area is the fan of
// triangles from one of its corners over its sides (a convex polygon, so every triangle counts
// positively). The volume is Eq. 9 with the reference point o = the mean of the vertices: a cone
// from o over each fan triangle. No LP, no polar transform and no hull: the same arithmetic runs
// for every pair, which suits one GPU thread per pair.
//
// The path only answers when the result is certain; otherwise it declines and the caller runs
// the LP and the dual hull (Algorithms II-VI), which handle every case:
//  - a vertex with another plane within its round-off (a vertex where four planes meet, twin
//    planes of A and B, a face that is nearly an edge): declined;
//  - the topology must be that of a simple polytope: every vertex exactly three edges, leaving
//    out each of its planes once (so every corner of a face has exactly 2 neighbours on it),
//    Euler's F = 2 + V / 2, and the faces' vector areas closing to sqrt(eps) of their sum (a lost
//    vertex breaks one of these);
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

// Records, for vertex v, the plane `left` (a bit) that one of its edges leaves out: 8 bits a
// vertex, vertices 0-7 in `low`, 8-11 in `high`.
TALUS_HD inline void note_left_plane(int v, unsigned left, unsigned long long& low,
                                     unsigned& high) {
  if (v < 8)
    low |= static_cast<unsigned long long>(left) << (8 * v);
  else
    high |= left << (8 * (v - 8));
}

// A vertex found, padded to four reals aligned to two (two 16-byte loads on a GPU thread).
template <class Real>
struct alignas(2 * sizeof(Real)) EnumerationVertex {
  Vec3<Real> p;
  Real unused;
};

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
  EnumerationVertex<Real> vertex[kEnumerationVertices];
  unsigned char on[kEnumerationVertices];  // bit i: the vertex is the meet of plane i
  // Each plane's first vertex found (4 bits a plane; 0xf: none yet), its fan's apex below.
  unsigned first_corner = 0xffffffffu;
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
        if (det == Real(0)) continue;            // parallel: no single meeting point
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
        vertex[n_vertices].p = w * (Real(1) / det);
        on[n_vertices] = static_cast<unsigned char>((1u << i) | (1u << j) | (1u << k));
        unsigned long long rest = (1ull << i) | (1ull << j) | (1ull << k);
        while (rest != 0) {
          const int f = pop_lowest_bit(rest);
          if (((first_corner >> (4 * f)) & 0xfu) == 0xfu)
            first_corner ^= (0xfu ^ unsigned(n_vertices)) << (4 * f);
        }
        ++n_vertices;
      }
    }
  }
  if (n_vertices < 4) return false;
  // The reference point o: the mean of the vertices, inside the polytope.
  Vec3<Real> o;
  for (int v = 0; v < n_vertices; ++v) o += vertex[v].p;
  o = o * (Real(1) / Real(n_vertices));
  if (!strictly_inside(a, frame.rot[0], frame.center[0], o, round_off) ||
      !strictly_inside(b, frame.rot[1], frame.center[1], o, round_off))
    return false;
  for (int v = 0; v < n_vertices; ++v) vertex[v].p = vertex[v].p - o;  // relative to o from here

  // The faces: the planes some vertex lies on, each at height h_f - n_f . o above o.
  unsigned used = 0;
  for (int v = 0; v < n_vertices; ++v) used |= on[v];
  Real height[kEnumerationPlanes];
  Real least_height = 0;
  int faces = 0;
  for (int f = 0; f < m; ++f) {
    if (!((used >> f) & 1u)) continue;  // a plane that bounds nothing
    height[f] = plane[f].h - dot(plane[f].n, o);
    if (!(height[f] > round_off)) return false;
    least_height = faces == 0 ? height[f] : min_of(least_height, height[f]);
    ++faces;
  }
  // Euler for a simple polytope: V - E + F = 2 with E = 3V / 2.
  if (2 * faces != 4 + n_vertices) return false;

  // The edges: the pairs of vertices sharing exactly two planes, f and g. Each is a side of
  // face f's polygon and of face g's; the fan of face f from its apex (its first vertex c_f)
  // takes the triangle (c_f, u, w) from it (zero when c_f is u or w). On a convex polygon these
  // triangles tile the face, all with one orientation, so each counts |area| positively.
  // Cones from o (Eq. 9): each triangle's tetrahedron (o, c, u, w) has volume
  // triangle * height / 3 and centroid (c + u + w) / 4 relative to o.
  Real volume = 0, area_sum = 0;
  Vec3<Real> moment, vector_area, closure;
  // Per vertex, 4 bits of its count of edges and 8 of the planes its edges leave out.
  unsigned long long degree = 0, left_low = 0;
  unsigned left_high = 0;
  for (int u = 0; u + 1 < n_vertices; ++u) {
    const unsigned on_u = on[u];
    for (int w = u + 1; w < n_vertices; ++w) {
      const unsigned on_w = on[w];
      const unsigned shared = on_u & on_w;
      if (!exactly_two_bits(shared)) continue;
      degree += (1ull << (4 * u)) + (1ull << (4 * w));
      note_left_plane(u, on_u ^ shared, left_low, left_high);
      note_left_plane(w, on_w ^ shared, left_low, left_high);
      unsigned long long faces_of_edge = shared;
      while (faces_of_edge != 0) {
        const int f = pop_lowest_bit(faces_of_edge);
        const int c = int((first_corner >> (4 * f)) & 0xfu);
        if (c == u || c == w) continue;
        const Vec3<Real> apex = vertex[c].p, pu = vertex[u].p, pw = vertex[w].p;
        const Real triangle = abs_of(dot(cross(pu - apex, pw - apex), plane[f].n)) * Real(0.5);
        const Real cone = triangle * height[f];
        volume += cone * (Real(1) / Real(3));
        moment += (apex + pu + pw) * (cone * (Real(1) / Real(12)));
        const Vec3<Real> face_area = plane[f].n * triangle;
        if (!((b_planes >> f) & 1u)) vector_area += face_area;
        closure += face_area;
        area_sum += triangle;
      }
    }
  }
  // Every vertex has three edges, one along each pair of its planes: its edges leave out each of
  // its three planes once. So each face's corners form cycles of at least 3; a face of two
  // cycles would count one face short in Euler's check above.
  for (int v = 0; v < n_vertices; ++v) {
    const unsigned left =
        v < 8 ? unsigned(left_low >> (8 * v)) & 0xffu : (left_high >> (8 * (v - 8))) & 0xffu;
    if (((degree >> (4 * v)) & 0xfu) != 3u || left != on[v]) return false;
  }
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
