// Chebyshev centre of an intersection of half-spaces dot(n_i, x) <= h_i (unit n_i): the point
// deepest inside, found by the small linear program
//     maximise t  subject to  dot(n_i, x) + t <= h_i  (all i),  t <= t_cap,
// in the four unknowns (x, t). The polar transform of §2.3 (Eqs. 4-5) needs a reference point
// strictly inside the intersection; the deepest point keeps every dual point as short as possible
// (|y_i| = 1/(h_i - n_i.x) <= 1/t), which is the best conditioning the dual hull can have, and
// t itself says separate (t < 0), touching (t ~ 0) or overlapping (t > 0).
//
// Method: the active-set (primal simplex) method for an LP in inequality form. The iterate stays
// feasible; the active set W holds at most four linearly independent constraints. While c = e_t
// has a component outside span(W) we move along its projection onto null(W) until a constraint
// blocks; otherwise the multipliers of c = W^T lambda decide: all >= 0 is optimal, else the
// constraint with the most negative multiplier leaves W.
#pragma once

#include "solver/core/math.hpp"
#include "solver/core/vec3.hpp"

#include <cmath>

namespace talus {

template <class Real>
struct ChebyshevResult {
  Vec3<Real> center;
  Real depth = 0;  // t: distance from center to the nearest plane (negative: infeasible)
  int iterations = 0;
  bool converged = false;
};

namespace lp_detail {

// Solves the k x k symmetric system G y = r (k <= 4) by Gaussian elimination with partial
// pivoting. Returns false when G is numerically singular.
template <class Real>
TALUS_HD inline bool solve_small(Real g[4][4], Real* r, int k) {
  for (int col = 0; col < k; ++col) {
    int pivot = col;
    for (int row = col + 1; row < k; ++row)
      if (abs_of(g[row][col]) > abs_of(g[pivot][col])) pivot = row;
    // Entries are O(1) (unit normals). A pivot can be as small as the square of the sine of the
    // angle between nearly parallel planes, which the ratio test admits down to ~(1e2 eps)^2.
    if (!(abs_of(g[pivot][col]) > Eps<Real>::value * Eps<Real>::value)) return false;
    if (pivot != col) {
      for (int j = 0; j < k; ++j) swap_of(g[col][j], g[pivot][j]);
      swap_of(r[col], r[pivot]);
    }
    for (int row = col + 1; row < k; ++row) {
      const Real f = g[row][col] / g[col][col];
      for (int j = col; j < k; ++j) g[row][j] -= f * g[col][j];
      r[row] -= f * r[col];
    }
  }
  for (int row = k - 1; row >= 0; --row) {
    Real v = r[row];
    for (int j = row + 1; j < k; ++j) v -= g[row][j] * r[j];
    r[row] = v / g[row][row];
  }
  return true;
}

// Row of constraint i in 4-D: (n_i, 1) for a plane, (0, 0, 0, 1) for the cap (index m).
template <class Real, class Calc>
TALUS_HD inline void constraint_row(const Vec3<Real>* normals, int m, int i, Calc* row) {
  if (i == m) {
    row[0] = row[1] = row[2] = 0;
  } else {
    row[0] = normals[i].x;
    row[1] = normals[i].y;
    row[2] = normals[i].z;
  }
  row[3] = 1;
}

}  // namespace lp_detail

// normals[i] unit, offsets[i] = h_i; m planes. `start` is any point (the iterate starts feasible
// at (start, min_i slack)); t_cap bounds t (an upper bound of the inradius, e.g. the smaller
// bounding radius) so the program is bounded even when the planes are not.
// The arithmetic is done in Calc (double by default, also for float planes): the multipliers come
// from normal equations, whose conditioning is the square of the planes' (nearly parallel faces,
// 1/sin^2 of their angle), which float cannot carry; four unknowns cost little in double.
template <class Real, class Calc = double>
TALUS_HD inline ChebyshevResult<Real> chebyshev_center(const Vec3<Real>* normals,
                                                       const Real* offsets, int m,
                                                       const Vec3<Real>& start, Real t_cap,
                                                       int max_iterations) {
  using lp_detail::constraint_row;
  ChebyshevResult<Real> result;
  Calc z[4] = {Calc(start.x), Calc(start.y), Calc(start.z), Calc(t_cap)};
  int first_active = m;  // the cap
  for (int i = 0; i < m; ++i) {
    const Calc slack = Calc(offsets[i]) - dot(Vec3<Calc>(normals[i]), Vec3<Calc>(start));
    if (slack < z[3]) {
      z[3] = slack;
      first_active = i;
    }
  }
  int active[4] = {first_active, 0, 0, 0};
  int k = 1;

  const int bland_after = max_iterations / 2;
  for (int it = 0; it < max_iterations; ++it) {
    result.iterations = it + 1;
    Calc rows[4][4];
    for (int a = 0; a < k; ++a) constraint_row(normals, m, active[a], rows[a]);
    // Multipliers of the least-squares fit c ~ W^T lambda, c = e_t: (W W^T) lambda = W c.
    Calc gram[4][4];
    Calc lambda[4];
    for (int a = 0; a < k; ++a) {
      for (int b = 0; b < k; ++b)
        gram[a][b] = rows[a][0] * rows[b][0] + rows[a][1] * rows[b][1] + rows[a][2] * rows[b][2] +
                     rows[a][3] * rows[b][3];
      lambda[a] = rows[a][3];
    }
    if (!lp_detail::solve_small(gram, lambda, k)) break;  // dependent rows: keep the iterate
    // Direction: projection of c onto null(W), d = c - W^T lambda.
    Calc d[4] = {0, 0, 0, 1};
    for (int a = 0; a < k; ++a)
      for (int j = 0; j < 4; ++j) d[j] -= lambda[a] * rows[a][j];
    const Calc d_norm2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + d[3] * d[3];
    // Four independent active rows leave no direction (a nonzero d is round-off then).
    if (k == 4 || d_norm2 <= Calc(1e6) * Eps<Calc>::value * Eps<Calc>::value) {  // |d| <= 1e3 eps
      // c lies in span(W): optimal unless a multiplier is negative. The most negative leaves
      // (Dantzig). Bland's lowest-index rule, which provably never cycles for vertex-to-vertex
      // pivots, did cycle here between a vertex and an edge direction on nearly parallel planes
      // (float, degenerate zero steps); after `bland_after` iterations it takes over anyway.
      const bool bland = it >= bland_after;
      int leave = -1;
      for (int a = 0; a < k; ++a)
        if (lambda[a] < -Calc(1e2) * Eps<Calc>::value &&
            (leave < 0 || (bland ? active[a] < active[leave] : lambda[a] < lambda[leave])))
          leave = a;
      if (leave < 0) {
        result.converged = true;
        break;
      }
      active[leave] = active[k - 1];
      --k;
      continue;
    }
    // Ratio test along d (Bland: ties go to the lowest index).
    Calc step = Calc(-1);
    int enter = -1;
    for (int i = 0; i <= m; ++i) {
      bool is_active = false;
      for (int a = 0; a < k; ++a) is_active |= (active[a] == i);
      if (is_active) continue;
      Calc row[4];
      constraint_row(normals, m, i, row);
      const Calc rate = row[0] * d[0] + row[1] * d[1] + row[2] * d[2] + row[3] * d[3];
      if (rate <= Calc(1e2) * Eps<Calc>::value * std::sqrt(d_norm2)) continue;
      Calc slack = Calc(i == m ? t_cap : offsets[i]) -
                   (row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + z[3]);
      if (slack < 0) slack = 0;  // round-off of an iterate sitting on the plane
      const Calc ratio = slack / rate;
      if (enter < 0 || ratio < step) {
        step = ratio;
        enter = i;
      }
    }
    if (enter < 0) break;  // cannot happen with the cap; keep the feasible iterate
    for (int j = 0; j < 4; ++j) z[j] += step * d[j];
    active[k++] = enter;
  }
  // The depth at the centre as returned (rounded to Real): exactly the smallest slack.
  result.center = Vec3<Real>(Vec3<Calc>(z[0], z[1], z[2]));
  const Vec3<Calc> center(result.center);
  Calc depth = Calc(t_cap);
  for (int i = 0; i < m; ++i)
    depth = min_of(depth, Calc(offsets[i]) - dot(Vec3<Calc>(normals[i]), center));
  result.depth = Real(depth);
  return result;
}

}  // namespace talus
