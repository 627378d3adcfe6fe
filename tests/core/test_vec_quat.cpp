// The core value types every kernel builds on: vectors, quaternions, rotation matrices.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "solver/core/quat.hpp"

namespace talus {
namespace {

// Double round-off of a few operations on unit-size numbers: 1e-15 is a few ulps.
constexpr double kTight = 1e-15;

Quatd random_unit_quaternion(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  return Quatd(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
}

TEST(Vec3, CrossAndTripleProductFollowTheRightHandRule) {
  const Vec3d x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  EXPECT_EQ(cross(x, y).z, 1.0);
  EXPECT_EQ(cross(y, x).z, -1.0);
  EXPECT_EQ(triple(x, y, z), 1.0);
  EXPECT_EQ(norm(Vec3d(3, 4, 12)), 13.0);
}

TEST(Quat, RotationAgreesWithItsMatrixAndItsInverse) {
  std::mt19937_64 rng(4);
  for (int k = 0; k < 1000; ++k) {
    const Quatd q = random_unit_quaternion(rng);
    const Vec3d v(0.3, -1.2, 2.5);
    const Mat3<double> r = rotation_matrix(q);
    EXPECT_LT(norm(rotate(q, v) - r * v), kTight * 4 * norm(v));
    EXPECT_LT(norm(rotate_inverse(q, rotate(q, v)) - v), kTight * 4 * norm(v));
    EXPECT_LT(norm(r.transpose_times(r * v) - v), kTight * 4 * norm(v));
    EXPECT_NEAR(norm(rotate(q, v)), norm(v), kTight * 4 * norm(v));  // a rotation keeps length
  }
}

TEST(Quat, CompositionAppliesTheRightFactorFirst) {
  const double half_pi = std::acos(0.0);
  const Quatd about_z = Quatd::from_axis_angle({0, 0, 1}, half_pi);
  const Quatd about_x = Quatd::from_axis_angle({1, 0, 0}, half_pi);
  // (about_x * about_z) v = about_x (about_z v): x -> y (about z) -> z (about x).
  const Vec3d v = rotate(about_x * about_z, Vec3d(1, 0, 0));
  EXPECT_NEAR(v.x, 0, kTight);
  EXPECT_NEAR(v.y, 0, kTight);
  EXPECT_NEAR(v.z, 1, kTight);
}

TEST(Finite, RejectsInfinitiesAndNaNs) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(is_finite(1e308));
  EXPECT_FALSE(is_finite(inf));
  EXPECT_FALSE(is_finite(std::nan("")));
  EXPECT_FALSE(is_finite(Vec3d(0, inf, 0)));
  EXPECT_FALSE(is_finite(Quatd(1, 0, std::nan(""), 0)));
  EXPECT_TRUE(is_finite(Quatd()));
}

}  // namespace
}  // namespace talus
