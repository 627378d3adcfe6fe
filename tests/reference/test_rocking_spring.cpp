// The default volume law's rocking spring (reference/contact/force_law.hpp, patch_couple) over
// steps, against its definition: M_e = -k_r sum_k w_perp,k dt at a constant k_r = k_n A_n / 12,
// its energy |M_e|^2 / (2 k_r), the cap |F_n| sqrt(A_n) / 2 and the slip there, the scaling by
// sqrt(k_r / k_before) when k_r falls, the turn with the normal, and the reset where the area is
// zero. The spring in a world (the pair's history, a wall): test_wall_point_and_patch_couple.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "reference/contact/force_law.hpp"

namespace talus::reference {
namespace {

// A contact with unit normal n, patch A_n = 1e-4 m^2, k_n = 5e4 N/m (k_r = k_n A_n / 12 =
// 0.41667 N m/rad), c_n = 0.3 N s/m (c_r = 2.5e-6 N m s), no friction (no twisting).
struct Patch {
  Eigen::Vector3d n = Eigen::Vector3d(2, -1, 2) / 3;
  double area = 1e-4, k_n = 5e4, c_n = 0.3;
  ContactForce force;
  ContactHistory history;
  explicit Patch(double load) {
    force.normal_force = -load * n;
    force.normal_damping = c_n;
  }
  double k_r() const { return k_n * area / 12; }
  double c_r() const { return c_n * area / 12; }
  double cap() const { return force.normal_force.norm() * std::sqrt(area) / 2; }
  Eigen::Vector3d in_plane(const Eigen::Vector3d& w) const { return w - w.dot(n) * n; }
  PatchCouple step(const Eigen::Vector3d& w, double dt) {
    return patch_couple(force, n, area, k_n, 0.0, w, dt, history);
  }
};

// The tilt rate w_k (with a twist along n that the spring ignores) of step k.
Eigen::Vector3d tilt_rate(int k) {
  return {0.4 * std::cos(0.3 * k), -0.2 + 0.01 * k, 0.7 * std::sin(0.2 * k)};
}

// Far from the cap, N steps of dt build M_e = -k_r sum_k w_perp,k dt (exact for a constant k_r:
// the same increments in the same order, up to the round-off of the sum, ~N eps relative: 1e-13
// covers it), and the couple is M_e - c_r w_perp. The energy |M_e|^2 / (2 k_r) is the spring's.
// Turning the same tilts back (w -> -w in reverse order) unloads it to zero.
TEST(ReferenceRockingSpring, BuildsTheIntegralOfTheTiltRate) {
  Patch p(100);  // |F_n| = 100 N: cap 0.5 N m, far above the moments here
  const double dt = 1e-3;
  const int steps = 40;
  PatchCouple first = p.step(tilt_rate(0), 0);  // the evaluation before the first step
  EXPECT_EQ(p.history.rocking_moment, Eigen::Vector3d::Zero());
  EXPECT_EQ(p.history.rocking_stiffness, p.k_r());
  EXPECT_LT((first.rocking + p.c_r() * p.in_plane(tilt_rate(0))).norm(), 1e-18);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();  // sum of w_perp dt
  for (int k = 1; k <= steps; ++k) {
    const Eigen::Vector3d w = tilt_rate(k);
    const PatchCouple pc = p.step(w, dt);
    sum += p.in_plane(w) * dt;
    const Eigen::Vector3d spring = -p.k_r() * sum;
    ASSERT_LT((p.history.rocking_moment - spring).norm(), 1e-13 * spring.norm()) << "step " << k;
    EXPECT_LT((pc.rocking - (spring - p.c_r() * p.in_plane(w))).norm(), 1e-13 * spring.norm());
    EXPECT_EQ(pc.twisting, Eigen::Vector3d::Zero());  // no friction
    EXPECT_NEAR(pc.spring_energy, spring.squaredNorm() / (2 * p.k_r()), 1e-12 * pc.spring_energy);
    EXPECT_NEAR(pc.dissipation, -pc.total().dot(w), 1e-15 * pc.total().norm());
  }
  ASSERT_LT(p.history.rocking_moment.norm() + p.c_r(), 0.1 * p.cap());
  std::printf("rocking spring after %d steps: |M_e| %.4g N m, energy %.4g J\n", steps,
              p.history.rocking_moment.norm(), p.step(Eigen::Vector3d::Zero(), 0).spring_energy);
  for (int k = steps; k >= 1; --k) p.step(-tilt_rate(k), dt);
  EXPECT_LT(p.history.rocking_moment.norm(), 1e-13 * p.k_r() * sum.norm());
}

// Where |M_e - c_r w_perp| passes |F_n| sqrt(A_n) / 2, the couple is that long and the spring
// keeps what the capped couple leaves it, M_e = couple + c_r w_perp (it slips): further tilting
// the same way keeps the couple at the cap, and tilting back unloads from the slipped value.
TEST(ReferenceRockingSpring, CapAndSlip) {
  Patch p(0.02);  // |F_n| = 0.02 N: cap 1e-4 N m
  const double dt = 1e-3;
  const Eigen::Vector3d w = p.in_plane(Eigen::Vector3d(0.3, 0.5, -0.1));
  p.step(w, 0);
  // Steps to reach the cap: k_r |w| dt per step, 2.4e-4 N m each here, so the first step binds.
  const PatchCouple pc = p.step(w, dt);
  const double unbounded = (p.k_r() * dt + p.c_r()) * w.norm();
  ASSERT_GT(unbounded, p.cap());
  EXPECT_NEAR(pc.rocking.norm(), p.cap(), 1e-15);
  EXPECT_LT((pc.rocking + p.cap() * w.normalized()).norm(), 1e-15);  // against the tilt
  const Eigen::Vector3d slipped = pc.rocking + p.c_r() * w;
  EXPECT_LT((p.history.rocking_moment - slipped).norm(), 1e-18);
  EXPECT_NEAR(pc.spring_energy, slipped.squaredNorm() / (2 * p.k_r()), 1e-15 * pc.spring_energy);
  // Slipping on: the same couple, the same spring.
  const PatchCouple again = p.step(w, dt);
  EXPECT_LT((again.rocking - pc.rocking).norm(), 1e-18);
  EXPECT_LT((p.history.rocking_moment - slipped).norm(), 1e-18);
  // Tilting back a little at 1/100 of the rate: M_e = slipped + k_r (w / 100) dt, under the cap.
  const Eigen::Vector3d back = -0.01 * w;
  const PatchCouple unloading = p.step(back, dt);
  const Eigen::Vector3d spring = slipped - p.k_r() * back * dt;
  ASSERT_LT((spring - p.c_r() * back).norm(), p.cap());
  EXPECT_LT((p.history.rocking_moment - spring).norm(), 1e-15 * spring.norm());
  EXPECT_LT((unloading.rocking - (spring - p.c_r() * back)).norm(), 1e-15 * spring.norm());
  // The spring gives energy back as it unloads: the power the couple takes is negative.
  EXPECT_LT(unloading.dissipation, 0);
}

// When k_r falls (the patch shrinks or k_n falls) the moment is scaled by sqrt(k_r / k_before)
// before the increment, so the energy |M_e|^2 / (2 k_r) is the one held; a rising k_r keeps the
// moment (its energy falls). Only the scale factor's round-off: 1e-14.
TEST(ReferenceRockingSpring, KeepsItsEnergyWhenTheStiffnessFalls) {
  Patch p(100);
  const double dt = 1e-3;
  p.step(tilt_rate(0), 0);
  for (int k = 1; k <= 10; ++k) p.step(tilt_rate(k), dt);
  const Eigen::Vector3d held = p.history.rocking_moment;
  const double energy = held.squaredNorm() / (2 * p.k_r());
  // The area falls by 4: k_r by 4, the moment by 2.
  p.area /= 4;
  PatchCouple pc = p.step(Eigen::Vector3d::Zero(), dt);
  EXPECT_EQ(p.history.rocking_stiffness, p.k_r());
  EXPECT_LT((p.history.rocking_moment - 0.5 * held).norm(), 1e-14 * held.norm());
  EXPECT_NEAR(pc.spring_energy, energy, 1e-14 * energy);
  // k_n falls by 9/16 (k_r by 9/16 again): the moment by 3/4.
  p.k_n *= 9.0 / 16.0;
  pc = p.step(Eigen::Vector3d::Zero(), 0);
  EXPECT_LT((p.history.rocking_moment - 0.375 * held).norm(), 1e-14 * held.norm());
  EXPECT_NEAR(pc.spring_energy, energy, 1e-14 * energy);
  // Back up: the moment is kept, the energy falls with 1 / k_r.
  p.k_n *= 16.0 / 9.0;
  p.area *= 4;
  pc = p.step(Eigen::Vector3d::Zero(), dt);
  EXPECT_LT((p.history.rocking_moment - 0.375 * held).norm(), 1e-14 * held.norm());
  EXPECT_NEAR(pc.spring_energy, 0.375 * 0.375 * energy, 1e-14 * energy);
}

// The normal turns: the moment is turned into the new contact plane with its length kept.
TEST(ReferenceRockingSpring, TurnsWithTheNormal) {
  Patch p(100);
  p.step(tilt_rate(0), 0);
  for (int k = 1; k <= 10; ++k) p.step(tilt_rate(k), 1e-3);
  const Eigen::Vector3d held = p.history.rocking_moment;
  p.n = Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 1, 0).normalized()) * p.n;
  p.force.normal_force = -100 * p.n;
  p.step(Eigen::Vector3d::Zero(), 1e-3);
  const Eigen::Vector3d& turned = p.history.rocking_moment;
  EXPECT_NEAR(turned.dot(p.n), 0, 1e-15 * held.norm());
  EXPECT_NEAR(turned.norm(), held.norm(), 1e-15 * held.norm());
  // Along the old moment's projection onto the new plane.
  const Eigen::Vector3d projected = held - held.dot(p.n) * p.n;
  EXPECT_LT((turned - projected.normalized() * held.norm()).norm(), 1e-14 * held.norm());
}

// No area (the contact's overlap has no area left): no couple, and the spring is cleared; the
// next contact starts from nothing.
TEST(ReferenceRockingSpring, ZeroAtZeroArea) {
  Patch p(100);
  p.step(tilt_rate(0), 0);
  for (int k = 1; k <= 10; ++k) p.step(tilt_rate(k), 1e-3);
  ASSERT_GT(p.history.rocking_moment.norm(), 0);
  const double area = p.area;
  p.area = 0;
  const PatchCouple none = p.step(tilt_rate(11), 1e-3);
  EXPECT_EQ(none.total(), Eigen::Vector3d::Zero());
  EXPECT_EQ(none.spring_energy, 0.0);
  EXPECT_EQ(none.dissipation, 0.0);
  EXPECT_EQ(p.history.rocking_moment, Eigen::Vector3d::Zero());
  EXPECT_EQ(p.history.rocking_stiffness, 0.0);
  p.area = area;
  const Eigen::Vector3d w = tilt_rate(12);
  p.step(w, 1e-3);
  const Eigen::Vector3d fresh = -p.k_r() * p.in_plane(w) * 1e-3;
  EXPECT_LT((p.history.rocking_moment - fresh).norm(), 1e-15 * fresh.norm());
}

}  // namespace
}  // namespace talus::reference
