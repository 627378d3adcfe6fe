#include "solver/contact/damping_calibration.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace talus {

namespace {

// The normalised contact force of the impact (no tension).
double impact_acceleration(double beta, double q, double v) {
  const double push = std::cbrt(q > 0 ? q : 0.0) + beta * v;
  return push > 0 ? -push : 0.0;
}

}  // namespace

double normalised_impact_restitution(double beta) {
  const double h = 2e-4;
  double q = 0, v = 1;
  for (long step = 0; step < 100000000; ++step) {
    const double a1 = impact_acceleration(beta, q, v), d1 = v;
    const double a2 = impact_acceleration(beta, q + 0.5 * h * d1, v + 0.5 * h * a1);
    const double d2 = v + 0.5 * h * a1;
    const double a3 = impact_acceleration(beta, q + 0.5 * h * d2, v + 0.5 * h * a2);
    const double d3 = v + 0.5 * h * a2;
    const double a4 = impact_acceleration(beta, q + h * d3, v + h * a3), d4 = v + h * a3;
    q += h / 6 * (d1 + 2 * d2 + 2 * d3 + d4);
    v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    if (v < 0 && (q <= 0 || impact_acceleration(beta, q, v) == 0)) return -v;
  }
  throw std::runtime_error("damping calibration: the normalised impact did not end");
}

double calibrated_damping_ratio_for(double restitution) {
  if (!(restitution > 0 && restitution <= 1)) {
    throw std::invalid_argument("damping calibration: restitution must be in (0, 1], got " +
                                std::to_string(restitution));
  }
  if (restitution == 1) return 0;
  // The rebound speed falls monotonically from 1 (beta = 0) as beta grows.
  double lo = 0, hi = 1;
  while (normalised_impact_restitution(hi) > restitution) lo = hi, hi *= 2;
  while (hi - lo > 1e-10 * hi) {
    const double mid = 0.5 * (lo + hi);
    (normalised_impact_restitution(mid) > restitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace talus
