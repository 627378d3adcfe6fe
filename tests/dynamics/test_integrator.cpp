// The production integrator (solver/dynamics/integrator.hpp) on closed-form cases.
#include <gtest/gtest.h>

#include <cmath>

#include "solver/dynamics/body_forces.hpp"
#include "solver/dynamics/integrator.hpp"

namespace talus {
namespace {

// Velocity Verlet is exact for a constant force: x = x0 + v0 t + a t^2 / 2 after any number of
// steps, up to the round-off of 1000 additions (1e-13 relative).
TEST(Integrator, VelocityVerletIsExactUnderConstantForce) {
  Vec3d x(1, 2, 3), v(0.5, -0.25, 2), a0;
  const Vec3d force(0, 0, -9.81 * 2);
  const double mass = 2, dt = 1e-3;
  for (int k = 0; k < 1000; ++k) {
    begin_translation(x, v, force, mass, dt, a0);
    end_translation(v, force, mass, dt, a0);
  }
  const double t = 1.0;
  EXPECT_NEAR(x.x, 1 + 0.5 * t, 1e-12);
  EXPECT_NEAR(x.y, 2 - 0.25 * t, 1e-12);
  EXPECT_NEAR(x.z, 3 + 2 * t - 0.5 * 9.81 * t * t, 1e-12);
  EXPECT_NEAR(v.z, 2 - 9.81 * t, 1e-12);
}

// Quadratic drag opposes the velocity with magnitude alpha v^2.
TEST(BodyForces, DragOpposesTheVelocityQuadratically) {
  const Vec3d f = quadratic_drag_force(0.5, Vec3d(3, 0, -4));
  EXPECT_DOUBLE_EQ(f.x, -0.5 * 5 * 3);
  EXPECT_DOUBLE_EQ(f.z, 0.5 * 5 * 4);
  EXPECT_DOUBLE_EQ(gravity_force(2.0, Vec3d(0, 0, -9.81)).z, -19.62);
}

// A free asymmetric top (the intermediate axis, where explicit schemes drift fastest): the
// implicit-midpoint rotation keeps the kinetic energy and the world-frame angular momentum to
// round-off over 1e4 steps (bound 1e-12 relative: 1e4 steps of ~1e-16 each, with margin).
TEST(Integrator, FreeRotationConservesEnergyAndAngularMomentum) {
  const Vec3d inertia(1.0, 2.0, 3.0);
  Quatd q = Quatd::from_axis_angle(Vec3d(0.6, 0.0, 0.8), 0.3);
  Vec3d w(0.01, 5.0, 0.02);
  const auto energy = [&] {
    return 0.5 * (inertia.x * w.x * w.x + inertia.y * w.y * w.y + inertia.z * w.z * w.z);
  };
  const auto momentum = [&] {
    return rotate(q, Vec3d(inertia.x * w.x, inertia.y * w.y, inertia.z * w.z));
  };
  const double e0 = energy();
  const Vec3d l0 = momentum();
  Vec3d t0;
  for (int k = 0; k < 10000; ++k) {
    ASSERT_TRUE(begin_rotation(q, w, Vec3d(), inertia, 1e-3, t0));
    end_rotation(q, w, Vec3d(), inertia, 1e-3, t0);
  }
  EXPECT_NEAR(energy(), e0, 1e-12 * e0);
  EXPECT_LT(norm(momentum() - l0), 1e-12 * norm(l0));
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  // It really tumbled: the intermediate axis is unstable, w left the y axis.
  EXPECT_GT(std::abs(w.x) + std::abs(w.z), 0.1);
}

// A constant torque about a principal axis of a body at rest: w = T t / I and the angle
// T t^2 / (2 I), both exact for the kick-drift-kick splitting (up to round-off).
TEST(Integrator, ConstantTorqueAboutAPrincipalAxis) {
  const Vec3d inertia(2.0, 2.0, 4.0);
  Quatd q;
  Vec3d w, t0;
  const Vec3d torque(0, 0, 0.8);
  for (int k = 0; k < 500; ++k) {
    ASSERT_TRUE(begin_rotation(q, w, torque, inertia, 1e-3, t0));
    end_rotation(q, w, torque, inertia, 1e-3, t0);
  }
  EXPECT_NEAR(w.z, 0.8 * 0.5 / 4.0, 1e-13);
  // The midpoint rotation turns by 2 atan(w_m dt / 2) per step instead of w_m dt: relative
  // O((w dt)^2 / 12) = 1e-10 here.
  const double angle = 2 * std::atan2(q.z, q.w);
  EXPECT_NEAR(angle, 0.8 * 0.25 / (2 * 4.0), 1e-9);
}

// A spin too fast for the step: the fixed point does not converge and the state is kept.
TEST(Integrator, RotationTooFastForTheStepIsReported) {
  Quatd q;
  Vec3d w(1e4, 2e4, 0.0);
  const Vec3d before = w;
  EXPECT_FALSE(rotate_torque_free_midpoint(q, w, Vec3d(1, 2, 3), 1.0));
  EXPECT_EQ(w.x, before.x);
  EXPECT_EQ(q.w, 1.0);
}

}  // namespace
}  // namespace talus
