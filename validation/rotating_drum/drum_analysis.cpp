#include "validation/rotating_drum/drum_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace talus::validation {
namespace {

constexpr double kDegree = 180.0 / 3.14159265358979323846;

double squared(double x) {
  return x * x;
}

double distance_squared(const PlanePoint& p, const PlanePoint& q) {
  return squared(p.a - q.a) + squared(p.b - q.b);
}

}  // namespace

VelocityField::VelocityField(int cells, double cell)
    : cells_(cells),
      cell_(cell),
      sum_u_(std::size_t(cells) * cells, 0.0),
      sum_w_(std::size_t(cells) * cells, 0.0),
      count_(std::size_t(cells) * cells, 0) {}

void VelocityField::add(const PlanePoint& at, double u, double w) {
  const double half = 0.5 * cells_ * cell_;
  const double fi = std::floor((at.a + half) / cell_), fj = std::floor((at.b + half) / cell_);
  if (!(fi >= 0 && fi < cells_ && fj >= 0 && fj < cells_)) return;  // outside, or NaN
  const int k = index(static_cast<int>(fi), static_cast<int>(fj));
  sum_u_[k] += u;
  sum_w_[k] += w;
  ++count_[k];
}

PlanePoint VelocityField::centre(int i, int j) const {
  const double half = 0.5 * cells_ * cell_;
  return {(i + 0.5) * cell_ - half, (j + 0.5) * cell_ - half};
}

double VelocityField::mean_u(int i, int j) const {
  const int k = index(i, j);
  return count_[k] > 0 ? sum_u_[k] / double(count_[k]) : 0.0;
}

double VelocityField::mean_w(int i, int j) const {
  const int k = index(i, j);
  return count_[k] > 0 ? sum_w_[k] / double(count_[k]) : 0.0;
}

double field_r_squared(const VelocityField& measured, const VelocityField& truth, int min_samples,
                       int* used) {
  struct Cell {
    double mu, mw, tu, tw;
  };
  std::vector<Cell> cells;
  const int n = std::min(measured.cells(), truth.cells());
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (measured.count(i, j) >= min_samples && truth.count(i, j) >= min_samples)
        cells.push_back(
            {measured.mean_u(i, j), measured.mean_w(i, j), truth.mean_u(i, j), truth.mean_w(i, j)});
  if (used) *used = static_cast<int>(cells.size());
  if (cells.empty()) return std::numeric_limits<double>::quiet_NaN();
  double mean_u = 0, mean_w = 0;
  for (const Cell& c : cells) mean_u += c.tu, mean_w += c.tw;
  mean_u /= double(cells.size());
  mean_w /= double(cells.size());
  double residual = 0, spread = 0;
  for (const Cell& c : cells) {
    residual += squared(c.mu - c.tu) + squared(c.mw - c.tw);
    spread += squared(c.tu - mean_u) + squared(c.tw - mean_w);
  }
  return spread > 0 ? 1 - residual / spread : std::numeric_limits<double>::quiet_NaN();
}

double repose_angle(const std::vector<PlanePoint>& centres, double strip, double half_width,
                    double neighbour) {
  const int strips = std::max(1, static_cast<int>(std::floor(2 * half_width / strip)));
  std::vector<double> top(strips, -std::numeric_limits<double>::infinity());
  const double reach = squared(neighbour);
  for (std::size_t k = 0; k < centres.size(); ++k) {
    const PlanePoint& p = centres[k];
    const double f = std::floor((p.a + half_width) / strip);
    if (!(f >= 0 && f < strips)) continue;
    const int s = static_cast<int>(f);
    if (p.b <= top[s]) continue;
    bool touches = false;
    for (std::size_t m = 0; m < centres.size() && !touches; ++m)
      touches = m != k && distance_squared(p, centres[m]) <= reach;
    if (touches) top[s] = p.b;
  }
  // Least squares b = slope a + c through the strips' tops, a at the strips' centres.
  double sa = 0, sb = 0, saa = 0, sab = 0;
  int used = 0;
  for (int s = 0; s < strips; ++s) {
    if (!std::isfinite(top[s])) continue;
    const double a = -half_width + (s + 0.5) * strip;
    sa += a, sb += top[s], saa += a * a, sab += a * top[s];
    ++used;
  }
  if (used < 3) return std::numeric_limits<double>::quiet_NaN();
  const double slope = (used * sab - sa * sb) / (used * saa - sa * sa);
  return std::atan(std::abs(slope)) * kDegree;
}

double highest_lift(const std::vector<PlanePoint>& centres, double radius, double band,
                    bool rising_right) {
  double best = -90;
  for (const PlanePoint& p : centres) {
    const double a = rising_right ? p.a : -p.a;
    if (a <= 0 || std::hypot(p.a, p.b) < radius - band) continue;
    best = std::max(best, std::atan2(p.b, a) * kDegree);
  }
  return best;
}

std::vector<std::pair<int, int>> match_nearest(const std::vector<PlanePoint>& from,
                                               const std::vector<PlanePoint>& to,
                                               double max_distance) {
  // Brute force: a few hundred particles a frame. nearest_to[m]: the index in `from` nearest to
  // to[m]; a pair stands when the nearest relation goes both ways.
  const auto nearest = [](const PlanePoint& p, const std::vector<PlanePoint>& in) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < in.size(); ++k) {
      const double d = distance_squared(p, in[k]);
      if (d < best_d) best_d = d, best = static_cast<int>(k);
    }
    return std::pair<int, double>{best, best_d};
  };
  std::vector<std::pair<int, int>> pairs;
  const double reach = squared(max_distance);
  for (std::size_t k = 0; k < from.size(); ++k) {
    const auto [m, d] = nearest(from[k], to);
    if (m < 0 || d > reach) continue;
    if (nearest(to[m], from).first == static_cast<int>(k)) pairs.emplace_back(int(k), m);
  }
  return pairs;
}

}  // namespace talus::validation
