// Reference integrator against closed forms (issue 3): free fall with quadratic drag (BLAZE-DEM
// §5.1), the gravity parabola, and the torque-free asymmetric body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "reference/dynamics/effects.hpp"
#include "reference/dynamics/integrator.hpp"

namespace talus::reference {
namespace {

constexpr double kGravity = 9.81;

// Largest relative errors of the velocity and the fall height against BLAZE-DEM §5.1:
// v(t) = v_t tanh(g t / v_t), x(t) = (v_t^2 / g) ln cosh(g t / v_t), v_t = sqrt(m g / alpha).
struct DragErrors {
  double velocity = 0;
  double height = 0;
};

DragErrors free_fall_with_drag(double mass, double alpha, double dt) {
  const double terminal = std::sqrt(mass * kGravity / alpha);
  const double time_scale = terminal / kGravity;
  auto effects = [&](RigidBody& body) {
    add_gravity(body, Eigen::Vector3d(0, 0, -kGravity));
    add_quadratic_drag(body, alpha);
  };
  RigidBody body = RigidBody::with_mass_properties(mass, Eigen::Vector3d::Ones());
  effects(body);
  // Five time scales: v reaches tanh(5) = 99.99% of v_t, the whole transient.
  const long steps = std::lround(5 * time_scale / dt);
  DragErrors errors;
  for (long k = 1; k <= steps; ++k) {
    step(body, dt, RotationScheme::kImplicitMidpoint, effects);
    const double u = k * dt / time_scale;
    const double v = terminal * std::tanh(u);
    // ln cosh u = log1p(2 sinh^2(u/2)): no cancellation at small u, where x is tiny.
    const double half_sinh = std::sinh(0.5 * u);
    const double x = terminal * time_scale * std::log1p(2 * half_sinh * half_sinh);
    errors.velocity = std::max(errors.velocity, std::abs(-body.velocity.z() - v) / v);
    errors.height = std::max(errors.height, std::abs(-body.position.z() - x) / x);
  }
  return errors;
}

// BLAZE-DEM §5.1 gives alpha = 0.5 (kg/m) but neither the mass nor the time span (Fig. 13 only):
// m = 1 kg gives v_t = 4.43 m/s and g t / v_t = 1 at t = 0.45 s; the run covers 0 to 2.26 s.
// The bounds are BLAZE-DEM's: 0.1% at dt = 1e-3 s, 0.01% at 1e-4 s. Measured: 1.4e-6 and
// 1.4e-8 (v), 8.2e-7 and 8.2e-9 (x).
TEST(ReferenceIntegrator, FreeFallWithDragAtDt1e3) {
  const DragErrors errors = free_fall_with_drag(1, 0.5, 1e-3);
  EXPECT_LE(errors.velocity, 1e-3);
  EXPECT_LE(errors.height, 1e-3);
}

TEST(ReferenceIntegrator, FreeFallWithDragAtDt1e4) {
  const DragErrors errors = free_fall_with_drag(1, 0.5, 1e-4);
  EXPECT_LE(errors.velocity, 1e-4);
  EXPECT_LE(errors.height, 1e-4);
}

TEST(ReferenceIntegrator, FreeFallWithDragIsSecondOrder) {
  // Velocity Verlet with the drag evaluated at the predicted velocity is second order: ten times
  // smaller dt, a hundred times smaller error (measured 100.0). Evaluating it at the half-step
  // velocity instead (the usual DEM
  // split) gives 10.0, with errors 5.4e-4 and 5.4e-5 at m = 1 kg: BLAZE-DEM's 0.1% and 0.01%. A
  // light body (m = 0.1 kg, g t / v_t = 1 at 0.14 s) keeps the errors far above round-off at dt =
  // 1e-4 s.
  const DragErrors coarse = free_fall_with_drag(0.1, 0.5, 1e-3);
  const DragErrors fine = free_fall_with_drag(0.1, 0.5, 1e-4);
  EXPECT_NEAR(coarse.velocity / fine.velocity, 100, 10);
  EXPECT_NEAR(coarse.height / fine.height, 100, 10);
}

TEST(ReferenceIntegrator, GravityParabolaIsExact) {
  // Eqs. 5-6 are exact for a constant acceleration; what remains is the rounding of 1000 steps,
  // about 1000 ulps of |x| at most (2e-13 relative), so 1e-12 relative.
  const Eigen::Vector3d gravity(0, 0, -kGravity);
  const Eigen::Vector3d x0(0.1, -0.2, 1), v0(2, 0.5, 3);
  auto effects = [&](RigidBody& body) { add_gravity(body, gravity); };
  RigidBody body = RigidBody::with_mass_properties(0.3, Eigen::Vector3d::Ones());
  body.position = x0;
  body.velocity = v0;
  effects(body);
  const double dt = 1e-3;
  for (int k = 1; k <= 1000; ++k) step(body, dt, RotationScheme::kImplicitMidpoint, effects);
  const double t = 1;
  const Eigen::Vector3d x = x0 + v0 * t + 0.5 * gravity * t * t;
  const Eigen::Vector3d v = v0 + gravity * t;
  EXPECT_LT((body.position - x).norm(), 1e-12 * x.norm());
  EXPECT_LT((body.velocity - v).norm(), 1e-12 * v.norm());
}

// Torque-free body with principal moments 1:2:3 started near the intermediate axis,
// omega = (1e-3, 1, 1e-3) rad/s (body frame): the tennis-racket instability reverses omega_y
// within the first 20 s, then again periodically. Largest relative drifts of the kinetic energy, of
// |L| and of the world-frame components of L (relative to |L|) over `steps` steps.
struct RotationDrifts {
  double energy = 0;
  double momentum_norm = 0;
  double momentum_world = 0;
  double smallest_omega_y = 1;  // < 0 once the body has flipped
};

RotationDrifts spin_near_intermediate_axis(RotationScheme scheme, double dt, long steps) {
  RigidBody body = RigidBody::with_mass_properties(1, Eigen::Vector3d(1, 2, 3));
  body.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 2) / 3));
  body.angular_velocity_body = Eigen::Vector3d(1e-3, 1, 1e-3);
  const double energy = body.rotational_kinetic_energy();
  const Eigen::Vector3d momentum = body.angular_momentum_world();
  RotationDrifts drifts;
  for (long k = 0; k < steps; ++k) {
    step(body, dt, scheme, [](RigidBody&) {});
    const Eigen::Vector3d l = body.angular_momentum_world();
    drifts.energy =
        std::max(drifts.energy, std::abs(body.rotational_kinetic_energy() / energy - 1));
    drifts.momentum_norm = std::max(drifts.momentum_norm, std::abs(l.norm() / momentum.norm() - 1));
    drifts.momentum_world =
        std::max(drifts.momentum_world, (l - momentum).cwiseAbs().maxCoeff() / momentum.norm());
    drifts.smallest_omega_y = std::min(drifts.smallest_omega_y, body.angular_velocity_body.y());
  }
  return drifts;
}

TEST(ReferenceIntegrator, FreeRotationMidpointConservesEnergyAndWorldMomentum) {
  // dt = 1e-3 s at |omega| = 1 rad/s, i.e. |omega| dt = 1e-3: the paper's dt = 1e-5 s (drum,
  // Table 2) for a particle turning at 100 rad/s. 1e5 steps = 100 s, several flips. The scheme
  // conserves all three exactly up to rounding (measured E 2.2e-14, |L| 1.2e-14, world L 1.6e-13);
  // the bound is 1e-6.
  const RotationDrifts drifts =
      spin_near_intermediate_axis(RotationScheme::kImplicitMidpoint, 1e-3, 100000);
  EXPECT_LT(drifts.smallest_omega_y, -0.9);  // it did flip: the test sees the hard part
  EXPECT_LE(drifts.energy, 1e-6);
  EXPECT_LE(drifts.momentum_norm, 1e-6);
  EXPECT_LE(drifts.momentum_world, 1e-6);
}

TEST(ReferenceIntegrator, FreeRotationExplicitMeetsTheBoundOnlyAtSmallSteps) {
  // The paper's rates stepped by forward Euler (BLAZE-DEM Eq. 7) meet 1e-6 over 1e5 steps at
  // |omega| dt = 1e-5 (1 s, before any flip; measured E 4.5e-12, |L| 1.4e-12, world L 6.3e-9),
  // but not at |omega| dt = 1e-3 (measured E 4.6e-3, |L| 2.3e-3, world L 2.1e-3).
  const RotationDrifts small =
      spin_near_intermediate_axis(RotationScheme::kExplicitEuler, 1e-5, 100000);
  EXPECT_LE(small.energy, 1e-6);
  EXPECT_LE(small.momentum_norm, 1e-6);
  EXPECT_LE(small.momentum_world, 1e-6);
  const RotationDrifts large =
      spin_near_intermediate_axis(RotationScheme::kExplicitEuler, 1e-3, 100000);
  EXPECT_GT(large.energy, 1e-4);
}

TEST(ReferenceIntegrator, FreeRotationExplicitIsFirstOrder) {
  // Forward Euler raises the free-body energy by dt^2 |omega'|^2_I / 2 a step, so over a fixed
  // 20 s (one flip) the drift halves with dt (measured ratio 2.00).
  const RotationDrifts coarse =
      spin_near_intermediate_axis(RotationScheme::kExplicitEuler, 2e-4, 100000);
  const RotationDrifts fine =
      spin_near_intermediate_axis(RotationScheme::kExplicitEuler, 1e-4, 200000);
  EXPECT_NEAR(coarse.energy / fine.energy, 2, 0.1);
}

TEST(ReferenceIntegrator, ConstantTorqueAddsExactAngularImpulse) {
  // With the midpoint scheme the torque enters as two half-kicks of world L around a rotation
  // that keeps world L, so L(t) = L0 + T t to rounding for any body and orientation. The
  // explicit scheme integrates the same torque to first order only. 1000 steps of order-1
  // numbers: 1e-12 relative.
  for (const RotationScheme scheme :
       {RotationScheme::kImplicitMidpoint, RotationScheme::kExplicitEuler}) {
    RigidBody body = RigidBody::with_mass_properties(1, Eigen::Vector3d(1, 2, 3));
    body.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d(0, 0.6, 0.8)));
    body.angular_velocity_body = Eigen::Vector3d(0.3, -0.2, 0.5);
    const Eigen::Vector3d torque(0.2, -0.1, 0.3);
    auto effects = [&](RigidBody& b) { b.torque += torque; };
    const Eigen::Vector3d expected = body.angular_momentum_world() + torque * 1.0;
    effects(body);
    for (int k = 0; k < 1000; ++k) step(body, 1e-3, scheme, effects);
    const double error = (body.angular_momentum_world() - expected).norm() / expected.norm();
    if (scheme == RotationScheme::kImplicitMidpoint) {
      EXPECT_LT(error, 1e-12);
    } else {
      // First order with dt = 1e-3 s and rates of order 1 (measured 7.6e-5).
      EXPECT_LT(error, 1e-3);
    }
  }
}

}  // namespace
}  // namespace talus::reference
