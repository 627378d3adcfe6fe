#include "tests/support/random_poses.hpp"

#include <cmath>
#include <stdexcept>

namespace talus {
namespace {

constexpr double kPi = 3.14159265358979323846;

double uniform(std::mt19937_64& rng, double low, double high) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}

}  // namespace

Vec3d random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (;;) {
    const Vec3d v{gauss(rng), gauss(rng), gauss(rng)};
    const double length = norm(v);
    if (length > 1e-6) return v / length;
  }
}

Quatd random_rotation(std::mt19937_64& rng) {
  const double u1 = uniform(rng, 0, 1), u2 = uniform(rng, 0, 1), u3 = uniform(rng, 0, 1);
  const double r1 = std::sqrt(1 - u1), r2 = std::sqrt(u1);
  const double t1 = 2 * kPi * u2, t2 = 2 * kPi * u3;
  return Quatd(r2 * std::cos(t2), r1 * std::sin(t1), r1 * std::cos(t1), r2 * std::sin(t2))
      .normalized();
}

std::vector<Vec3d> random_convex_cloud(std::mt19937_64& rng, int n_points, double size) {
  if (n_points < 4) throw std::invalid_argument("random_convex_cloud: needs at least 4 points");
  const Vec3d semi_axes{uniform(rng, 0.25, 0.5) * size, uniform(rng, 0.25, 0.5) * size,
                        uniform(rng, 0.25, 0.5) * size};
  const Quatd axes = random_rotation(rng);
  std::vector<Vec3d> points;
  for (int i = 0; i < n_points; ++i) {
    const Vec3d d = random_direction(rng);
    // Radial factor near 1: a few points fall inside the hull, which the hull code must skip.
    const double r = uniform(rng, 0.85, 1.0);
    points.push_back(
        rotate(axes, Vec3d{d.x * semi_axes.x, d.y * semi_axes.y, d.z * semi_axes.z} * r));
  }
  return points;
}

Posed random_pose(std::mt19937_64& rng, double extent) {
  Posed pose;
  pose.position = {uniform(rng, -extent, extent), uniform(rng, -extent, extent),
                   uniform(rng, -extent, extent)};
  pose.orientation = random_rotation(rng);
  return pose;
}

PosePair random_overlapping_pair(std::mt19937_64& rng, double radius_a, double radius_b,
                                 double depth_fraction_min, double depth_fraction_max) {
  PosePair pair;
  pair.a = random_pose(rng, 4 * radius_a);  // up to two diameters from the origin per axis
  const double f = uniform(rng, depth_fraction_min, depth_fraction_max);
  pair.b.position = pair.a.position + random_direction(rng) * ((radius_a + radius_b) * (1 - f));
  pair.b.orientation = random_rotation(rng);
  return pair;
}

}  // namespace talus
