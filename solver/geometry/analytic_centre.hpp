// The overlap's retry point (overlap_polyhedra.hpp, step 4): the analytic centre of the kept
// planes by damped Newton steps, the barrier's Hessian there and its Cholesky factor, which
// rounds the polytope for the dual hull (x' = L^T x), and the maps back.
#pragma once

#include <cmath>

#include "solver/core/math.hpp"
#include "solver/core/vec3.hpp"

namespace talus {
namespace overlap_detail {

// Solves H x = rhs for a symmetric positive definite 3x3 H given as its upper triangle
// h = {xx, xy, xz, yy, yz, zz}: Gaussian elimination with symmetric pivoting, the largest
// remaining diagonal first, which is backward stable for such matrices however ill-conditioned
// (each eliminated entry's error is round-off of the largest entry, not of the determinant's
// cancelling products). False when a pivot is not positive (H not positive definite).
template <class Real>
TALUS_HD inline bool solve_spd3(const Real h[6], const Vec3<Real>& rhs, Vec3<Real>& x) {
  Real a[3][3] = {{h[0], h[1], h[2]}, {h[1], h[3], h[4]}, {h[2], h[4], h[5]}};
  Real b[3] = {rhs.x, rhs.y, rhs.z};
  int p[3] = {0, 1, 2};
  for (int k = 0; k < 3; ++k) {
    int best = k;
    for (int i = k + 1; i < 3; ++i)
      if (a[p[i]][p[i]] > a[p[best]][p[best]]) best = i;
    const int swap = p[k];
    p[k] = p[best];
    p[best] = swap;
    const int r = p[k];
    if (!(a[r][r] > Real(0))) return false;
    for (int i = k + 1; i < 3; ++i) {
      const int s = p[i];
      const Real l = a[s][r] / a[r][r];
      for (int j = k + 1; j < 3; ++j) a[s][p[j]] -= l * a[r][p[j]];
      b[s] -= l * b[r];
    }
  }
  Real y[3];
  for (int k = 2; k >= 0; --k) {
    const int r = p[k];
    Real sum = b[r];
    for (int j = k + 1; j < 3; ++j) sum -= a[r][p[j]] * y[p[j]];
    y[r] = sum / a[r][r];
  }
  x = Vec3<Real>(y[0], y[1], y[2]);
  return true;
}

// The gradient and Hessian of the barrier -sum log(slack_i) over the m planes n_i . x <= h_i,
// whose slacks are ws.plane_offset: g = sum n_i / s_i, H = sum n_i n_i^T / s_i^2 (upper triangle
// {xx, xy, xz, yy, yz, zz}).
template <class Real, class Workspace>
TALUS_HD inline void barrier_derivatives(const Workspace& ws, int m, Vec3<Real>& g, Real h[6]) {
  g = Vec3<Real>();
  for (int k = 0; k < 6; ++k) h[k] = 0;
  for (int i = 0; i < m; ++i) {
    const Vec3<Real> u = ws.hull.plane_normal[i] * (Real(1) / ws.plane_offset[i]);
    g += u;
    h[0] += u.x * u.x, h[1] += u.x * u.y, h[2] += u.x * u.z;
    h[3] += u.y * u.y, h[4] += u.y * u.z, h[5] += u.z * u.z;
  }
}

// The Cholesky factor H = L L^T of a symmetric 3x3 H (upper triangle, as above), L lower
// triangular as {L00, L10, L11, L20, L21, L22}; false when H is not (numerically) positive
// definite. Backward stable without pivoting for such H, however ill-conditioned.
template <class Real>
TALUS_HD inline bool cholesky3(const Real h[6], Real l[6]) {
  if (!(h[0] > Real(0))) return false;
  l[0] = std::sqrt(h[0]);
  l[1] = h[1] / l[0];
  l[3] = h[2] / l[0];
  const Real d1 = h[3] - l[1] * l[1];
  if (!(d1 > Real(0))) return false;
  l[2] = std::sqrt(d1);
  l[4] = (h[4] - l[3] * l[1]) / l[2];
  const Real d2 = h[5] - l[3] * l[3] - l[4] * l[4];
  if (!(d2 > Real(0))) return false;
  l[5] = std::sqrt(d2);
  return true;
}

// The rounding map x' = L^T x of overlap_finish's retry: L^-1 n (a plane's normal in x'), L^-T c
// (a point of x' back in x) and L s / det L (a vector area of x' back in x, Nanson's formula for
// the map's inverse).
template <class Real>
TALUS_HD inline Vec3<Real> lower_solve(const Real l[6], const Vec3<Real>& n) {
  const Real x = n.x / l[0];
  const Real y = (n.y - l[1] * x) / l[2];
  return Vec3<Real>(x, y, (n.z - l[3] * x - l[4] * y) / l[5]);
}
template <class Real>
TALUS_HD inline Vec3<Real> upper_solve(const Real l[6], const Vec3<Real>& c) {
  const Real z = c.z / l[5];
  const Real y = (c.y - l[4] * z) / l[2];
  return Vec3<Real>((c.x - l[1] * y - l[3] * z) / l[0], y, z);
}
template <class Real>
TALUS_HD inline Vec3<Real> lower_times(const Real l[6], const Vec3<Real>& s) {
  return Vec3<Real>(l[0] * s.x, l[1] * s.x + l[2] * s.y, l[3] * s.x + l[4] * s.y + l[5] * s.z);
}

// Moves x_o to the analytic centre of the m planes n_i . x <= h_i, whose slacks at x_o are
// ws.plane_offset (all positive): the minimum of -sum log(slack), by damped Newton steps that keep
// every slack positive, the slacks updated to the new x_o. Returns false when it cannot (a
// singular Hessian: the planes do not bound the point).
template <class Real, class Workspace>
TALUS_HD inline bool analytic_centre_shift(Workspace& ws, int m, Vec3<Real>& x_o) {
  const Vec3<Real>* n = ws.hull.plane_normal;
  Real* slack = ws.plane_offset;
  for (int iteration = 0; iteration < 60; ++iteration) {
    Vec3<Real> g;
    Real h[6];
    barrier_derivatives(ws, m, g, h);
    // Delta = -H^-1 g. Near a thin slab H is as ill-conditioned as (width / depth)^2, ~1e12 for
    // a slab of 3e-9 m under faces of 3 mm: Cramer's rule then loses the determinant's sign
    // (the side planes' terms cancel under the slab's), elimination with the largest pivot first
    // does not (solve_spd3).
    Vec3<Real> delta;
    if (!solve_spd3(h, g * Real(-1), delta)) return false;
    const Real decrement = -dot(g, delta);  // the Newton decrement squared
    Real t = 1;
    for (int halving = 0; halving < 60; ++halving, t *= Real(0.5)) {
      bool inside = true;
      for (int i = 0; i < m && inside; ++i) inside = slack[i] - t * dot(n[i], delta) > Real(0);
      if (inside) break;
    }
    for (int i = 0; i < m; ++i) slack[i] -= t * dot(n[i], delta);
    x_o += delta * t;
    if (!(decrement > Real(64) * Eps<Real>::value)) return true;
  }
  return true;
}

}  // namespace overlap_detail
}  // namespace talus
