// The overlap polytope of a few kept planes by vertex enumeration: the fast path of the overlap's
// steps 3-5 (overlap_polyhedra.hpp) for a shallow contact, whose culled plane set is small (5.45
// planes bound a shallow dodecahedron overlap on average, benchmarks/README.md).
//
// Every vertex of a simple polytope is the meet of exactly three of its planes. With m <= 8
// planes the C(m, 3) <= 56 triples are few: each is solved by Cramer's rule and kept when every
// other plane holds it strictly. The loops over planes are unrolled for each m (enumerate_fixed),
// so that the planes stay in registers. The volume (Eq. 9, cones from the reference point o, the
// mean of the vertices), the vector area S and the centroid are then sums over the edges of
// terms linear in each end's position along its edge (the divergence theorem, with each face's
// area taken as a signed fan from the foot of o on its plane): every vertex adds its share alone,
// from its own three planes, so that no vertex is stored and no face needs its corners in order.
// No LP, no polar transform and no hull: the same arithmetic runs for every pair, which suits one
// GPU thread per pair.
//
// The path only answers when the result is certain; otherwise it declines and the caller runs
// the LP and the dual hull (Algorithms II-VI), which handle every case:
//  - a vertex with another plane within its round-off (a vertex where four planes meet, twin
//    planes of A and B, a face that is nearly an edge): declined;
//  - the topology must be that of a simple polytope: every line of two planes that holds a vertex
//    holds exactly two (the ends of an edge, so that every vertex has three edges, one along each
//    pair of its planes), Euler's F = 2 + V / 2, and the faces' vector areas closing to
//    sqrt(eps) of their sum (a lost vertex breaks one of these);
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

// A kept plane: dot(n, x) <= h inside, in the pair's frame. Four reals aligned to two, so that a
// GPU thread reads one in two 16-byte loads.
template <class Real>
struct alignas(2 * sizeof(Real)) EnumerationPlane {
  Vec3<Real> n;
  Real h;
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

// The two posed bodies as the enumeration needs them: references to where the caller keeps the
// views and the poses (on the GPU, the views in shared memory and the poses in the batch's
// arrays), so that a call passes a few addresses and no copy, and the rotations are computed
// again from the quaternions where they are needed (overlap_frame computes them the same way, so
// the results do not change). `round_off`: the frame's (overlap_frame).
template <class Real>
struct EnumerationBodies {
  const ConvexView<Real>& a;
  const ConvexView<Real>& b;
  const Vec3<Real>& position_a;
  const Quat<Real>& orientation_a;
  const Vec3<Real>& position_b;
  const Quat<Real>& orientation_b;
  Real round_off;

  // True when p (in the pair's frame, centred on A) lies inside every face plane of both bodies
  // by more than the round-off.
  TALUS_HD bool hold_strictly(const Vec3<Real>& p) const {
    return strictly_inside(a, rotation_matrix(orientation_a), Vec3<Real>(), p, round_off) &&
           strictly_inside(b, rotation_matrix(orientation_b), position_b - position_a, p,
                           round_off);
  }
};

// The index of the line of planes f < g among the C(M, 2) lines of M planes, in the order
// (0,1), (0,2), ..., (1,2), ...
TALUS_HD constexpr int enumeration_line(int M, int f, int g) {
  return f * (2 * M - f - 1) / 2 + (g - f - 1);
}

// Adds one to the 4-bit counter of line `line` (lines 0-15 in count[0], 16-27 in count[1]).
TALUS_HD inline void count_on_line(int line, unsigned long long (&count)[2]) {
  count[line / 16] += 1ull << (4 * (line % 16));
}

// What the vertices add up to (enumerate_fixed, step 3), all relative to the reference point o.
template <class Real>
struct EnumerationSums {
  Real volume3 = 0, area_sum = 0;             // 3 V and the sum of the faces' areas
  Vec3<Real> moment12, vector_area, closure;  // 12 x the first moment, S, sum of n_f A_f
  Vec3<Real> surface_moment3;                 // 3 x the moment of A's faces, r x n dA, about o
};

// The share of a vertex v (relative to o) at one end of the edge on the line of planes f and g
// (offsets h_f, h_g: their heights above o; f_on_a: plane f is A's), with d = n_f x n_g and
// t = +-(d . v), + where v is the edge's far end along d. `vertex_area`: the end's part of S (A's
// faces' n dA), summed over the vertex's three ends for its term v x S_v of the surface moment
// (enumerate_fixed adds it, once a vertex instead of once an end).
template <class Real>
TALUS_HD inline void add_line_end(const Vec3<Real>& n_f, Real h_f, bool f_on_a,
                                  const Vec3<Real>& n_g, Real h_g, bool g_on_a, const Vec3<Real>& d,
                                  Real t, const Vec3<Real>& v, EnumerationSums<Real>& sums,
                                  Vec3<Real>& vertex_area) {
  // Face f's area is the sum over its edges of length * (distance from q_f, the foot of the
  // reference point o on plane f, to the edge's line) / 2: signed, so that any q_f gives the
  // area of the convex polygon. With c = n_f . n_g and s^2 = |d|^2 the distance is
  // (h_g - c h_f) / s, and the length (t_end - t_start) / s with t = d . x; each end adds its
  // +-t: k_f t to A_f and k_g t to A_g.
  const Real c = dot(n_f, n_g);
  const Real half_inverse = Real(0.5) / dot(d, d);
  const Real k_f = (h_g - c * h_f) * half_inverse, k_g = (h_f - c * h_g) * half_inverse;
  const Real a_f = t * k_f, a_g = t * k_g;
  // Eq. 9: the cone from o over face f has volume h_f A_f / 3 ...
  const Real cone_f = a_f * h_f, cone_g = a_g * h_g;
  sums.volume3 += cone_f + cone_g;
  sums.area_sum += a_f + a_g;
  const Vec3<Real> area_f = n_f * a_f, area_g = n_g * a_g;
  sums.closure += area_f + area_g;
  // A's part of this end's areas (selected, not branched on: one instruction each on a GPU).
  const Real a_f_on_a = f_on_a ? a_f : Real(0), a_g_on_a = g_on_a ? a_g : Real(0);
  vertex_area += n_f * a_f_on_a + n_g * a_g_on_a;
  // ... and its first moment is h_f / 4 times the face's, whose fan triangle (q_f, u, w) over
  // the edge (u, w) has its centroid at (q_f + u + w) / 3: with x0 the line's point nearest o,
  // u + w = 2 x0 + (t_u + t_w) d / s^2, and each end adds t (q_f + x0 + v).
  const Vec3<Real> x0 = (n_f * k_g + n_g * k_f) * Real(2);
  sums.moment12 += (x0 + v) * (cone_f + cone_g) + n_f * (cone_f * h_f) + n_g * (cone_g * h_g);
  // The same triangles' area moments, a_f (q_f + x0 + v) / 3 per end, crossed with n_f for the
  // surface moment (q_f = h_f n_f drops out): (x0 + v) x (n_f a_f) over A's faces. The v part is
  // the vertex's (v x vertex_area); the x0 part needs no cross product, as x0 x n_f = -2 k_f d
  // and x0 x n_g = 2 k_g d.
  sums.surface_moment3 += d * (Real(2) * (k_g * a_g_on_a - k_f * a_f_on_a));
}

// The vertices kept by step 1, in the order found, each as the indices of its three planes
// (i | j << 3 | k << 6, 9 bits): seven to a word, in two words held in registers (an array
// indexed at run time would live in a GPU thread's local memory).
struct EnumerationCorners {
  unsigned long long word[2] = {0, 0};

  TALUS_HD void set(int v, int i, int j, int k) {
    const unsigned long long code = unsigned(i | (j << 3) | (k << 6));
    if (v < 7)
      word[0] |= code << (9 * v);
    else
      word[1] |= code << (9 * (v - 7));
  }
  TALUS_HD void get(int v, int& i, int& j, int& k) const {
    const unsigned code = unsigned((v < 7 ? word[0] >> (9 * v) : word[1] >> (9 * (v - 7))) & 511u);
    i = code & 7u;
    j = (code >> 3) & 7u;
    k = code >> 6;
  }
};
static_assert(kEnumerationPlanes <= 8 && kEnumerationVertices <= 14,
              "EnumerationCorners holds 14 vertices of planes 0-7");

// The fast path for exactly M planes (4 <= M <= 8), every loop over planes unrolled so that the
// planes stay in registers. Plane p is plane[p * stride] (in the pair's frame, centred on A; a
// GPU kernel keeps each thread's planes in shared memory, interleaved with the other threads'),
// bit p of `b_planes` set when plane p is B's. Returns true with `result` filled (status
// overlapping), or false (declined; `result` untouched).
//
// 1. Every triple (i, j, k): its meet v = w / det by Cramer's rule, kept when every other plane
//    holds it by more than its round-off; its planes are recorded (EnumerationCorners), and each
//    of its three lines (i, j), (j, k), (k, i) counts one more vertex.
// 2. The certificates of a simple polytope: every line with a vertex has exactly two (the ends of
//    an edge: so every vertex has three edges, one along each pair of its planes), Euler's
//    F = 2 + V / 2, and o, the mean of the vertices, strictly inside both bodies and every
//    bounding plane.
// 3. Each vertex, relative to o, adds its share of the sums: by the divergence theorem the volume
//    (Eq. 9, cones from o), the faces' vector areas and the first moment are sums over the edges
//    of terms linear in each end's position along its edge, so that every vertex contributes on
//    its own, no face needs its corners in order, and no vertex is stored. The sign of each end
//    follows from det: at v = meet(i, j, k), moving along n_i x n_j raises n_k . x when
//    det(n_i, n_j, n_k) = n_k . (n_i x n_j) > 0, so v is then the far end of the edge along
//    n_i x n_j, and likewise for the lines (j, k) and (k, i), with the same det.
template <class Real, int M>
TALUS_HD inline bool enumerate_fixed(const EnumerationBodies<Real>& bodies,
                                     const EnumerationPlane<Real>* plane, int stride,
                                     unsigned b_planes, OverlapResult<Real>& result) {
  static_assert(M >= 4 && M <= kEnumerationPlanes, "the fast path takes 4 to 8 planes");
  static_assert(M * (M - 1) / 2 <= 32, "two words of 4-bit line counters");
  const Real round_off = bodies.round_off;
  Vec3<Real> n[M];
  Real h[M];
  TALUS_UNROLL
  for (int p = 0; p < M; ++p) {
    const EnumerationPlane<Real> q = plane[p * stride];
    n[p] = q.n;
    h[p] = q.h;
  }
  // Every intersection point lies in A, within its bounding sphere about the frame's origin; a
  // triple meeting farther (nearly parallel planes), or at a non-finite point, is no vertex.
  const Real reach = bodies.a.bounding_radius * Real(1.01);
  const Real reach2 = reach * reach;
  EnumerationCorners corners;
  int n_vertices = 0;
  unsigned used = 0;                       // the planes some vertex lies on
  unsigned long long on_line[2] = {0, 0};  // 4-bit vertex count of each line
  bool declined = false;
  // Step 1. The loops run over all of 0..M-1 and skip, so that each unrolls fully.
  TALUS_UNROLL
  for (int i = 0; i < M; ++i) {
    TALUS_UNROLL
    for (int j = 0; j < M; ++j) {
      if (j <= i) continue;
      // Cramer: v = w / det with w = h_i n_j x n_k + h_j n_k x n_i + h_k n_i x n_j
      // = u_ij x n_k + h_k c_ij, where u_ij = h_i n_j - h_j n_i and c_ij = n_i x n_j are shared
      // by every k. The tests run on w, scaled by |det|: no division here.
      const Vec3<Real> c_ij = cross(n[i], n[j]);
      const Vec3<Real> u_ij = n[j] * h[i] - n[i] * h[j];
      TALUS_UNROLL
      for (int k = 0; k < M; ++k) {
        if (k <= j) continue;
        const Real signed_det = dot(c_ij, n[k]);  // det(n_i, n_j, n_k)
        const Vec3<Real> signed_w = cross(u_ij, n[k]) + c_ij * h[k];
        // v = w / det with det > 0 (both negated together, exactly, where det < 0), so that
        // each slack below carries its sign as it is.
        const bool negative = signed_det < Real(0);
        const Real det = negative ? -signed_det : signed_det;
        const Vec3<Real> w = negative ? -signed_w : signed_w;
        // Parallel planes (det = 0) meet nowhere; NaN fails too.
        bool keep = det != Real(0) && dot(w, w) <= reach2 * (det * det);
        // The offsets carry round_off; Cramer's rule amplifies it by up to ~1 / |det| in v: the
        // tolerance of a slack is round_off (1 + 4 / |det|), here times |det|.
        const Real tolerance = round_off * (det + Real(4));
        bool ambiguous = false;
        TALUS_UNROLL
        for (int l = 0; l < M; ++l) {
          if (l == i || l == j || l == k) continue;
          // det (offset_l - dot(n_l, v)), the slack of plane l at the vertex times |det|.
          const Real slack = h[l] * det - dot(n[l], w);
          keep = keep && !(slack < -tolerance);
          ambiguous = ambiguous || !(slack > tolerance);  // a fourth plane through the vertex
#ifndef __CUDA_ARCH__
          // One CPU thread a pair: leaving at the first plane outside is cheaper than the test of
          // the rest (a GPU warp runs them anyway; there the branch would only diverge).
          if (!keep) break;
#endif
        }
        if (keep) {
          if (ambiguous || n_vertices == kEnumerationVertices)
            declined = true;
          else
            corners.set(n_vertices++, i, j, k);
          used |= (1u << i) | (1u << j) | (1u << k);
          count_on_line(enumeration_line(M, i, j), on_line);
          count_on_line(enumeration_line(M, j, k), on_line);
          count_on_line(enumeration_line(M, i, k), on_line);
        }
      }
    }
  }
  // Step 2. Counts of 0 or 2 only: no odd nibble, none of 4 or more.
  constexpr unsigned long long kOnes = 0x1111111111111111ull, kFours = 0xccccccccccccccccull;
  if (declined || n_vertices < 4 || ((on_line[0] | on_line[1]) & (kOnes | kFours)) != 0)
    return false;
  int faces = 0;
  TALUS_UNROLL
  for (int p = 0; p < M; ++p) faces += (used >> p) & 1u;
  // Euler for a simple polytope: V - E + F = 2 with E = 3V / 2.
  if (2 * faces != 4 + n_vertices) return false;
  // The reference point o: the mean of the vertices, inside the polytope.
  Vec3<Real> o;
  for (int v = 0; v < n_vertices; ++v) {
    int i, j, k;
    corners.get(v, i, j, k);
    const EnumerationPlane<Real> pi = plane[i * stride], pj = plane[j * stride],
                                 pk = plane[k * stride];
    const Vec3<Real> c_ij = cross(pi.n, pj.n);
    const Vec3<Real> w = cross(pj.n * pi.h - pi.n * pj.h, pk.n) + c_ij * pk.h;
    o += w * (Real(1) / dot(c_ij, pk.n));
  }
  o = o * (Real(1) / Real(n_vertices));
  if (!bodies.hold_strictly(o)) return false;
  // Every bounding plane holds o by more than the round-off; the least height bounds the
  // inradius from below (a ball about o of that radius lies inside).
  Real least_height = 0;
  bool first = true;
  TALUS_UNROLL
  for (int p = 0; p < M; ++p) {
    if (!((used >> p) & 1u)) continue;  // a plane that bounds nothing
    const Real height = h[p] - dot(n[p], o);
    if (!(height > round_off)) return false;
    least_height = first ? height : min_of(least_height, height);
    first = false;
  }
  // Step 3, relative to o: the offsets become the planes' heights above o.
  EnumerationSums<Real> sums;
  for (int v = 0; v < n_vertices; ++v) {
    int i, j, k;
    corners.get(v, i, j, k);
    const EnumerationPlane<Real> pi = plane[i * stride], pj = plane[j * stride],
                                 pk = plane[k * stride];
    const Real hi = pi.h - dot(pi.n, o), hj = pj.h - dot(pj.n, o), hk = pk.h - dot(pk.n, o);
    const Vec3<Real> d_ij = cross(pi.n, pj.n), d_jk = cross(pj.n, pk.n), d_ki = cross(pk.n, pi.n);
    const Real det = dot(d_ij, pk.n);
    const Vec3<Real> w = d_jk * hi + d_ki * hj + d_ij * hk;
    const Real inverse = Real(1) / det;
    const Vec3<Real> x = w * inverse;             // the vertex, relative to o
    const Real signed_inverse = abs_of(inverse);  // sign(det) / det: each end's sign
    const bool on_a_i = !((b_planes >> i) & 1u), on_a_j = !((b_planes >> j) & 1u),
               on_a_k = !((b_planes >> k) & 1u);
    Vec3<Real> vertex_area;
    add_line_end(pi.n, hi, on_a_i, pj.n, hj, on_a_j, d_ij, dot(d_ij, w) * signed_inverse, x, sums,
                 vertex_area);
    add_line_end(pj.n, hj, on_a_j, pk.n, hk, on_a_k, d_jk, dot(d_jk, w) * signed_inverse, x, sums,
                 vertex_area);
    add_line_end(pk.n, hk, on_a_k, pi.n, hi, on_a_i, d_ki, dot(d_ki, w) * signed_inverse, x, sums,
                 vertex_area);
    sums.vector_area += vertex_area;
    sums.surface_moment3 += cross(x, vertex_area);
  }
  const Real volume = sums.volume3 * (Real(1) / Real(3));
  if (!(norm(sums.closure) <= SqrtEps<Real>::value * sums.area_sum) || !(volume > Real(0)))
    return false;
  result.status = OverlapStatus::overlapping;
  result.volume = volume;
  result.vector_area = sums.vector_area;
  const Vec3<Real> centroid = sums.moment12 * (Real(1) / (Real(12) * volume));  // about o
  result.centroid = bodies.position_a + o + centroid;
  result.surface_moment =
      sums.surface_moment3 * (Real(1) / Real(3)) - cross(centroid, sums.vector_area);
  result.depth_hint = least_height;  // a ball about o of this radius lies inside: <= inradius
  result.hull_points = faces;
  result.workspace_overrun = false;
  result.enumerated = true;
  return true;
}

// The fast path for m planes, plane p at plane[p * stride] (in the pair's frame, centred on A),
// bit p of `b_planes` set when plane p is B's. Returns true with `result` filled (status
// overlapping), or false (declined; `result` untouched). The bodies come by value: a few
// addresses, which a GPU thread passes in registers.
template <class Real>
TALUS_HD inline bool enumerate_overlap(EnumerationBodies<Real> bodies,
                                       const EnumerationPlane<Real>* plane, int stride,
                                       unsigned b_planes, int m, OverlapResult<Real>& result) {
  switch (m) {
    case 4:
      return enumerate_fixed<Real, 4>(bodies, plane, stride, b_planes, result);
    case 5:
      return enumerate_fixed<Real, 5>(bodies, plane, stride, b_planes, result);
    case 6:
      return enumerate_fixed<Real, 6>(bodies, plane, stride, b_planes, result);
    case 7:
      return enumerate_fixed<Real, 7>(bodies, plane, stride, b_planes, result);
    case 8:
      return enumerate_fixed<Real, 8>(bodies, plane, stride, b_planes, result);
    default:
      return false;
  }
}

}  // namespace overlap_detail

}  // namespace talus
