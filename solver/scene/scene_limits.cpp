#include "solver/scene/scene_limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace talus {

std::string describe_limit(long long limit) {
  // A power of two or one less than it is written as such, with its digits.
  for (int k = 1; k < 63; ++k) {
    if (limit == (1LL << k)) return fmt::format("2^{} = {}", k, limit);
    if (limit == (1LL << k) - 1) return fmt::format("2^{} - 1 = {}", k, limit);
  }
  if (limit == kMaxSeed) return fmt::format("2^63 - 1 = {}", limit);
  return std::to_string(limit);
}

std::string step_count_problem(double end_time, double time_step) {
  const double steps = std::round(end_time / time_step);
  // Also catches inf (a tiny step under a huge end); NaN cannot reach here (both are > 0).
  if (steps <= double(kMaxSteps)) return "";
  return fmt::format(
      "an end time of {:.6g} s is {:.3g} steps of {:.6g} s, above the limit of {} steps (the "
      "step index and the time stay exact in a double up to it)",
      end_time, steps, time_step, describe_limit(kMaxSteps));
}

long long checked_step_count(double end_time, double time_step, const std::string& what) {
  const std::string problem = step_count_problem(end_time, time_step);
  if (!problem.empty()) throw std::overflow_error(what + ": " + problem);
  return std::llround(end_time / time_step);
}

long long scene_step_count(const Scene& scene) {
  return checked_step_count(scene.end_time, scene.time_step, "time.end");
}

std::array<double, 3> lattice_dimensions(const Region& box, const Vec3d& spacing) {
  std::array<double, 3> count{};
  for (int k = 0; k < 3; ++k) {
    // Points whose cell [i, i + 1) spacing lies in the box; the relative slack keeps a box
    // written as an exact multiple of the spacing from losing its last point to round-off.
    const double size = box.box_max[k] - box.box_min[k];
    count[k] = std::max(1.0, std::floor(size / spacing[k] * (1 + 1e-12)));
  }
  return count;
}

double lattice_point_count(const Region& box, const Vec3d& spacing) {
  const std::array<double, 3> n = lattice_dimensions(box, spacing);
  return n[0] * n[1] * n[2];
}

double feed_particle_count(double rate, double start, double stop) {
  return std::floor(rate * (stop - start));
}

double scene_particle_count(const Scene& scene) {
  double count = double(scene.particles.size());
  for (const LatticeRequest& l : scene.lattices) count += lattice_point_count(l.region, l.spacing);
  for (const RandomFillRequest& f : scene.random_fills) count += double(f.count);
  for (const FeedRequest& f : scene.feeds) count += feed_particle_count(f.rate, f.start, f.stop);
  return count;
}

}  // namespace talus
