// Force laws of the reference solver against closed forms (the paper's law, volume_paper: Eqs.
// 12-20; BLAZE-DEM Eqs. 2-3) and the area weighting of wall contacts (paper §2.4). The default
// volume law has its own tests: test_default_volume_law.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "reference/contact/contact_geometry.hpp"
#include "reference/contact/force_law.hpp"
#include "tests/reference/reference_test_util.hpp"
#include "tests/reference/world_test_util.hpp"

namespace talus::reference {
namespace {

using testing::kClosedRel;

// An axis-aligned box template with the mass properties the world needs (vertices only are read
// by the exact geometry).
ShapeTemplate box(double lx, double ly, double lz) {
  ShapeTemplate s = testing::box_vertices(lx, ly, lz);
  s.principal_moments =
      Vec3d(s.volume * (ly * ly + lz * lz) / 12, s.volume * (lx * lx + lz * lz) / 12,
            s.volume * (lx * lx + ly * ly) / 12);
  s.bounding_radius = 0.5 * std::sqrt(lx * lx + ly * ly + lz * lz);
  return s;
}

TEST(ReferenceContactLaw, BoxesFaceToFaceVolumeAreaAndForce) {
  // Two 10 mm cubes overlapping by d = 1 mm along x: dV = d a^2, A_n = a^2, n = +x (A into B),
  // |F| = (E/R + E/R) A_n dV^(1/3) (the paper's law, Eqs. 12-13), on A along -x.
  const double a = 0.01, d = 0.001, youngs = 1e7;
  RefWorldSetup s;
  s.templates = {box(a, a, a)};
  s.materials = {testing::material(youngs, 0.5)};
  s.bodies = {testing::polyhedron(0, 0, 1, Eigen::Vector3d::Zero()),
              testing::polyhedron(0, 0, 2, Eigen::Vector3d(a - d, 0, 0))};
  s.time_step = 1e-6;
  s.effects.contact = ContactModel::volume_paper;
  RefWorld world(s);
  world.evaluate_forces(0);
  ASSERT_EQ(world.contacts().size(), 1u);
  const RefContact& c = world.contacts()[0];
  const double radius = std::cbrt(3 * a * a * a / (4 * M_PI));
  const double expected = 2 * youngs / radius * a * a * std::cbrt(d * a * a);
  EXPECT_NEAR(c.volume, d * a * a, kClosedRel * d * a * a);
  EXPECT_NEAR(c.area, a * a, kClosedRel * a * a);
  EXPECT_NEAR((c.normal - Eigen::Vector3d::UnitX()).norm(), 0, kClosedRel);
  // At rest the damping adds nothing: the force is the elastic one, within the closed forms'
  // round-off (kClosedRel, reference_test_util.hpp).
  EXPECT_NEAR((c.force_on_a + expected * Eigen::Vector3d::UnitX()).norm(), 0,
              kClosedRel * expected);
  EXPECT_NEAR((world.bodies()[1].state.force - expected * Eigen::Vector3d::UnitX()).norm(), 0,
              kClosedRel * expected);
  // The contact point is the overlap's centroid, on the centre line: no torque.
  EXPECT_NEAR((c.point - Eigen::Vector3d(0.5 * (a - d), 0, 0)).norm(), 0, kClosedRel * a);
  EXPECT_LT(world.bodies()[0].state.torque.norm(), kClosedRel * expected * a);
}

TEST(ReferenceContactLaw, DampingOpposesTheNormalApproach) {
  // Eq. 15 as printed is negative for eps < 1; the coefficient used is its magnitude, and the
  // damping force on A does negative work on the relative normal motion (Eq. 14).
  const double k = 2e4, m = 1e-3;
  for (double eps : {0.1, 0.5, 0.85, 0.95}) {
    const double l = std::log(eps);
    const double printed = 2 * l * std::sqrt(k * m) / std::sqrt(l * l + M_PI * M_PI);
    const double c = damping_coefficient(eps, k, m);
    EXPECT_GT(c, 0);
    EXPECT_NEAR(c, -printed, 1e-15 * c);  // the same expression up to sign: a few ulps
    NormalContact nc;
    nc.normal = Eigen::Vector3d(0, 0.6, 0.8);
    nc.elastic = 1.0;
    nc.normal_stiffness = k;
    VolumeLawParameters law;
    law.effective_mass = m, law.restitution = eps, law.damping = NormalDamping::kPaper;
    ContactHistory h;
    const Eigen::Vector3d approach = 0.3 * nc.normal, recede = -0.3 * nc.normal;
    const ContactForce in = volume_contact_force(nc, law, approach, 0, h);
    const ContactForce out = volume_contact_force(nc, law, recede, 0, h);
    // Approaching: more push than the elastic force alone; receding: less (exactly c v_n).
    EXPECT_NEAR(in.normal_force.norm(), 1.0 + 0.3 * c, 1e-14);
    EXPECT_NEAR(out.normal_force.norm(), std::max(0.0, 1.0 - 0.3 * c), 1e-14);
    EXPECT_LT(in.normal_force.dot(approach) - (-1.0 * nc.normal).dot(approach), 0);
  }
  EXPECT_EQ(damping_coefficient(1.0, k, m), 0);
  EXPECT_THROW(damping_coefficient(0.0, k, m), std::invalid_argument);
  EXPECT_THROW(damping_coefficient(1.5, k, m), std::invalid_argument);
}

TEST(ReferenceContactLaw, TangentialElasticForceTurnsOntoTheNewPlaneAndIsCappedByCoulomb) {
  NormalContact nc;
  nc.elastic = 10.0, nc.normal_stiffness = 1e4, nc.tangential_stiffness = 5e3;
  VolumeLawParameters law;
  law.effective_mass = 1e-3, law.restitution = 1.0, law.friction = 0.5, law.with_friction = true;
  ContactHistory h;
  h.elastic_force = Eigen::Vector3d(-0.5, 0, 0);  // -k_t Delta-s, in the plane of n = z
  // The normal turns by 0.3 rad about y: the force keeps its length, lies in the new plane, and
  // (v = 0, dt = 0, under the cap) is the tangential force (Eq. 18).
  const double angle = 0.3;
  nc.normal = Eigen::Vector3d(std::sin(angle), 0, std::cos(angle));
  ContactForce f = volume_contact_force(nc, law, Eigen::Vector3d::Zero(), 0, h);
  EXPECT_FALSE(f.sliding);
  EXPECT_NEAR(h.elastic_force.norm(), 0.5, 1e-15);
  EXPECT_NEAR(h.elastic_force.dot(nc.normal), 0, 1e-16);  // in the tangent plane
  EXPECT_NEAR(h.elastic_force.x(), -0.5 * std::cos(angle), 1e-15);
  EXPECT_NEAR((f.tangential_force - h.elastic_force).norm(), 0, 1e-15);
  // An elastic force over mu |F_n| = 5 N: the force is capped to 5 N along it, and so is the
  // stored elastic part (Eq. 17).
  h.elastic_force = Eigen::Vector3d(0, -50, 0);
  f = volume_contact_force(nc, law, Eigen::Vector3d::Zero(), 0, h);
  EXPECT_TRUE(f.sliding);
  EXPECT_NEAR(f.tangential_force.norm(), 0.5 * 10.0, 1e-12);
  EXPECT_NEAR(f.tangential_force.normalized().dot(-Eigen::Vector3d::UnitY()), 1, 1e-12);
  EXPECT_NEAR(h.elastic_force.norm(), 5.0, 1e-12);
  // It changes by -k_t v_t dt (the normal part of v does not count), with the present k_t: a
  // stiffer contact at rest keeps its force.
  h.elastic_force.setZero();
  nc.normal = Eigen::Vector3d::UnitZ();
  volume_contact_force(nc, law, Eigen::Vector3d(1e-3, 0, 7.0), 1e-3, h);
  EXPECT_NEAR((h.elastic_force - Eigen::Vector3d(-5e-3, 0, 0)).norm(), 0, 1e-17);
  nc.tangential_stiffness = 2e4;
  f = volume_contact_force(nc, law, Eigen::Vector3d::Zero(), 1e-3, h);
  EXPECT_NEAR((f.tangential_force - Eigen::Vector3d(-5e-3, 0, 0)).norm(), 0, 1e-17);
}

TEST(ReferenceContactLaw, LinearModelNumbers) {
  // Two spheres r = 5 mm, centres 9 mm apart: delta = 1 mm along the centre line, the point
  // midway between the deepest points; F_N = K delta + eta v_n (Eq. 2), F_T from Eq. 3.
  const PairGeometry g =
      linear_sphere_geometry(Eigen::Vector3d::Zero(), 0.005, Eigen::Vector3d(0.009, 0, 0), 0.005);
  ASSERT_TRUE(g.in_contact);
  EXPECT_NEAR(g.depth, 0.001, 1e-17);
  EXPECT_NEAR((g.point - Eigen::Vector3d(0.0045, 0, 0)).norm(), 0, 1e-17);
  NormalContact nc;
  nc.normal = g.normal, nc.point = g.point, nc.elastic = 1e4 * g.depth;
  LinearLawParameters law;
  law.stiffness = 1e4, law.damping = 2.0, law.tangential_damping = 3.0, law.friction = 0.4;
  law.with_friction = true;
  // Slow sliding: gamma |v_T| = 0.3 N < mu K delta = 4 N.
  ContactForce f = linear_contact_force(nc, law, Eigen::Vector3d(0.5, 0.1, 0));
  EXPECT_NEAR(f.normal_force.x(), -(10.0 + 2.0 * 0.5), 1e-12);
  EXPECT_NEAR((f.tangential_force - Eigen::Vector3d(0, -0.3, 0)).norm(), 0, 1e-14);
  EXPECT_FALSE(f.sliding);
  // Fast sliding: the cap mu K delta = 4 N.
  f = linear_contact_force(nc, law, Eigen::Vector3d(0, 0, -10));
  EXPECT_NEAR((f.tangential_force - Eigen::Vector3d(0, 0, 4.0)).norm(), 0, 1e-12);
  EXPECT_TRUE(f.sliding);

  // Boxes by the separating-axis test: 20 x 10 x 10 mm box and 10 mm cube; B shifted by
  // (14, 3, 2) mm overlaps A by 1 mm in x, 7 in y, 8 in z: delta = 1 mm along +x.
  const ShapeTemplate a = make_shape("cuboid:0.02,0.01,0.01"),
                      b = make_shape("cuboid:0.01,0.01,0.01");
  RefPose pa, pb;
  // The body x axis has the smallest moment: the 20 mm side lies along x.
  pb.position = Eigen::Vector3d(0.014, 0.003, 0.002);
  const PairGeometry sat = linear_polyhedra_geometry(a, pa, b, pb);
  ASSERT_TRUE(sat.in_contact);
  EXPECT_NEAR(sat.depth, 0.001, 1e-15);  // a few ulps of the 10 mm coordinates
  EXPECT_NEAR((sat.normal - Eigen::Vector3d::UnitX()).norm(), 0, 1e-12);
  // Sphere r = 3 mm whose centre is 1 mm off the cube's +x face (outside), and 1 mm inside.
  const PairGeometry out =
      linear_polyhedron_sphere_geometry(b, RefPose{}, Eigen::Vector3d(0.006, 0, 0), 0.003);
  ASSERT_TRUE(out.in_contact);
  EXPECT_NEAR(out.depth, 0.002, 1e-15);
  EXPECT_NEAR((out.point - Eigen::Vector3d(0.004, 0, 0)).norm(), 0, 1e-15);
  const PairGeometry in =
      linear_polyhedron_sphere_geometry(b, RefPose{}, Eigen::Vector3d(0.004, 0.001, 0), 0.003);
  EXPECT_NEAR(in.depth, 0.004, 1e-15);
  EXPECT_NEAR((in.normal - Eigen::Vector3d::UnitX()).norm(), 0, 1e-15);
}

// The wall contact of one cube over the diagonal of a square made of two triangles, or over one
// big triangle covering the same region: the area weights of the halves sum to 1 (§2.4).
RefContact cube_on(const std::vector<RefTriangle>& triangles) {
  RefWorldSetup s;
  s.templates = {box(0.01, 0.01, 0.01)};
  s.materials = {testing::material(1e6, 0.5)};
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  s.bodies = {testing::polyhedron(0, 0, 1, Eigen::Vector3d(0.001, -0.0005, 0.006), q)};
  RefWall wall;
  wall.triangles = triangles;
  wall.material = 0;
  s.walls = {wall};
  s.time_step = 1e-6;
  RefWorld world(s);
  world.evaluate_forces(0);
  EXPECT_EQ(world.contacts().size(), 1u);
  return world.contacts().empty() ? RefContact{} : world.contacts()[0];
}

TEST(ReferenceContactLaw, WallAreaWeightingOverTwoCoplanarTrianglesEqualsOneTriangle) {
  const Eigen::Vector3d p00(-0.05, -0.05, 0), p10(0.05, -0.05, 0), p11(0.05, 0.05, 0),
      p01(-0.05, 0.05, 0);
  const RefContact two = cube_on({{p00, p10, p11}, {p00, p11, p01}});
  const RefContact one = cube_on({{Eigen::Vector3d(-0.2, -0.2, 0), Eigen::Vector3d(0.2, -0.2, 0),
                                   Eigen::Vector3d(0, 0.2, 0)}});
  // The exact areas are rounded to double with a relative error below 1e-10 (test_wall_area
  // measures 1.4e-11 at worst over 400 poses); the force is linear in them.
  const double f = one.force_on_a.norm();
  ASSERT_GT(f, 0);
  EXPECT_NEAR(two.weight, 1.0, 1e-10);
  EXPECT_NEAR((two.force_on_a - one.force_on_a).norm(), 0, 1e-10 * f);
  EXPECT_NEAR((two.point - one.point).norm(), 0, 1e-10 * 0.01);
  EXPECT_NEAR((one.normal + Eigen::Vector3d::UnitZ()).norm(), 0, 1e-12);
}

}  // namespace
}  // namespace talus::reference

namespace talus::reference {
namespace {

// Sphere on a wall, linear model (nearest-facet rule, world.cpp): a sphere r = 5 mm pressed
// 0.1 mm into a square of two triangles gets F = K_N delta along +z at the point midway between
// the surface and its deepest point, the same in a triangle's middle, on the shared diagonal and
// at a corner the two share: no facet counts twice.
TEST(ReferenceContactLaw, SphereOnAWallLinearModelCountsEachFacetOnce) {
  const double r = 0.005, delta = 1e-4, k = 1e4;
  for (const Eigen::Vector3d& xy : {Eigen::Vector3d(0.01, -0.01, 0), Eigen::Vector3d(0.01, 0.01, 0),
                                    Eigen::Vector3d(-0.025, -0.025, 0)}) {
    RefWorldSetup s;
    s.materials = {testing::material(1e6, 0.5)};
    s.effects.contact = ContactModel::linear;
    s.effects.linear.stiffness = k;
    RefBodySpec b;
    b.kind = ParticleShapeKind::sphere;
    b.sphere_radius = r;
    b.material = 0;
    b.id = 1;
    b.position = xy + Eigen::Vector3d(0, 0, r - delta);
    s.bodies = {b};
    s.walls = {testing::square_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.05, 0)};
    s.time_step = 1e-6;
    RefWorld world(s);
    world.evaluate_forces(0);
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& c = world.contacts()[0];
    // delta is r - (r - delta) in double: a few ulps of 5 mm, 1e-18 m; the force K_N times it.
    EXPECT_NEAR(c.depth, delta, 1e-17);
    EXPECT_NEAR((c.force_on_a - k * delta * Eigen::Vector3d::UnitZ()).norm(), 0, 1e-13);
    EXPECT_NEAR((c.point - (xy - 0.5 * delta * Eigen::Vector3d::UnitZ())).norm(), 0, 1e-17);
    EXPECT_NEAR(world.bodies()[0].state.torque.norm(), 0, 1e-18);  // the point is under c
  }
}

// Both volume laws still refuse spheres with walls, naming the way out.
TEST(ReferenceContactLaw, SphereOnAWallVolumeModelIsRefused) {
  for (const ContactModel model : {ContactModel::volume, ContactModel::volume_paper}) {
    RefWorldSetup s;
    s.effects.contact = model;
    s.materials = {testing::material(1e6, 0.5)};
    RefBodySpec b;
    b.kind = ParticleShapeKind::sphere;
    b.sphere_radius = 0.005;
    b.material = 0;
    b.position = Eigen::Vector3d(0, 0, 0.01);
    s.bodies = {b};
    s.walls = {testing::square_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.05, 0)};
    s.time_step = 1e-6;
    EXPECT_THROW(RefWorld world(s), std::invalid_argument);
  }
}

// beta(eps) of the calibrated damping inverts the clamped oscillator (force_law.hpp).
TEST(ReferenceContactLaw, CalibratedDampingRatioGivesTheRestitution) {
  for (double eps : {0.1, 0.5, 0.85, 0.95}) {
    const double beta = calibrated_damping_ratio(eps);
    std::printf("calibrated damping: eps %.2f beta %.6f\n", eps, beta);
    // The bisection stops at 1e-10 relative in beta; the rebound speed is smooth in beta.
    EXPECT_NEAR(clamped_volume_oscillator_restitution(beta), eps, 1e-8);
  }
  EXPECT_EQ(calibrated_damping_ratio(1.0), 0.0);
  // Monotone: more damping, less rebound.
  EXPECT_GT(calibrated_damping_ratio(0.1), calibrated_damping_ratio(0.5));
  EXPECT_THROW(calibrated_damping_ratio(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace talus::reference
