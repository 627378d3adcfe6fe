// The production force laws (solver/contact/force_law.hpp), the damping calibration and the
// history keys, on cases with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "solver/contact/damping_calibration.hpp"
#include "solver/contact/force_law.hpp"
#include "solver/contact/pair_geometry.hpp"
#include "solver/contact/tangential_history.hpp"

namespace talus {
namespace {

// beta(eps) solves the normalised impact: feeding it back gives eps (the bisection stops at
// 1e-10 relative in beta; the rebound speed moves by less than 1e-9 then).
TEST(DampingCalibration, RatioGivesTheRestitution) {
  for (const double eps : {0.1, 0.5, 0.9}) {
    const double beta = calibrated_damping_ratio_for(eps);
    EXPECT_GT(beta, 0.0);
    EXPECT_NEAR(normalised_impact_restitution(beta), eps, 1e-9) << eps;
  }
  EXPECT_EQ(calibrated_damping_ratio_for(1.0), 0.0);
  EXPECT_THROW(calibrated_damping_ratio_for(0.0), std::invalid_argument);
  // Undamped, the clamped oscillator is elastic; the integration stops at the first step past the
  // end of the contact, which costs up to h |q''| = 2e-4 x q^(1/3) there (measured 1.5e-6).
  EXPECT_NEAR(normalised_impact_restitution(0.0), 1.0, 1e-5);
}

// Eq. 15 with the dissipating sign: positive for eps < 1, zero for eps = 1.
TEST(ForceLaw, DampingCoefficientDissipates) {
  EXPECT_GT(dissipative_damping(0.5, 100.0, 2.0), 0.0);
  EXPECT_EQ(dissipative_damping(1.0, 100.0, 2.0), 0.0);
  // eps -> critical damping 2 sqrt(k m) as eps -> 0: at eps = 1e-12, 0.994 of it.
  EXPECT_NEAR(dissipative_damping(1e-12, 100.0, 1.0) / 20.0, 0.9941, 1e-3);
}

// The no-tension rule: a separating contact whose damping exceeds its elastic force gives zero,
// never a pull.
TEST(ForceLaw, LinearContactNeverPulls) {
  NormalContactData<double> c;
  c.normal = Vec3d(1, 0, 0);
  c.elastic = 1.0;
  LinearLawData<double> law;
  law.stiffness = 100, law.damping = 10;
  const ContactForceData<double> approaching = linear_contact_force(c, law, Vec3d(0.1, 0, 0));
  EXPECT_DOUBLE_EQ(approaching.normal_force.x, -2.0);  // -(1 + 10 * 0.1) n on A
  const ContactForceData<double> leaving = linear_contact_force(c, law, Vec3d(-0.5, 0, 0));
  EXPECT_EQ(leaving.normal_force.x, 0.0);
}

// BLAZE-DEM Eq. 3: F_T = -min(mu K_N delta, gamma |v_T|) along v_T.
TEST(ForceLaw, LinearFrictionIsTheSmallerOfCapAndViscous) {
  NormalContactData<double> c;
  c.normal = Vec3d(0, 0, 1);
  c.elastic = 2.0;
  LinearLawData<double> law;
  law.stiffness = 100, law.tangential_damping = 3, law.friction = 0.5, law.with_friction = true;
  const ContactForceData<double> slow = linear_contact_force(c, law, Vec3d(0.1, 0, 0));
  EXPECT_DOUBLE_EQ(slow.tangential_force.x, -0.3);
  EXPECT_FALSE(slow.sliding);
  const ContactForceData<double> fast = linear_contact_force(c, law, Vec3d(0, 2.0, 0));
  EXPECT_DOUBLE_EQ(fast.tangential_force.y, -1.0);  // mu K_N delta = 0.5 * 2
  EXPECT_TRUE(fast.sliding);
}

// The elastic tangential force F_t^e = -k_t Delta-s is turned onto the new tangent plane with
// its length kept, changes by -k_t v_t dt, keeps its value when k_t changes (the incremental
// form; force_law.hpp says why), and is reset to the capped force where Coulomb binds (Eqs.
// 17-20).
TEST(ForceLaw, VolumeElasticForceTurnsKeepsLengthAndRescalesAtTheCap) {
  NormalContactData<double> c;
  c.normal = Vec3d(0, 0, 1);
  c.elastic = 10.0;
  c.normal_stiffness = 1e4;
  c.tangential_stiffness = 1e3;
  c.area = 1e-4;
  VolumeLawData<double> law;
  law.effective_mass = 0.01, law.restitution = 1, law.friction = 0.5, law.with_friction = true;
  ContactHistoryData<double> h;
  h.elastic_force = Vec3d(-0.3, 0, -0.4);  // 0.5 N, partly along the normal
  const ContactForceData<double> f = volume_contact_force(c, law, Vec3d(), 1e-3, h);
  EXPECT_NEAR(norm(h.elastic_force), 0.5, 1e-15);
  EXPECT_NEAR(h.elastic_force.z, 0.0, 1e-15);
  EXPECT_NEAR(f.tangential_force.x, -0.5, 1e-12);  // under the cap mu |F_n| = 5
  // Twice the stiffness (twice the area) at rest: the force stays; Eq. 18 read literally at a
  // fixed Delta-s would double it, and with it the spring's energy.
  c.tangential_stiffness = 2e3;
  const ContactForceData<double> stiffer = volume_contact_force(c, law, Vec3d(), 1e-3, h);
  EXPECT_NEAR(stiffer.tangential_force.x, -0.5, 1e-12);
  // A tangential speed of 0.1 m/s for 1 ms: -k_t v dt = -0.2 N more (the normal part of the
  // velocity does not count; restitution 1: no damping).
  const ContactForceData<double> moved = volume_contact_force(c, law, Vec3d(0.1, 0, 3.0), 1e-3, h);
  EXPECT_NEAR(moved.tangential_force.x, -0.7, 1e-12);
  EXPECT_NEAR(h.elastic_force.x, -0.7, 1e-12);
  h.elastic_force = Vec3d(-20, 0, 0);  // over the cap mu |F_n| = 5
  const ContactForceData<double> capped = volume_contact_force(c, law, Vec3d(), 1e-3, h);
  EXPECT_TRUE(capped.sliding);
  EXPECT_NEAR(capped.tangential_force.x, -5.0, 1e-12);
  EXPECT_NEAR(h.elastic_force.x, -5.0, 1e-12);  // the elastic part of the capped force
}

// The calibrated damping: eta = beta m^(1/4) K^(3/4) / sqrt(v0), c_n = eta A_n, with v0 the
// approach speed; a contact formed at rest takes v0 = sqrt(2 U / m), U = 3/4 K dV^(4/3), the speed
// that would have made its overlap; c_n never exceeds m / dt.
TEST(ForceLaw, CalibratedDampingFromTheApproachSpeed) {
  NormalContactData<double> c;
  c.normal = Vec3d(1, 0, 0);
  c.area = 2e-4;
  c.normal_stiffness = 1e9 * c.area;  // K = 1e9 N/m^3
  const double cube_root = 1e-5;      // dV^(1/3)
  c.elastic = c.normal_stiffness * cube_root;
  VolumeLawData<double> law;
  law.effective_mass = 0.01, law.restitution = 0.5, law.damping_ratio = 1.5, law.time_step = 1e-6;
  ContactHistoryData<double> h;
  const ContactForceData<double> f = volume_contact_force(c, law, Vec3d(0.2, 0, 0), 0.0, h);
  EXPECT_DOUBLE_EQ(h.approach_speed, 0.2);  // above sqrt(2 U / m) = 9.5e-3 m/s here
  const double c_n = 1.5 * std::pow(0.01, 0.25) * std::pow(1e9, 0.75) / std::sqrt(0.2) * 2e-4;
  ASSERT_LT(c_n, 0.01 / 1e-6);  // below the step limit: the calibrated value acts
  EXPECT_NEAR(-f.normal_force.x, c.elastic + c_n * 0.2, 1e-12 * (c.elastic + c_n));

  ContactHistoryData<double> at_rest;
  volume_contact_force(c, law, Vec3d(), 0.0, at_rest);
  const double energy = 0.75 * 1e9 * std::pow(cube_root, 4);
  EXPECT_NEAR(at_rest.approach_speed, std::sqrt(2 * energy / 0.01), 1e-15);
}

// The lens of two equal spheres at distance d: volume 2 pi h^2 (3r - h) / 3 with h = r - d/2,
// disc area pi (r^2 - d^2/4), point midway, normal along the centre line.
TEST(PairGeometry, SphereLensOfEqualSpheres) {
  const double r = 1.0, d = 1.6, h = r - d / 2;
  const PairGeometryData<double> g = sphere_lens_geometry(Vec3d(0, 0, 0), r, Vec3d(d, 0, 0), r);
  ASSERT_TRUE(g.in_contact);
  EXPECT_NEAR(g.volume, 2 * M_PI * h * h * (3 * r - h) / 3, 1e-14);
  EXPECT_NEAR(g.area, M_PI * (r * r - d * d / 4), 1e-14);
  EXPECT_NEAR(g.point.x, d / 2, 1e-14);
  EXPECT_DOUBLE_EQ(g.normal.x, 1.0);
  EXPECT_FALSE(sphere_lens_geometry(Vec3d(), r, Vec3d(2.0, 0, 0), r).in_contact);
  EXPECT_TRUE(sphere_lens_geometry(Vec3d(), 2.0, Vec3d(0.5, 0, 0), 1.0).degenerate);
}

// History keys: ordered by (low, high) and found by binary search.
TEST(TangentialHistory, KeysAreFoundBySearch) {
  const PairKey keys[] = {{0, 3}, {1, 2}, {1, 7}, {4, 5}};
  EXPECT_EQ(find_pair_key(keys, 4, make_pair_key(7, 1)), 2);
  EXPECT_EQ(find_pair_key(keys, 4, make_pair_key(4, 5)), 3);
  EXPECT_EQ(find_pair_key(keys, 4, make_pair_key(2, 3)), -1);
  EXPECT_EQ(find_pair_key(keys, 0, make_pair_key(0, 3)), -1);
}

// The rocking spring of patch_couple: a contact of area A and k_n rocked at a steady rate w_perp
// (no damping, a large load so that the cap stays away) builds M_e = -k_r w_perp t, k_r = k_n A /
// 12, exactly (each step adds -k_r w dt; the sums of 100 equal terms round at 1e-16 relative);
// its energy is |M_e|^2 / (2 k_r), and the power the couple takes is -M . w.
TEST(PatchCouple, RockingSpringBuildsAtTheWinklerStiffness) {
  const Vec3<double> n(0, 0, 1), w(2.0, -1.0, 0.0);  // rad/s, in the contact plane
  const double area = 1e-4, k_n = 5e4, dt = 1e-5;
  const double k_r = k_n * area / 12;
  ContactForceData<double> f;
  f.normal_force = Vec3<double>(0, 0, -1e3);  // the cap, 1e3 sqrt(A) / 2 = 5 N m, stays away
  ContactHistoryData<double> h;
  Vec3<double> couple;
  for (int k = 0; k < 100; ++k) {
    f.dissipation = f.spring_energy = 0;
    couple = patch_couple(f, n, area, k_n, 0.0, w, dt, h);
  }
  const Vec3<double> expected = w * (-k_r * dt * 100);
  EXPECT_NEAR(norm(couple - expected), 0.0, 1e-14 * norm(expected));
  EXPECT_NEAR(norm(h.rocking_moment - expected), 0.0, 1e-14 * norm(expected));
  EXPECT_DOUBLE_EQ(h.rocking_stiffness, k_r);
  EXPECT_NEAR(f.spring_energy, norm2(expected) / (2 * k_r), 1e-13 * f.spring_energy);
  EXPECT_NEAR(f.dissipation, -dot(couple, w), 1e-14 * std::abs(f.dissipation));
  // The spring takes energy in: the power is positive, and it is the rate of the spring's
  // energy, M . dM/dt / k_r = -M . w (the ledger takes the energy's change off it).
  EXPECT_GT(f.dissipation, 0.0);
}

// The cap |F_n| sqrt(A) / 2: a spring wound past it slips there, its elastic part then holding the
// capped couple plus the dashpot's (as the tangential spring at Coulomb's cap).
TEST(PatchCouple, RockingSpringSlipsAtThePatchEdge) {
  const Vec3<double> n(0, 0, 1), w(0.0, 3.0, 0.0);
  const double area = 4e-4, k_n = 1e6;
  ContactForceData<double> f;
  f.normal_force = Vec3<double>(0, 0, -2.0);  // cap = 2 x 0.02 / 2 = 0.02 N m
  f.normal_damping = 10.0;                    // c_r = 10 x 4e-4 / 12
  const double c_r = 10.0 * area / 12;
  ContactHistoryData<double> h;
  h.rocking_moment = Vec3<double>(0, -0.5, 0);  // far past the cap
  h.rocking_stiffness = k_n * area / 12;
  const Vec3<double> couple = patch_couple(f, n, area, k_n, 0.0, w, 1e-5, h);
  EXPECT_NEAR(norm(couple), 0.02, 1e-15);
  EXPECT_NEAR(couple.y, -0.02, 1e-15);
  EXPECT_NEAR(h.rocking_moment.y, -0.02 + c_r * 3.0, 1e-15);
}

// k_r follows the area: when it falls the stored couple is scaled by sqrt(k_r / k_before), so the
// spring's energy is kept, not raised (|M|^2 / (2 k_r) at a fixed |M| would grow as 1 / k_r); a
// contact that loses its area loses its spring.
TEST(PatchCouple, RockingSpringKeepsItsEnergyAsTheAreaFalls) {
  const Vec3<double> n(0, 0, 1), still;
  const double k_n = 1e5;
  ContactForceData<double> f;
  f.normal_force = Vec3<double>(0, 0, -1e3);
  ContactHistoryData<double> h;
  h.rocking_moment = Vec3<double>(1e-3, 0, 0);
  h.rocking_stiffness = k_n * 4e-4 / 12;
  const double before = norm2(h.rocking_moment) / (2 * h.rocking_stiffness);
  patch_couple(f, n, 1e-4, k_n, 0.0, still, 1e-5, h);  // the area falls by 4
  EXPECT_NEAR(h.rocking_moment.x, 0.5e-3, 1e-18);      // sqrt(1/4)
  EXPECT_NEAR(f.spring_energy, before, 1e-15 * before);
  patch_couple(f, n, 0.0, k_n, 0.0, still, 1e-5, h);
  EXPECT_EQ(norm(h.rocking_moment), 0.0);
  EXPECT_EQ(h.rocking_stiffness, 0.0);
}

}  // namespace
}  // namespace talus
