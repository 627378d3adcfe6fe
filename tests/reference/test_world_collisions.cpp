// Whole-world physics of the reference solver under the paper's law (volume_paper, Eqs. 12-22,
// with its calibrated damping): restitution of head-on impacts, a cube at rest, a block on an
// incline, the cylinder-wall impact of the paper's §3.1; and a free cloud under both volume laws.
// The default volume law's own: test_default_volume_law.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "tests/reference/world_test_util.hpp"

namespace talus::reference {
namespace {

using testing::material;
using testing::polyhedron;
using testing::square_wall;
using testing::turning;

Eigen::Vector3d e3(const Vec3d& v) {
  return {v.x, v.y, v.z};
}

// Steps until the first contact has ended; returns the number of steps in contact.
long run_through_impact(RefWorld& world, long max_steps) {
  long in_contact = 0;
  for (long k = 0; k < max_steps; ++k) {
    world.step();
    if (!world.contacts().empty()) {
      ++in_contact;
    } else if (in_contact > 0) {
      break;
    }
  }
  return in_contact;
}

// Head-on impacts, the paper's law: two dodecahedra (D = 10 mm) face to face or corner first, or a
// cube (D = 10 mm) on a wall face or corner first, at 1 m/s closing speed; restitution measured
// along the line of impact. dt gives about 200 steps in contact (faces, F ~ d^(1/3), are stiff:
// 1e-7 s; corners, F ~ d^3, soft: 8e-6 s).
struct ImpactCase {
  bool wall;
  bool corner;
  double restitution;
  NormalDamping damping;
};

double measured_restitution(const ImpactCase& c, long* steps_in_contact) {
  const ShapeTemplate t = make_shape(c.wall ? "cube:0.01" : "dodecahedron:0.01");
  const Eigen::Vector3d axis = c.corner ? e3(t.vertices[0]).normalized() : e3(t.faces[0].normal);
  const double reach = c.corner ? e3(t.vertices[0]).norm() : t.faces[0].offset;
  const Eigen::Quaterniond q = turning(axis, -Eigen::Vector3d::UnitZ());
  RefWorldSetup s;
  s.templates = {t};
  s.materials = {material(1e7, c.restitution)};
  s.time_step = c.corner ? 8e-6 : 1e-7;
  s.effects.contact = ContactModel::volume_paper;
  s.effects.damping = c.damping;
  const double gap = 1e-7, v = c.wall ? 1.0 : 0.5;
  if (c.wall) {
    s.bodies = {
        polyhedron(0, 0, 1, Eigen::Vector3d(0, 0, reach + gap), q, Eigen::Vector3d(0, 0, -v))};
    s.walls = {square_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.05, 0,
                           Eigen::Vector3d(1, 0.3, 0))};
  } else {
    // Same orientation: the dodecahedron is centrally symmetric, so B's -z feature mirrors A's.
    s.bodies = {
        polyhedron(0, 0, 1, Eigen::Vector3d(0, 0, -reach - gap), q, Eigen::Vector3d(0, 0, v)),
        polyhedron(0, 0, 2, Eigen::Vector3d(0, 0, reach + gap), q, Eigen::Vector3d(0, 0, -v))};
  }
  RefWorld world(s);
  *steps_in_contact = run_through_impact(world, 20000);
  const auto& b = world.bodies();
  return c.wall ? b[0].state.velocity.z() / v
                : (b[1].state.velocity.z() - b[0].state.velocity.z()) / (2 * v);
}

std::string case_name(const ImpactCase& c) {
  return std::string(c.damping == NormalDamping::kPaper ? "Paper" : "Calibrated") +
         (c.wall ? "CubeWall" : "Dodecahedra") + (c.corner ? "Corner" : "Face") + "Eps" +
         std::to_string(static_cast<int>(std::lround(100 * c.restitution)));
}

class ReferenceRestitution : public ::testing::TestWithParam<ImpactCase> {};

TEST_P(ReferenceRestitution, HeadOnImpact) {
  const ImpactCase c = GetParam();
  long steps = 0;
  const double e = measured_restitution(c, &steps);
  std::printf("restitution %s: eps %.2f measured %.4f (%+.1f%%), %ld steps in contact\n",
              case_name(c).c_str(), c.restitution, e, 100 * (e / c.restitution - 1), steps);
  RecordProperty("measured_restitution", std::to_string(e));
  EXPECT_GT(steps, 100);  // resolved: about 200 steps in contact
  if (c.damping == NormalDamping::kCalibrated) {
    // Exact for a head-on impact in the continuous limit (force_law.hpp: the impact in the
    // variable dV is the calibration's 1-D problem whatever the shape); what remains is the
    // time step's error, first order in dt / contact time: measured 1.2% at most with about 200
    // steps in contact (faces, eps = 0.1) and 0.6% with 400. 3% leaves room for it and still
    // fails a calibration off by a few percent (the brief's bound is 5%).
    EXPECT_NEAR(e, c.restitution, 0.03 * c.restitution);
  } else {
    // Eq. 15 as printed, on k_n of Eq. 13: its damping ratio is that of a linear spring, and
    // the volume law is far from linear, so the restitution is not epsilon: measured 0.86-0.997
    // face first and 0.33-0.96 corner first for eps = 0.1-0.95 (too little damping, most of all
    // for faces, where F ~ dV^(1/3) stores the energy at a small penetration). Asserted: that it
    // damps (e < 1) but less than asked.
    EXPECT_GT(e, c.restitution);
    EXPECT_LT(e, 1.0);
  }
}

std::vector<ImpactCase> impact_cases() {
  std::vector<ImpactCase> out;
  for (NormalDamping d : {NormalDamping::kCalibrated, NormalDamping::kPaper}) {
    for (bool wall : {false, true}) {
      for (bool corner : {false, true}) {
        for (double eps : {0.1, 0.5, 0.85, 0.95}) out.push_back({wall, corner, eps, d});
      }
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Cases, ReferenceRestitution, ::testing::ValuesIn(impact_cases()),
                         [](const ::testing::TestParamInfo<ImpactCase>& info) {
                           return case_name(info.param);
                         });

// A cube (side 10 mm, 2.5 g) on one big triangle tilted by theta, friction on, restitution 0.1,
// dropped from 1 um above it; the paper's law (the numbers below are its).
RefWorldSetup cube_on_slope(double theta, double mu, double youngs, double dt) {
  const ShapeTemplate t = make_shape("cuboid:0.01,0.01,0.01");
  RefWorldSetup s;
  s.templates = {t};
  s.materials = {material(youngs, 0.1, mu)};
  s.time_step = dt;
  s.effects.contact = ContactModel::volume_paper;
  s.effects.friction = true;
  s.effects.gravity = Eigen::Vector3d(0, 0, -9.81);
  // The plane through the origin with normal (-sin, 0, cos): it descends along +x.
  const Eigen::Vector3d n(-std::sin(theta), 0, std::cos(theta));
  const Eigen::Vector3d down(std::cos(theta), 0, std::sin(theta));
  RefWall w;
  w.material = 0;
  const Eigen::Vector3d side = Eigen::Vector3d::UnitY();
  w.triangles = {{-2 * down - 2 * side, 2 * down - 2 * side, 4 * side}};
  if (n.dot((w.triangles[0][1] - w.triangles[0][0]).cross(w.triangles[0][2] - w.triangles[0][0])) <
      0) {
    std::swap(w.triangles[0][1], w.triangles[0][2]);
  }
  s.walls = {w};
  const Eigen::Quaterniond q = turning(Eigen::Vector3d::UnitZ(), n);
  s.bodies = {polyhedron(0, 0, 1, (0.005 + 1e-6) * n, q)};
  return s;
}

// At rest, E = 10 kPa: the face's equilibrium depth is m g / (K A^(4/3)) cubed = 35 nm, where the
// normal law's tangent stiffness m g / (3 d) = 2.3e5 N/m gives a period of 0.65 ms (32 steps of
// 2e-5 s); Eq. 19's k_t = 62 N/m a period of 40 ms and, with Eq. 20's damping ratio 0.59
// (eps = 0.1), a decay rate of 93 /s. (E = 1 kPa, used before, gives a spring period of 0.13 s
// and a 0.7 mm stretch on a 10 degree slope: the block creeps for seconds. A stiffer E makes the
// face's normal period, ~ E^(-3/2), too short to step cheaply.)
constexpr double kRestYoungs = 1e4, kRestStep = 2e-5;

// The largest displacement of the cube over `window` steps after `settle` steps.
double drift_after(RefWorld& world, long settle, long window) {
  world.run(settle);
  const Eigen::Vector3d rest = world.bodies()[0].state.position;
  double worst = 0;
  for (long k = 0; k < window; ++k) {
    world.step();
    worst = std::max(worst, (world.bodies()[0].state.position - rest).norm());
  }
  return worst;
}

TEST(ReferenceWorld, CubeOnAPlaneComesToRestAndStays) {
  RefWorld world(cube_on_slope(0, 0.5, kRestYoungs, kRestStep));
  // 0.1 s to settle: the landing at 4.4 mm/s is damped (kCalibrated, eps = 0.1) within a few
  // normal periods; then 1 s watched (the horizon; about a minute of CI time).
  const double worst = drift_after(world, 5000, 50000);
  std::printf("cube at rest: largest displacement over 1 s %.3g m\n", worst);
  // 1e-12 m: 3e-5 of the 35 nm depth, 1000 times the ulp of the 5 mm height (9e-19 m); a
  // resting contact that gained energy, or an undamped rest oscillation, would move by nm.
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(world.contacts().size(), 1u);
  EXPECT_LT(world.bodies()[0].state.velocity.norm(), 1e-9);
}

// Along-slope velocity of the cube's centre.
double slope_speed(const RefWorld& world, double theta) {
  // The plane's normal is (-sin, 0, cos): gravity's in-plane part points along -(cos, 0, sin).
  return -world.bodies()[0].state.velocity.dot(
      Eigen::Vector3d(std::cos(theta), 0, std::sin(theta)));
}

TEST(ReferenceWorld, BlockSlidesDownAnInclineAtGSinMinusMuCos) {
  const double theta = 30 * M_PI / 180, mu = 0.3;
  // E = 1 kPa, dt = 2e-4 s: the face's normal period is 20 ms (100 steps); sliding needs no
  // stiff tangential spring.
  RefWorld world(cube_on_slope(theta, mu, 1e3, 2e-4));
  world.run(500);  // 0.1 s: the landing oscillation has died out
  const double v0 = slope_speed(world, theta), t0 = world.time();
  world.run(500);
  const double a = (slope_speed(world, theta) - v0) / (world.time() - t0);
  const double expected = 9.81 * (std::sin(theta) - mu * std::cos(theta));
  std::printf("incline 30 deg, mu 0.3: a = %.5f m/s^2, expected %.5f (%+.3f%%)\n", a, expected,
              100 * (a / expected - 1));
  // 1%: the brief's bound; velocity Verlet is exact for the constant force of steady sliding.
  EXPECT_NEAR(a, expected, 0.01 * expected);
}

TEST(ReferenceWorld, BlockStaysOnAnInclineBelowTheFrictionAngle) {
  const double theta = 10 * M_PI / 180, mu = 0.3;  // tan(theta) = 0.18 < mu
  RefWorld world(cube_on_slope(theta, mu, kRestYoungs, kRestStep));
  // 0.15 s to settle: the spring's stretch m g sin(theta) / k_t = 69 um builds within a period
  // and its oscillation decays (measured: a factor 5-6 per 25 ms, exp(-70 t), where the Eq. 20
  // damping alone predicts exp(-93 t)), to 2e-9 m by then; 0.05 s watched.
  const double worst = drift_after(world, 7500, 2500);
  const double speed = world.bodies()[0].state.velocity.norm();
  std::printf("incline 10 deg, mu 0.3: moved %.3g m in 0.05 s, speed %.3g m/s\n", worst, speed);
  ASSERT_EQ(world.contacts().size(), 1u);
  EXPECT_FALSE(world.contacts()[0].sliding);
  // Held by the Coulomb-capped spring. Measured 3.4e-9 m and 4.6e-10 m/s: the tail of that
  // decay. 1e-8 m is 1.5e-4 of the stretch; a creeping block (E = 1 kPa before) moved by um.
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(speed, 1e-8);
}

}  // namespace
}  // namespace talus::reference

namespace talus::reference {
namespace {

// The cylinder-wall impact of the paper's §3.1 (Table 1, Fig. 9): the 80-facet cylinder (D = 8
// mm, L = 5.3 mm, rho = 1245, E = 1.15e9, nu = 0.35, mu = 0, eps = 0.85, dt = 5e-7 s, no
// gravity) falls at V = 1 m/s (Table 1 gives no speed; Eqs. 27-28 scale with it) onto a wall with
// its face at angle theta to the wall, a rim corner C first. Eqs. 27-28, with the corner at
// r (cos(alpha + theta), 0, -sin(alpha + theta)) from the centre, tan(alpha) = (L/2) / (D/2).
struct CylinderImpact {
  double theta_deg = 0;
  double omega = 0, omega_analytic = 0;       // rad/s: Eq. 27's omega_y^+ (its sign convention)
  double v_z = 0, v_z_analytic = 0;           // m/s: Eq. 28's V_z^+ (z into the wall)
  double d_omega_d_arm = 0, d_v_z_d_arm = 0;  // |derivatives| of Eqs. 27-28 in the lever arm
  double depth = 0;                           // m: the corner's largest penetration
  long steps = 0;                             // in contact
};

CylinderImpact cylinder_impact(double theta_deg) {
  const ShapeTemplate t = make_shape("cylinder:0.008,0.0053");
  const double rho = 1245, v = 1.0, eps = 0.85;
  // Body frame: principal axes, moments ascending, so the cylinder's axis (largest moment) is z.
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int corner = 0;  // a rim vertex on the -z face
  for (int i = 0; i < static_cast<int>(t.vertices.size()); ++i) {
    const Eigen::Vector3d p = e3(t.vertices[i]);
    if (p.z() < 0 && p.norm() > e3(t.vertices[corner]).norm() + 1e-12) corner = i;
    if (p.z() < 0 && corner != i && std::abs(p.norm() - e3(t.vertices[corner]).norm()) < 1e-12 &&
        e3(t.vertices[corner]).z() > 0) {
      corner = i;
    }
  }
  const Eigen::Vector3d c_body = e3(t.vertices[corner]);
  const Eigen::Vector3d radial = (c_body - c_body.dot(axis) * axis).normalized();
  // R0: radial -> x, axis -> z; then a turn by theta about y takes the corner's side down.
  Eigen::Matrix3d frame;
  frame.row(0) = radial.transpose();
  frame.row(1) = axis.cross(radial).transpose();
  frame.row(2) = axis.transpose();
  const double theta = theta_deg * M_PI / 180;
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY())) *
      Eigen::Quaterniond(frame);
  const Eigen::Vector3d c_world = q * c_body;
  CylinderImpact out;
  RefWorldSetup s;
  s.templates = {t};
  s.materials = {material(1.15e9, eps, 0, rho, 0.35)};
  s.time_step = 5e-7;
  s.effects.contact = ContactModel::volume_paper;  // the paper's case, its law
  s.bodies = {polyhedron(0, 0, 1, Eigen::Vector3d(0, 0, -c_world.z() + 1e-7), q,
                         Eigen::Vector3d(0, 0, -v))};
  s.walls = {square_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.05, 0)};
  RefWorld world(s);
  long in_contact = 0;
  for (long k = 0; k < 20000; ++k) {
    world.step();
    if (world.contacts().empty()) {
      if (in_contact > 0) break;
      continue;
    }
    ++in_contact;
    out.depth = std::max(out.depth, world.contacts()[0].depth);
  }
  out.steps = in_contact;
  const RigidBody& b = world.bodies()[0].state;
  // Eqs. 27-28 with this mesh's m, I_yy (about the turned y axis: a transverse principal axis)
  // and r = |C|, alpha from C's axial and radial parts.
  const double m = b.mass;
  const double i_yy = rho * t.principal_moments.x;
  const double r = c_body.norm();
  const double alpha = std::atan2(-c_body.z(), c_body.dot(radial));
  const double arm = r * std::cos(alpha + theta);
  out.theta_deg = theta_deg;
  out.omega_analytic = m * v * (1 + eps) * arm / (i_yy + m * arm * arm);  // Eq. 27
  out.v_z_analytic = out.omega_analytic * arm - eps * v;                  // Eq. 28
  // The paper's frame: z into the wall (V_z^- = +V) and omega_y^+ > 0 for a corner on the +x
  // side; ours has z out of the wall, so both flip.
  out.omega = -b.angular_velocity_world().y();
  out.v_z = -b.velocity.z();
  const double den = i_yy + m * arm * arm;
  out.d_omega_d_arm = std::abs(m * v * (1 + eps) * (i_yy - m * arm * arm) / (den * den));
  out.d_v_z_d_arm = std::abs(out.omega_analytic + arm * out.d_omega_d_arm);
  return out;
}

// The corner's angle alpha of Eq. 27 for this mesh (atan(2.65 / 4) = 33.5 deg): at theta = 90 -
// alpha = 56.5 deg the corner lies under the centre and omega^+ crosses zero.
double cylinder_alpha_deg() {
  return std::atan2(0.0053 / 2, 0.008 / 2) * 180 / M_PI;
}

// Within 5% of Eqs. 27-28, or, where they cross zero (omega at theta = 56.5 deg, V_z near 27.5
// deg), within the change that a shift of the lever arm r cos(alpha + theta) by delta = 25 um
// gives: Eqs. 27-28 take the contact at the fixed corner C, the model at the overlap's centroid,
// inside the penetrated tip (90 um deep at most over the sweep, at 1 m/s; a tip's centroid sits
// at a quarter of its height from its base), so the lever arm is uncertain by about a quarter of
// the depth. d omega / d arm = m V (1 + eps) (I - m arm^2) / (I + m arm^2)^2 and d V_z / d arm
// = omega + arm d omega / d arm: 7.4 rad/s and 0.02 m/s at the crossings (2% of the largest
// omega, 2.4% of V).
void expect_cylinder(double theta_deg) {
  const CylinderImpact c = cylinder_impact(theta_deg);
  std::printf(
      "cylinder theta %5.2f: omega %8.2f (Eq. 27 %8.2f, diff %+6.2f)  V_z %8.4f (Eq. 28 %8.4f, "
      "diff %+7.4f)  depth %.2g m, %ld steps\n",
      c.theta_deg, c.omega, c.omega_analytic, c.omega - c.omega_analytic, c.v_z, c.v_z_analytic,
      c.v_z - c.v_z_analytic, c.depth, c.steps);
  const double delta = 25e-6;
  EXPECT_GT(c.steps, 100);  // resolved
  EXPECT_NEAR(c.omega, c.omega_analytic,
              std::max(0.05 * std::abs(c.omega_analytic), c.d_omega_d_arm * delta));
  EXPECT_NEAR(c.v_z, c.v_z_analytic,
              std::max(0.05 * std::abs(c.v_z_analytic), c.d_v_z_d_arm * delta));
}

// CI: three angles and the crossing (5 s); the sweep below is the full table.
TEST(ReferenceCylinderImpact, Paper31AtFewAngles) {
  for (double theta : {15.0, 30.0, 45.0, 90 - cylinder_alpha_deg()}) expect_cylinder(theta);
}

// The sweep of Fig. 10, 10 to 60 degrees by 5, and the crossing (16 s): run with
// --gtest_also_run_disabled_tests --gtest_filter='*Paper31Sweep*'.
TEST(ReferenceCylinderImpact, DISABLED_Paper31Sweep) {
  for (double theta = 10; theta <= 60.5; theta += 5) expect_cylinder(theta);
  expect_cylinder(90 - cylinder_alpha_deg());
}

}  // namespace
}  // namespace talus::reference

namespace talus::reference {
namespace {

// A cloud: 8 dodecahedra (D = 10 mm, eps = 0.5, no friction) on a 2 x 2 x 2 lattice of spacing
// 11 mm, with random velocities (0.3 m/s towards the centre plus up to 0.2 m/s in each component)
// and spins (up to 100 rad/s), no gravity, no walls: they collide, several at once. Either volume
// law: both are Feng's construction (a potential in the overlap volume), so momentum and angular
// momentum are conserved and the damping only removes energy. E = 0.1 MPa for the paper's law;
// the default law is softer at these overlaps (K V / A_ref against K V^(1/3)): with 0.1 MPa a face
// contact would last 3.4 ms, longer than the 1.4 ms watched, so it gets 10 MPa (0.34 ms).
void expect_cloud(ContactModel model, double youngs) {
  RefWorldSetup s;
  s.effects.contact = model;
  s.templates = {make_shape("dodecahedron:0.01")};
  s.materials = {material(youngs, 0.5)};
  s.time_step = 2e-6;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d x(i & 1 ? 0.0051 : -0.0051, i & 2 ? 0.0051 : -0.0051,
                            i & 4 ? 0.0051 : -0.0051);
    const Eigen::Vector3d jitter(u(rng), u(rng), u(rng));
    const Eigen::Quaterniond q(
        Eigen::AngleAxisd(M_PI * u(rng), Eigen::Vector3d::Random().normalized()));
    RefBodySpec b = polyhedron(0, 0, i + 1, x, q, -1.0 / x.norm() * x + 0.3 * jitter);
    b.angular_velocity = 100 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.bodies.push_back(b);
  }
  RefWorld world(s);
  double mass_speed = 0;  // sum of m |v|: the scale of the momentum
  for (const RefBody& b : world.bodies()) mass_speed += b.state.mass * b.state.velocity.norm();
  const Eigen::Vector3d p0 = world.momentum(), l0 = world.angular_momentum();
  double l_scale = 0;
  for (const RefBody& b : world.bodies()) {
    l_scale += b.state.position.norm() * b.state.mass * b.state.velocity.norm() +
               b.state.angular_momentum_world().norm();
  }
  world.step();
  double energy = world.kinetic_energy() + world.contact_elastic_energy();
  const double e0 = energy;
  double worst_gain = 0, worst_p = 0, worst_l = 0;
  long contact_steps = 0;
  size_t most = 0;
  for (int k = 0; k < 700; ++k) {
    world.step();
    const double e = world.kinetic_energy() + world.contact_elastic_energy();
    worst_gain = std::max(worst_gain, e - energy);
    energy = e;
    worst_p = std::max(worst_p, (world.momentum() - p0).norm());
    worst_l = std::max(worst_l, (world.angular_momentum() - l0).norm());
    contact_steps += world.contacts().empty() ? 0 : 1;
    most = std::max(most, world.contacts().size());
  }
  std::printf(
      "cloud %s: %ld steps with contacts (at most %zu at once), energy %.4g -> %.4g J, largest "
      "one-step gain %.3g J, |dp| %.3g (of %.3g), |dL| %.3g (of %.3g)\n",
      to_string(model), contact_steps, most, e0, energy, worst_gain, worst_p, mass_speed, worst_l,
      l_scale);
  EXPECT_GT(most, 1u);          // several contacts at once
  EXPECT_LT(energy, 0.9 * e0);  // eps = 0.5: the collisions dissipate
  // Every contact applies equal and opposite forces at one point: momentum and angular momentum
  // change only by round-off, a few eps of the sums per step.
  EXPECT_LT(worst_p, 1e-12 * mass_speed);
  EXPECT_LT(worst_l, 1e-12 * l_scale);
  EXPECT_LE(worst_gain, 0.0);
}

TEST(ReferenceWorld, CloudConservesMomentumAndNeverGainsEnergy) {
  expect_cloud(ContactModel::volume, 1e7);
}

TEST(ReferenceWorld, CloudConservesMomentumAndNeverGainsEnergyPaperLaw) {
  expect_cloud(ContactModel::volume_paper, 1e5);
}

// A moving wall's velocity enters the contact (§2.4 walls; issue 3 "moving walls"): a cube at
// rest on a floor that starts translating at u = 10 mm/s. The tangential spring starts empty, so
// the first pull is Eq. 20's damping c_t u, below the Coulomb cap (mu m g = 12 mN): the cube
// starts at a0 = c_t u / m and is then carried by the spring until it moves with the floor. A
// wall velocity left out of the relative velocity would leave the cube at rest.
TEST(ReferenceWorld, TranslatingFloorCarriesTheCube) {
  RefWorldSetup setup = cube_on_slope(0, 0.5, kRestYoungs, kRestStep);
  // eps = 0.5: at eps = 0.1 the calibrated normal damping of a loaded face at rest is ~4 times
  // critical and meets the explicit step's limit m_eff / dt, where the normal force alternates
  // between steps (a known limit of the reference's damping at very low eps, noted in
  // force_law.hpp); this test is about the wall's velocity, not that.
  setup.materials[0].restitution = 0.5;
  RefWorld settled(setup);
  settled.run(5000);  // 0.1 s: at rest on the still floor (CubeOnAPlaneComesToRestAndStays)
  const double u = 0.01;
  setup.walls[0].motion.kind = RefWallMotion::Kind::kTranslation;
  setup.walls[0].motion.velocity = Eigen::Vector3d(u, 0, 0);
  setup.bodies[0].position = settled.bodies()[0].state.position;  // start where it rested
  RefWorld world(setup);

  // Eq. 19 on the 10 mm face (the wall adds no term): k_t = E / (2 (1 + nu) R) A_n, R the
  // equal-volume radius; Eq. 20's c_t with eps = 0.5 (material(): nu = 0.3, rho = 2500).
  const double mass = 2500 * 1e-6, radius = std::cbrt(3e-6 / (4 * M_PI));
  const double k_t = kRestYoungs / (2 * 1.3 * radius) * 1e-4;
  const double log_eps = std::log(0.5);
  const double c_t =
      -2 * log_eps * std::sqrt(k_t * mass) / std::sqrt(log_eps * log_eps + M_PI * M_PI);
  world.step();
  // One step: v = a0 dt, plus the spring's k_t u dt^2 / 2 / m = 1e-3 of it; the contact area
  // is the resting face's to 1e-3 (35 nm deep). 1% covers both and fails for a missing or
  // doubled wall velocity.
  EXPECT_NEAR(world.bodies()[0].state.velocity.x(), c_t * u / mass * kRestStep,
              1e-2 * c_t * u / mass * kRestStep);
  world.run(9999);  // to 0.2 s
  // Carried: the spring oscillates about u with period 2 pi sqrt(m / k_t) = 40 ms and Eq. 20's
  // damping ratio 0.215 (eps = 0.5), decaying at 34 /s: by 0.2 s to exp(-6.8) = 1e-3 of u; 1% of
  // u is above that and far below a cube left behind.
  EXPECT_NEAR(world.bodies()[0].state.velocity.x(), u, 1e-2 * u);
  EXPECT_NEAR(world.bodies()[0].state.velocity.z(), 0, 1e-6);  // still resting on the floor
  EXPECT_EQ(world.contacts().size(), 1u);
}

// The rotating wall's point velocity is omega axis x (x - point), and its triangles turn by
// omega t about the axis through the point.
TEST(ReferenceWorld, RotatingWallMotionIsARigidRotation) {
  RefWallMotion m;
  m.kind = RefWallMotion::Kind::kRotation;
  m.axis = Eigen::Vector3d::UnitZ();
  m.point = Eigen::Vector3d(1, 2, 0);
  m.angular_speed = 2.0;
  const Eigen::Vector3d x0(2, 2, 0.5);  // 1 m from the axis along +x
  // Exact to round-off: the rotation of a unit vector by a quarter turn, 1e-15 m.
  const Eigen::Vector3d quarter = m.position(x0, M_PI / 4);  // 2 rad/s x pi/4 s = 90 degrees
  EXPECT_NEAR((quarter - Eigen::Vector3d(1, 3, 0.5)).norm(), 0, 1e-15);
  const Eigen::Vector3d v = m.velocity_at(quarter, 0.0);  // omega z x (0, 1, 0.5) = (-2, 0, 0)
  EXPECT_NEAR((v - Eigen::Vector3d(-2, 0, 0)).norm(), 0, 1e-15);
}

}  // namespace
}  // namespace talus::reference
