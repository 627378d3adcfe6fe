// Wall motion: rigid transforms at time t and velocities of points on the wall, against closed
// forms (quarter and whole turns at the scene's rpm, straight-line translation).
#include <gtest/gtest.h>

#include <cmath>

#include "solver/scene/wall_motion.hpp"
#include "tests/scene/wall_test_util.hpp"

namespace talus {
namespace {

// Positions are a rotation of O(1) vectors (a few ulps) plus a translation: 1e-14 m on
// coordinates of order 1.
constexpr double kRoundOff = 1e-14;

void expect_point(const Vec3d& actual, const Vec3d& expected, double tolerance = kRoundOff) {
  EXPECT_NEAR(norm(actual - expected), 0, tolerance)
      << "got (" << actual.x << ", " << actual.y << ", " << actual.z << ")";
}

WallMotion rotation(const Vec3d& axis, const Vec3d& point, double rpm) {
  WallMotion motion;
  motion.kind = WallMotion::Kind::rotation;
  motion.axis = axis;
  motion.point = point;
  motion.rpm = rpm;
  return motion;
}

TEST(WallMotion, QuarterTurnAtTheRpmAfterAQuarterPeriod) {
  // 30 rpm: one turn in 2 s, a quarter turn in 0.5 s. About +z through (1, 2, 3), right-handed:
  // the point one radius along +x goes to one radius along +y.
  const WallMotion motion = rotation({0, 0, 1}, {1, 2, 3}, 30);
  EXPECT_NEAR(motion.angular_speed(), M_PI, 1e-15);
  const RigidTransform quarter = wall_transform(motion, 0.5);
  expect_point(quarter.apply({1.5, 2, 7}), {1, 2.5, 7});
  expect_point(quarter.apply({1, 2, -4}), {1, 2, -4});  // on the axis: stays
  // Negative rpm turns the other way; a whole period brings every point back.
  expect_point(wall_transform(rotation({0, 0, 1}, {1, 2, 3}, -30), 0.5).apply({1.5, 2, 7}),
               {1, 1.5, 7});
  expect_point(wall_transform(motion, 2.0).apply({1.5, 2, 7}), {1.5, 2, 7});
  expect_point(wall_transform(motion, 0).apply({1.5, 2, 7}), {1.5, 2, 7});
}

TEST(WallMotion, TiltedAxisKeepsDistancesAndTheAxis) {
  const Vec3d axis = Vec3d(1, -2, 2) / 3.0, point(0.1, 0.2, -0.3);
  const WallMotion motion = rotation(axis, point, 17);
  // A third of a turn at 17 rpm takes (60 / 17) / 3 s; compare with Rodrigues' formula.
  const double t = 60.0 / 17 / 3, angle = 2 * M_PI / 3;
  const Vec3d x0(0.4, -0.1, 0.25), d = x0 - point;
  const Vec3d rodrigues = d * std::cos(angle) + cross(axis, d) * std::sin(angle) +
                          axis * (dot(axis, d) * (1 - std::cos(angle)));
  expect_point(wall_transform(motion, t).apply(x0), point + rodrigues);
  expect_point(wall_transform(motion, t).apply(point + axis * 2.0), point + axis * 2.0);
}

TEST(WallMotion, TranslationAndNoMotion) {
  WallMotion motion;
  motion.kind = WallMotion::Kind::translation;
  motion.velocity = {0.01, -0.02, 0.5};
  expect_point(wall_transform(motion, 2.0).apply({1, 1, 1}), {1.02, 0.96, 2});
  expect_point(wall_point_velocity(motion, 3.0, {5, 5, 5}), motion.velocity);
  expect_point(wall_angular_velocity(motion), {});
  const WallMotion still;
  expect_point(wall_transform(still, 7.0).apply({1, 2, 3}), {1, 2, 3});
  expect_point(wall_point_velocity(still, 7.0, {1, 2, 3}), {});
}

TEST(WallMotion, PointVelocityMatchesTheMotionOfThePoint) {
  const Vec3d axis = Vec3d(2, 3, 6) / 7.0;
  const WallMotion motion = rotation(axis, {0.05, 0, 0.02}, 45);
  const Vec3d x0(0.1, -0.03, 0.07);
  const double t = 0.37, h = 1e-5;
  const Vec3d x = wall_transform(motion, t).apply(x0);
  const Vec3d v = wall_point_velocity(motion, t, x);
  // Central difference of the position: error w^3 r h^2 / 6 ~ 1e-9 m/s (w = 4.7 rad/s, r ~ 0.1 m)
  // plus round-off 1e-16 / h ~ 1e-11 m/s; 1e-8 m/s bounds both.
  const Vec3d difference =
      (wall_transform(motion, t + h).apply(x0) - wall_transform(motion, t - h).apply(x0)) / (2 * h);
  expect_point(v, difference, 1e-8);
  // Speed w times the distance from the axis (closed form).
  const Vec3d d = x - motion.point;
  const double r = norm(d - axis * dot(d, axis));
  EXPECT_NEAR(norm(v), motion.angular_speed() * r, 1e-14);
}

TEST(WallMotion, MovedMeshKeepsItsWindingAndTurnsItsNormals) {
  TriangleMesh floor;
  floor.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  floor.triangles = {{0, 1, 2}};  // normal +z
  // A quarter turn about +x (15 rpm: 1 s): +z goes to -y.
  const TriangleMesh moved =
      transformed(floor, wall_transform(rotation({1, 0, 0}, {0, 0, 0}, 15), 1.0));
  expect_point(triangle_normal(moved, 0), {0, -1, 0});
}

WallMotion oscillation(const Vec3d& direction, double amplitude, double frequency, double start,
                       int cycles) {
  WallMotion motion;
  motion.kind = WallMotion::Kind::oscillation;
  motion.direction = direction;
  motion.amplitude = amplitude;
  motion.frequency = frequency;
  motion.start = start;
  motion.cycles = cycles;
  return motion;
}

// The raised cosine d(t) = A (1 - cos 2 pi f (t - start)) along the direction for `cycles` whole
// cycles: still before the start, A up after a quarter cycle (at the peak speed A 2 pi f), 2A up
// at the half (at rest), back at the rest position with speed zero after each whole cycle and
// for good after the last.
TEST(WallMotion, OscillationIsARaisedCosineForItsCycles) {
  const Vec3d up(0, 0.6, 0.8);
  const double a = 0.002, f = 25, start = 0.1;  // 40 ms a cycle
  const WallMotion motion = oscillation(up, a, f, start, 3);
  const double w = 2 * M_PI * f;
  const Vec3d x0(0.3, -0.2, 0.1);
  const auto at = [&](double t) { return wall_transform(motion, t).apply(x0); };
  expect_point(at(0), x0);
  expect_point(at(start), x0);
  expect_point(wall_point_velocity(motion, start, x0), {});
  expect_point(at(start + 0.01), x0 + up * a);  // a quarter cycle
  expect_point(wall_point_velocity(motion, start + 0.01, x0), up * (a * w), 1e-12);
  expect_point(at(start + 0.02), x0 + up * (2 * a));  // half a cycle: the top
  expect_point(wall_point_velocity(motion, start + 0.02, x0), {}, 1e-15);
  expect_point(at(start + 0.03), x0 + up * a);  // going down at the peak speed
  expect_point(wall_point_velocity(motion, start + 0.03, x0), up * (-a * w), 1e-12);
  expect_point(at(start + 0.04), x0, 1e-15);                // a whole cycle: back
  expect_point(at(start + 0.1), x0 + up * (2 * a), 1e-15);  // the third cycle's top
  // After the third cycle (t > start + 0.12) the wall rests where it started.
  expect_point(at(start + 0.12 + 1e-9), x0);
  expect_point(wall_point_velocity(motion, start + 0.13, x0), {});
  expect_point(at(5.0), x0);
  expect_point(wall_angular_velocity(motion), {});
  // Without a number of cycles it goes on.
  expect_point(wall_transform(oscillation(up, a, f, start, 0), start + 4.02).apply(x0),
               x0 + up * (2 * a), 1e-14);
}

TEST(WallMotion, OscillationVelocityIsTheRateOfItsDisplacement) {
  const WallMotion motion = oscillation({0, 0, 1}, 0.001, 40, 0.05, 10);
  const Vec3d x0(0, 0, 0);
  const double h = 1e-7;
  for (const double t : {0.0513, 0.0671, 0.0802, 0.1234, 0.2899}) {
    // Central difference: error A w^3 h^2 / 6 ~ 2.6e-12 m/s (A = 1 mm, w = 251 rad/s) plus
    // round-off 1e-19 m / h ~ 1e-12 m/s; the speed is at most A w = 0.25 m/s. 1e-10 bounds both.
    const Vec3d difference =
        (wall_transform(motion, t + h).apply(x0) - wall_transform(motion, t - h).apply(x0)) /
        (2 * h);
    expect_point(wall_point_velocity(motion, t, x0), difference, 1e-10);
  }
}

}  // namespace
}  // namespace talus
