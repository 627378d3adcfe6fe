// The volume laws' rotational terms in the reference solver: the wall contact point (the default
// law: each facet's clipped section's centroid, the exact torque of U(V); volume_paper: moved by
// the offset of the volume below the plane from the whole section's centroid,
// reference/geometry/wall_area.hpp, reference/world/world.cpp), the default law's torques as the
// rate of its energy under a turn (pair and wall), and its patch couple
// (reference/contact/force_law.hpp, patch_couple), against hand computations: a tilted cube's
// wedge below a plane, the torque it gets, and the rocking and twisting moments for a given
// relative angular velocity; the rocking spring in a pair's history and at a wall. The rocking
// spring's own rules: test_rocking_spring.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "reference/contact/force_law.hpp"
#include "reference/geometry/exact_overlap.hpp"
#include "reference/geometry/wall_area.hpp"
#include "solver/shape/builtins.hpp"
#include "tests/reference/reference_test_util.hpp"
#include "tests/reference/world_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::reference {
namespace {

using testing::at;
using testing::box_vertices;
using testing::kClosedRel;
using testing::material;
using testing::polyhedron;
using testing::square_wall;
using testing::to_eigen;
using testing::turn_axes;
using testing::turned;

// An axis-aligned box template with the mass properties the world needs.
ShapeTemplate box(double lx, double ly, double lz) {
  ShapeTemplate s = box_vertices(lx, ly, lz);
  s.principal_moments =
      Vec3d(s.volume * (ly * ly + lz * lz) / 12, s.volume * (lx * lx + lz * lz) / 12,
            s.volume * (lx * lx + ly * ly) / 12);
  s.bounding_radius = 0.5 * std::sqrt(lx * lx + ly * ly + lz * lz);
  return s;
}

double equal_volume_radius(double volume) {
  return std::cbrt(3 * volume / (4 * M_PI));
}

// Eqs. 15 and 20 with the dissipating sign, written out again: 2 zeta sqrt(k m).
double dashpot(double restitution, double stiffness, double mass) {
  const double l = std::log(restitution);
  return -2 * l / std::sqrt(l * l + M_PI * M_PI) * std::sqrt(stiffness * mass);
}

// A cube of side L turned by theta about +y (its body +x edge goes down: the deep side is world
// +x) and sunk into the plane z = 0 by the mean depth D along its axis. In the body frame the
// plane is b3 = h0 + t b1, t = tan(theta), h0 = D - L/2 (the centre at z_c = (L/2 - D) cos(theta));
// with D > t L / 2 the whole bottom face is below it, and the part below is a wedge-topped prism
// over the square face: columns of height c(b1) = D + t b1. Its volume is L^2 D, its centroid
// b1 = t L^2 / (12 D), b3 = -L/2 + (integral of c^2) / (2 integral of c) = -L/2 + D/2 +
// t^2 L^2 / (24 D). The section is the prism's cut by the plane: area L^2 / cos(theta), centroid
// where the cube's axis pierces the plane, body (0, 0, h0). For small theta and D << L the
// in-plane offset from the section's centroid to the volume's is theta L^2 / (12 D) towards the
// deep side (the wedge's hand computation); exactly it is b1 cos(theta) + (b3 - h0) sin(theta).
struct TiltedCube {
  double side = 0.01, tilt = 0.01, depth = 0.0001;  // L, theta, D
  double tan_tilt() const { return std::tan(tilt); }
  double centre_height() const { return (0.5 * side - depth) * std::cos(tilt); }
  double plane_offset() const { return depth - 0.5 * side; }  // h0
  Eigen::Quaterniond orientation() const {
    return Eigen::Quaterniond(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()));
  }
  // Body (a, 0, c) in the world.
  Eigen::Vector3d world(double a, double c) const {
    const double cs = std::cos(tilt), sn = std::sin(tilt);
    return {a * cs + c * sn, 0, centre_height() - a * sn + c * cs};
  }
  double centroid_b1() const { return tan_tilt() * side * side / (12 * depth); }
  double centroid_b3() const {
    const double t = tan_tilt();
    return -0.5 * side + 0.5 * depth + t * t * side * side / (24 * depth);
  }
  Eigen::Vector3d section_centroid() const { return world(0, plane_offset()); }
  Eigen::Vector3d volume_centroid() const { return world(centroid_b1(), centroid_b3()); }
  double exact_offset() const {  // along +x
    return centroid_b1() * std::cos(tilt) + (centroid_b3() - plane_offset()) * std::sin(tilt);
  }
  double wedge_offset() const { return tilt * side * side / (12 * depth); }  // small theta
};

const Eigen::Vector3d kBigA(-10, -10, 0), kBigB(20, -10, 0), kBigC(-10, 20, 0);

TEST(ReferenceWallPoint, TiltedCubeVolumeOffsetAgainstTheWedge) {
  const TiltedCube cube;
  const double l = cube.side;
  ASSERT_GT(cube.depth, 0.5 * cube.tan_tilt() * l);  // the whole bottom face is below
  const RefWallContact w =
      wall_contact(box_vertices(l, l, l), at(0, 0, cube.centre_height(), cube.orientation()), kBigA,
                   kBigB, kBigC);
  ASSERT_TRUE(w.reaches_plane);
  EXPECT_NEAR(w.volume_below, l * l * cube.depth, kClosedRel * l * l * l);
  EXPECT_NEAR(w.section_area, l * l / std::cos(cube.tilt), kClosedRel * l * l);
  // The centroids and the offset: exact geometry rounded once; the closed forms' round-off is a
  // few ulps of L, amplified by ~L / D = 100 in b1 = t L^2 / (12 D). kClosedRel L covers it.
  EXPECT_LT((w.section_centroid - cube.section_centroid()).norm(), kClosedRel * l);
  EXPECT_LT((w.volume_below_centroid - cube.volume_centroid()).norm(), kClosedRel * l);
  const Eigen::Vector3d offset = w.volume_offset;
  EXPECT_LT((offset - cube.exact_offset() * Eigen::Vector3d::UnitX()).norm(), kClosedRel * l);
  EXPECT_EQ(offset.z(), 0.0);  // in the plane: the projection removes z exactly
  // The wedge's small-angle value theta L^2 / (12 D), towards the deep side (+x): the exact form
  // differs by -6 D^2 / L^2 (the volume's centroid lies D/2 below the section along the tilted
  // axis) and by O(theta^2), 6.5e-4 relative here.
  EXPECT_GT(offset.x(), 0.0);
  EXPECT_NEAR(offset.x(), cube.wedge_offset(), 1e-3 * cube.wedge_offset());
  std::printf(
      "tilted cube: volume offset %.6g m, wedge theta L^2 / (12 D) = %.6g m (%.2e relative), "
      "section centroid %.6g m from below the centre\n",
      offset.x(), cube.wedge_offset(), offset.x() / cube.wedge_offset() - 1,
      w.section_centroid.x());
}

// The same cube on a plane wall at rest, in a world. volume_paper's contact point is the
// section's centroid plus the offset, under the deep side, so its normal force levels the cube
// (torque against the tilt). The default and the linear laws keep the section's centroid, on the
// shallow side of the centre: their force tips the cube further. For the default law that is the
// exact torque of its potential, -dU/dtheta: U(V) alone is an inverted pendulum on a face, and the
// tilt stiffness is the rocking spring's, which holds nothing at rest before any rotation
// (test_rocking_spring.cpp).
TEST(ReferenceWallPoint, TiltedCubeOnAPlaneWall_PointAndTorque) {
  const TiltedCube cube;
  const double l = cube.side, youngs = 1e7;
  const Eigen::Vector3d centre(0, 0, cube.centre_height());
  const auto world_of = [&](ContactModel model, const Eigen::Quaterniond& orientation) {
    RefWorldSetup s;
    s.templates = {box(l, l, l)};
    s.materials = {material(youngs, 0.5, 0.5)};
    s.time_step = 1e-6;
    s.effects.contact = model;
    s.effects.linear.stiffness = 1e4;
    s.effects.friction = true;
    s.effects.rotation = true;
    s.bodies = {polyhedron(0, 0, 1, centre, orientation)};
    s.walls = {square_wall(Eigen::Vector3d(0.002, -0.001, 0), Eigen::Vector3d::UnitZ(), 0.05, 0)};
    RefWorld world(s);
    world.evaluate_forces(0);
    return world;
  };
  for (const ContactModel model :
       {ContactModel::volume, ContactModel::volume_paper, ContactModel::linear}) {
    const RefWorld world = world_of(model, cube.orientation());
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& c = world.contacts()[0];
    const Eigen::Vector3d torque = world.bodies()[0].state.torque;
    const double force = c.force_on_a.z();
    ASSERT_GT(force, 0);
    // At rest the force is the elastic one along +z (the plane's normal; both facets coplanar).
    EXPECT_LT(c.force_on_a.head<2>().norm(), 1e-12 * force);
    // Each facet's point carries the same offset (the same plane), so the weighted mean of the two
    // facets' points is the section's centroid plus it.
    const double offset = model == ContactModel::volume_paper ? cube.exact_offset() : 0.0;
    const Eigen::Vector3d point = cube.section_centroid() + offset * Eigen::Vector3d::UnitX();
    EXPECT_LT((c.point - point).norm(), kClosedRel * l) << to_string(model);
    // (point - x) x F about y: -x_p F, x_p the point's x from the centre. At rest, at the first
    // evaluation (dt = 0), the patch couple is zero.
    EXPECT_NEAR(torque.y(), -point.x() * force, 1e-12 * l * force) << to_string(model);
    EXPECT_NEAR(torque.x(), 0, 1e-12 * l * force);
    EXPECT_NEAR(torque.z(), 0, 1e-12 * l * force);
    if (model != ContactModel::volume_paper) {
      // The section's centroid is on the shallow side, (L/2 - D) sin(theta) from below the
      // centre: a torque along the tilt (+y), i.e. tipping further.
      EXPECT_GT(torque.y(), 0) << "the section's centroid tips the cube back";
    } else {
      // Against the tilt (+theta about y): restoring, with the lever theta L^2 / (12 D) less the
      // section's (L/2 - D) sin(theta) to within the wedge's approximation.
      EXPECT_LT(torque.y(), 0) << to_string(model);
      const double lever = cube.wedge_offset() - (0.5 * l - cube.depth) * std::sin(cube.tilt);
      EXPECT_NEAR(-torque.y() / force, lever, 1e-3 * cube.wedge_offset()) << to_string(model);
    }
    if (model == ContactModel::volume) {
      // -dE/dtheta by a central difference, the cube turned about y through its centroid by
      // +-h, E the contact's sum_i w_i U(V_i) = U(V) (the section lies within the wall, so the
      // weights sum to 1 at every angle). E = |F| D / 2 here; its round-off (the exact volume
      // rounded once, the turned corners rounded: ~1e-14 relative) over 2h is ~1e-13 |F| m, and
      // the truncation h^2 / (6 theta) relative (V ~ 1 / cos(theta) at a fixed centre): 2e-11.
      // Both are far below 1e-6 of the torque (|F| times a lever of 5e-5 m).
      const double h = 1e-6;
      const auto energy = [&](double angle) {
        const RefWorld turned =
            world_of(model, Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY())));
        return turned.contacts().at(0).elastic_energy;
      };
      const double rate = (energy(cube.tilt + h) - energy(cube.tilt - h)) / (2 * h);
      EXPECT_NEAR(torque.y(), -rate, 1e-6 * std::abs(torque.y()));
      std::printf("volume: torque about y %.10g N m, -dU/dtheta %.10g N m\n", torque.y(), -rate);
    }
    std::printf("%s: torque about y %.4g N m for |F| %.4g N (lever %.4g m)\n", to_string(model),
                torque.y(), force, -torque.y() / force);
  }
}

// Released tilted by 0.03 rad with its low edge touching the plane, under gravity, friction and
// rotation, the cube comes to rest face down under the default law: U(V)'s torque rights it once
// the face touches, the rocking spring stiffens the face's tilt and the patch's dashpots damp the
// rocking. It does not end exactly level: the spring slips at its cap while the cube lands and
// rocks, and then keeps a moment that balances U(V)'s at a small tilt (measured at 50 ms: tilt
// 1.13e-4 rad, the face touching only near its low edge, the point 1.56 mm from under the centre,
// the spring holding 3.8e-5 N m = 0.31 m g L / 2; speed 2e-6 m/s, spin 3e-4 rad/s; it stays so
// to 150 ms). The old law without the spring (the force at the volume's centroid) ended level to
// 3.6e-7 rad; the bound 5e-4 rad says "face down" (the face's own depth is 2e-7 m over L = 1e-2 m)
// with room for the spring's memory.
TEST(ReferenceWallPoint, TiltedCubeComesToRestOnItsFace) {
  const double l = 0.01, theta = 0.03, g = 9.81;
  RefWorldSetup s;
  s.templates = {box(l, l, l)};
  s.materials = {material(1e7, 0.5, 0.5)};
  s.time_step = 1e-5;
  s.effects.gravity = Eigen::Vector3d(0, 0, -g);
  s.effects.friction = true;
  s.effects.rotation = true;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
  // The lowest corners (body x = +L/2, z = -L/2) just on the plane.
  const double height = 0.5 * l * (std::sin(theta) + std::cos(theta));
  s.bodies = {polyhedron(0, 0, 1, Eigen::Vector3d(0, 0, height), q)};
  s.walls = {square_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.05, 0)};
  RefWorld world(s);
  // 50 ms: it falls from the edge onto the face by ~10 ms, rocks and is at rest by ~30 ms.
  world.run(5000);
  const RigidBody& b = world.bodies()[0].state;
  const double tilt = std::acos(std::min(1.0, (b.orientation * Eigen::Vector3d::UnitZ()).z()));
  ASSERT_EQ(world.contacts().size(), 1u);
  const RefContact& c = world.contacts()[0];
  std::printf(
      "tilted cube released: tilt %.3g rad after 50 ms (from %.3g), speed %.3g m/s, "
      "spin %.3g rad/s, point %.3g m from under the centre, springs' energy %.3g J\n",
      tilt, theta, b.velocity.norm(), b.angular_velocity_world().norm(),
      (c.point - b.position).head<2>().norm(), c.tangential_energy);
  EXPECT_LT(tilt, 5e-4);
  EXPECT_LT(b.velocity.norm(), 1e-4);
  EXPECT_LT(b.angular_velocity_world().norm(), 1e-2);
  // At rest it carries its weight.
  EXPECT_NEAR(c.force_on_a.z(), b.mass * g, 1e-3 * b.mass * g);
}

// The couple's two parts against their formulas for a given w_rel, and their caps, at a
// contact's first evaluation (a fresh history, dt = 0: the rocking spring holds nothing).
TEST(ReferencePatchCouple, RockingAndTwistingFormulas) {
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 2) / 3;
  const Eigen::Vector3d w(0.3, -0.2, 0.7);
  const double area = 1e-4, friction = 0.5, c_n = 3, c_t = 2, k_n = 5e4;
  const double w_n = w.dot(n);
  const Eigen::Vector3d w_perp = w - w_n * n;
  ContactForce f;
  f.normal_damping = c_n;
  f.tangential_damping = c_t;
  f.tangential_force = Eigen::Vector3d(0.1, -0.3, 0.1);  // not read
  const auto first = [&](double a) {
    ContactHistory fresh;
    return patch_couple(f, n, a, k_n, friction, w, 0.0, fresh);
  };

  // Under a large load neither cap binds: -c_n A/12 w_perp and -c_t A/6 w_n n.
  f.normal_force = -100 * n;
  PatchCouple pc = first(area);
  const Eigen::Vector3d rocking = -c_n * area / 12 * w_perp;
  const Eigen::Vector3d twisting = -c_t * area / 6 * w_n * n;
  EXPECT_LT((pc.rocking - rocking).norm(), 1e-15 * rocking.norm());
  EXPECT_LT((pc.twisting - twisting).norm(), 1e-15 * twisting.norm());
  EXPECT_LT((pc.total() - rocking - twisting).norm(), 1e-15 * rocking.norm());
  EXPECT_NEAR(pc.rocking.dot(n), 0, 1e-15 * rocking.norm());  // in the contact plane
  const double power = c_n * area / 12 * w_perp.squaredNorm() + c_t * area / 6 * w_n * w_n;
  EXPECT_NEAR(pc.dissipation, power, 1e-14 * power);
  EXPECT_GT(pc.dissipation, 0);
  EXPECT_EQ(pc.spring_energy, 0.0);

  // Under a light load both caps bind: the rocking moment is |F_n| sqrt(A) / 2 against w_perp,
  // the twisting mu |F_n| (2/3) sqrt(A / pi) against w_n.
  const double load = 1e-3;
  f.normal_force = -load * n;
  pc = first(area);
  const double rocking_cap = load * std::sqrt(area) / 2;
  const double twisting_cap = friction * load * 2 / 3 * std::sqrt(area / M_PI);
  ASSERT_GT(rocking.norm(), rocking_cap);
  ASSERT_GT(std::abs(twisting.dot(n)), twisting_cap);
  EXPECT_LT((pc.rocking + rocking_cap * w_perp.normalized()).norm(), 1e-15 * rocking_cap);
  EXPECT_LT((pc.twisting + twisting_cap * (w_n > 0 ? 1 : -1) * n).norm(), 1e-15 * twisting_cap);
  EXPECT_GT(pc.dissipation, 0);

  // No push (the no-tension rule dropped the normal force), no area: no couple.
  f.normal_force.setZero();
  EXPECT_EQ(first(area).total(), Eigen::Vector3d::Zero());
  f.normal_force = -100 * n;
  EXPECT_EQ(first(0).total(), Eigen::Vector3d::Zero());
  // Without friction c_t = 0: no twisting.
  f.tangential_damping = 0;
  EXPECT_EQ(first(area).twisting, Eigen::Vector3d::Zero());
}

// A cube face down on a rotating plane wall, spinning: the world gives the particle the couple
// of the formulas with the law's own c_n (Eq. 15 on k_n = K A^2 / A_ref) and c_t (Eq. 20 on
// k_t = G A), w_rel = w - Omega z, and the wall its opposite. At a face contact the point lies
// under the centre, so the spin adds no normal speed and |F_n| is the elastic K V A / A_ref.
TEST(ReferencePatchCouple, CubeSpinningOnARotatingWall) {
  const double l = 0.01, youngs = 1e7, nu = 0.3, eps = 0.5, mu = 0.5, depth = 1e-6;
  const double omega_wall = 0.4, dt = 1e-5;
  const Eigen::Vector3d w(0.3, -0.2, 0.7), centre(0.001, -0.002, 0.5 * l - depth);
  RefWorldSetup s;
  s.templates = {box(l, l, l)};
  s.materials = {material(youngs, eps, mu, 2500, nu)};
  s.time_step = dt;
  s.effects.friction = true;
  s.effects.rotation = true;
  RefBodySpec body = polyhedron(0, 0, 1, centre);
  body.angular_velocity = w;
  s.bodies = {body};
  RefWall wall = square_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.05, 0);
  wall.motion.kind = RefWallMotion::Kind::kRotation;
  wall.motion.axis = Eigen::Vector3d::UnitZ();
  wall.motion.angular_speed = omega_wall;
  s.walls = {wall};
  for (const bool rotation : {true, false}) {
    s.effects.rotation = rotation;
    RefWorld world(s);
    world.evaluate_forces(0);
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& c = world.contacts()[0];
    if (!rotation) {
      EXPECT_EQ(c.couple, Eigen::Vector3d::Zero());
      continue;
    }
    const double mass = world.bodies()[0].state.mass;
    const double r = equal_volume_radius(l * l * l), area = l * l, volume = area * depth;
    const double k = youngs / r, a_ref = M_PI * r * r;
    const double k_n = k * area * area / a_ref, k_t = youngs / (2 * (1 + nu) * r) * area;
    const double c_n = std::min(dashpot(eps, k_n, mass), mass / dt), c_t = dashpot(eps, k_t, mass);
    const double load = k * volume / a_ref * area;
    const Eigen::Vector3d n = -Eigen::Vector3d::UnitZ();  // from the particle into the wall
    EXPECT_LT((c.normal - n).norm(), 1e-15);
    EXPECT_NEAR((c.force_on_a - c.tangential_force).norm(), load, kClosedRel * load);
    const Eigen::Vector3d w_rel = w - omega_wall * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d w_perp = w_rel - w_rel.dot(n) * n;
    const Eigen::Vector3d couple =
        -c_n * area / 12 * w_perp - c_t * area / 6 * w_rel.dot(n) * n;  // neither cap binds here
    ASSERT_LT(c_n * area / 12 * w_perp.norm(), load * std::sqrt(area) / 2);
    ASSERT_LT(c_t * area / 6 * std::abs(w_rel.dot(n)), mu * load * 2 / 3 * std::sqrt(area / M_PI));
    EXPECT_LT((c.couple - couple).norm(), 1e-12 * couple.norm());
    const Eigen::Vector3d expected_torque = (c.point - centre).cross(c.force_on_a) + couple;
    EXPECT_LT((world.bodies()[0].state.torque - expected_torque).norm(), 1e-12 * couple.norm());
    // The wall loses both: its torque about its axis point (the origin).
    const Eigen::Vector3d wall_torque = -c.point.cross(c.force_on_a) - couple;
    EXPECT_LT((world.wall_torque(0) - wall_torque).norm(), 1e-12 * couple.norm());
    std::printf("cube spinning on a rotating wall: rocking %.4g N m, twisting %.4g N m\n",
                (couple - couple.dot(n) * n).norm(), std::abs(couple.dot(n)));

    // One more evaluation that advances the springs by dt (the state unchanged): the rocking
    // spring holds -k_r w_perp dt, k_r = k_n A / 12, the particle as A, and the contact's spring
    // energy is the tangential spring's k_t |v_t dt|^2 / 2 plus the rocking spring's
    // k_r |w_perp dt|^2 / 2 (neither cap binds: asserted).
    world.evaluate_forces(dt);
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& next = world.contacts()[0];
    const double k_r = k_n * area / 12;
    const Eigen::Vector3d rocking = -(k_r * dt + c_n * area / 12) * w_perp;
    ASSERT_LT(rocking.norm(), load * std::sqrt(area) / 2);
    EXPECT_LT((next.couple - next.couple.dot(n) * n - rocking).norm(), 1e-12 * rocking.norm());
    const Eigen::Vector3d v_r =
        w.cross(next.point - centre) - omega_wall * Eigen::Vector3d::UnitZ().cross(next.point);
    const Eigen::Vector3d v_t = v_r - v_r.dot(n) * n;
    ASSERT_LT((k_t * dt + c_t) * v_t.norm(), mu * load);
    const double energy =
        0.5 * k_t * (v_t * dt).squaredNorm() + 0.5 * k_r * (w_perp * dt).squaredNorm();
    EXPECT_NEAR(next.tangential_energy, energy, 1e-12 * energy);
    std::printf("after dt: rocking spring %.4g N m, springs' energy %.4g J (rocking %.4g J)\n",
                k_r * dt * w_perp.norm(), next.tangential_energy,
                0.5 * k_r * (w_perp * dt).squaredNorm());
  }
}

// Two particles face on face (a 10 mm cube A under a 6 x 6 x 10 mm box B, overlapping by d, so
// A_n = 36 mm^2 and n = +z), each spinning: A gets the couple of the formulas with m_eff and the
// pair's K, G; B its opposite. The other laws have none. The overlap's surface moment is zero
// here (A's part is the overlap's top face, straight above its centroid), and the springs hold
// nothing at the first evaluation.
TEST(ReferencePatchCouple, PairOfBoxesFaceOnFace) {
  const double a = 0.01, b = 0.006, d = 1e-5, youngs = 1e7, nu = 0.3, eps = 0.5, mu = 0.4;
  const double dt = 1e-6;
  const Eigen::Vector3d w_a(0.5, 0.1, -0.3), w_b(-0.2, 0.4, 0.9);
  const Eigen::Vector3d x_a = Eigen::Vector3d::Zero(), x_b(0, 0, 0.5 * (a + a) - d);
  for (const ContactModel model : {ContactModel::volume, ContactModel::volume_paper}) {
    RefWorldSetup s;
    s.templates = {box(a, a, a), box(b, b, a)};
    s.materials = {material(youngs, eps, mu, 2500, nu)};
    s.time_step = dt;
    s.effects.contact = model;
    s.effects.friction = true;
    s.effects.rotation = true;
    RefBodySpec body_a = polyhedron(0, 0, 1, x_a), body_b = polyhedron(1, 0, 2, x_b);
    body_a.angular_velocity = w_a;
    body_b.angular_velocity = w_b;
    s.bodies = {body_a, body_b};
    RefWorld world(s);
    world.evaluate_forces(0);
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& c = world.contacts()[0];
    ASSERT_EQ(c.body_a, 0);
    const Eigen::Vector3d& torque_a = world.bodies()[0].state.torque;
    const Eigen::Vector3d& torque_b = world.bodies()[1].state.torque;
    const double scale = c.force_on_a.norm() * a;
    if (model != ContactModel::volume) {
      EXPECT_EQ(c.couple, Eigen::Vector3d::Zero());
      EXPECT_LT((torque_a - (c.point - x_a).cross(c.force_on_a)).norm(), 1e-15 * scale);
      continue;
    }
    const double area = b * b, volume = area * d;
    EXPECT_NEAR(c.area, area, kClosedRel * area);
    const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    EXPECT_LT((c.normal - n).norm(), 1e-12);
    const double m_a = world.bodies()[0].state.mass, m_b = world.bodies()[1].state.mass;
    const double m_eff = m_a * m_b / (m_a + m_b);
    const double r_a = equal_volume_radius(a * a * a), r_b = equal_volume_radius(b * b * a);
    const double k = youngs / r_a + youngs / r_b, a_ref = M_PI * r_b * r_b;
    const double g = youngs / (2 * (1 + nu) * r_a) + youngs / (2 * (1 + nu) * r_b);
    const double c_n = std::min(dashpot(eps, k * area * area / a_ref, m_eff), m_eff / dt);
    const double c_t = dashpot(eps, g * area, m_eff);
    const double load = k * volume / a_ref * area;
    EXPECT_NEAR((c.force_on_a - c.tangential_force).norm(), load, 1e-9 * load);
    const Eigen::Vector3d w_rel = w_a - w_b;
    const Eigen::Vector3d w_perp = w_rel - w_rel.dot(n) * n;
    Eigen::Vector3d rocking = -c_n * area / 12 * w_perp;
    const double rocking_cap = load * std::sqrt(area) / 2;
    if (rocking.norm() > rocking_cap) rocking *= rocking_cap / rocking.norm();
    double twisting = -c_t * area / 6 * w_rel.dot(n);
    const double twisting_cap = mu * load * 2 / 3 * std::sqrt(area / M_PI);
    twisting = std::max(-twisting_cap, std::min(twisting, twisting_cap));
    const Eigen::Vector3d couple = rocking + twisting * n;
    EXPECT_LT((c.couple - couple).norm(), 1e-9 * couple.norm());
    EXPECT_LT((torque_a - (c.point - x_a).cross(c.force_on_a) - c.couple).norm(), 1e-14 * scale);
    EXPECT_LT((torque_b - (c.point - x_b).cross(-c.force_on_a) + c.couple).norm(), 1e-14 * scale);
    std::printf(
        "boxes face on face: |F_n| %.4g N, rocking %.4g N m (cap %.4g), twisting %.4g N m "
        "(cap %.4g)\n",
        load, rocking.norm(), rocking_cap, twisting, twisting_cap);
  }
}

// The rocking spring between particles: the boxes of PairOfBoxesFaceOnFace without friction,
// each turning, the state held (evaluate_forces alone, twice by dt after the first evaluation).
// The pair's history holds M_e = -2 k_r w_perp dt, k_r = k_n A_n / 12, w_perp the in-plane part
// of w_lower - w_upper, as seen from the lower id as A: with the ids swapped (the upper box the
// lower id), A (body 0) gets the same couple and the history holds the opposite moment. The
// contact's tangential energy is the spring's |M_e|^2 / (2 k_r) (no tangential spring here).
TEST(ReferencePatchCouple, PairRockingSpringHistory) {
  const double a = 0.01, b = 0.006, d = 1e-5, youngs = 1e7, nu = 0.3, eps = 0.5, dt = 1e-5;
  const Eigen::Vector3d w_low(0.5, 0.1, -0.3), w_up(-0.2, 0.4, 0.9);
  const Eigen::Vector3d x_low = Eigen::Vector3d::Zero(), x_up(0, 0, a - d);
  Eigen::Vector3d stored[2], couples[2];
  for (const bool swapped : {false, true}) {
    RefWorldSetup s;
    s.templates = {box(a, a, a), box(b, b, a)};
    s.materials = {material(youngs, eps, 0, 2500, nu)};
    s.time_step = dt;
    s.effects.rotation = true;
    RefBodySpec low = polyhedron(0, 0, swapped ? 2 : 1, x_low);
    RefBodySpec up = polyhedron(1, 0, swapped ? 1 : 2, x_up);
    low.angular_velocity = w_low;
    up.angular_velocity = w_up;
    s.bodies = {low, up};
    RefWorld world(s);
    world.evaluate_forces(0);
    world.evaluate_forces(dt);
    world.evaluate_forces(dt);
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& c = world.contacts()[0];
    ASSERT_EQ(c.body_a, 0);
    const double area = b * b, volume = area * d;
    const double m_low = world.bodies()[0].state.mass, m_up = world.bodies()[1].state.mass;
    const double m_eff = m_low * m_up / (m_low + m_up);
    const double r_low = equal_volume_radius(a * a * a), r_up = equal_volume_radius(b * b * a);
    const double k = youngs / r_low + youngs / r_up, a_ref = M_PI * r_up * r_up;
    const double k_n = k * area * area / a_ref, k_r = k_n * area / 12;
    const double c_r = std::min(dashpot(eps, k_n, m_eff), m_eff / dt) * area / 12;
    const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d w_rel = w_low - w_up, w_perp = w_rel - w_rel.dot(n) * n;
    const Eigen::Vector3d spring = -2 * k_r * dt * w_perp;  // on the lower box
    const Eigen::Vector3d rocking = spring - c_r * w_perp;
    ASSERT_LT(rocking.norm(), k * volume / a_ref * area * std::sqrt(area) / 2);  // under the cap
    EXPECT_LT((c.couple - c.couple.dot(n) * n - rocking).norm(), 1e-12 * rocking.norm());
    EXPECT_NEAR(c.tangential_energy, spring.squaredNorm() / (2 * k_r),
                1e-12 * spring.squaredNorm() / (2 * k_r));
    const ContactHistory* h = world.pair_history(1, 2);
    ASSERT_NE(h, nullptr);
    EXPECT_NEAR(h->rocking_stiffness, k_r, 1e-12 * k_r);
    stored[swapped] = h->rocking_moment;
    couples[swapped] = c.couple;
    // The lower id's view: the lower box's spring, or the upper box's (its opposite).
    EXPECT_LT((h->rocking_moment - (swapped ? -spring : spring)).norm(), 1e-12 * spring.norm());
  }
  EXPECT_LT((couples[0] - couples[1]).norm(), 1e-14 * couples[0].norm());
  EXPECT_LT((stored[0] + stored[1]).norm(), 1e-14 * stored[0].norm());
  std::printf("pair rocking spring after 2 dt: %.4g N m (stored %.4g, %.4g along x)\n",
              stored[0].norm(), stored[0].x(), stored[1].x());
}

// The default law's torques between particles are exactly -dU/dtheta: two built-ins at random
// overlapping poses, at rest (no dashpot, spring or patch couple acts at the first evaluation),
// the torque on each body about its centroid along an axis e against a central difference of the
// contact's U(V) with that body turned by +-h about e through its centroid. Without the couple
// -p M (the overlap's surface moment) the torque would be (c - x) x F alone. Error budget,
// relative to p A_P R (p = |F^e| / A_n, A_P the overlap's boundary area, R the larger bounding
// radius; |dV/dtheta| <= A_P R): U's round-off is p times V's (~1e-15 A_P R), ~5e-10 over 2h
// (h = 1e-6); truncation ~h^2 (test_exact_overlap.cpp, SurfaceMomentIsTheVolumeRateUnderATurn);
// U'' dV^2 terms enter the central difference at h^2 only. 1e-7 leaves margin.
TEST(ReferencePatchCouple, PairTorquesAreMinusTheEnergyRate) {
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"cube:0.01", "tetrahedron:0.012"},
      {"dodecahedron:0.01", "mineral:0.01"},
      {"cube:0.01", "cube:0.01"}};
  std::mt19937_64 rng(99120);
  double worst = 0;
  int checked = 0;
  for (const auto& [spec_a, spec_b] : pairs) {
    const ShapeTemplate a = make_builtin(spec_a), b = make_builtin(spec_b);
    RefWorldSetup s;
    s.templates = {a, b};
    s.materials = {material(1e7, 0.5, 0.5)};
    s.time_step = 1e-6;
    s.effects.friction = true;
    s.effects.rotation = true;
    PosePair poses;
    RefOverlap overlap;
    for (int draw = 0; draw < 100; ++draw) {
      poses = random_overlapping_pair(rng, a.bounding_radius, b.bounding_radius, 0.15, 0.3);
      overlap = exact_overlap(a, to_ref_pose(poses.a), b, to_ref_pose(poses.b));
      if (overlap.overlapping &&
          overlap.volume > 1e-3 * overlap.boundary_area * a.bounding_radius) {
        break;
      }
    }
    ASSERT_TRUE(overlap.overlapping) << spec_a << " vs " << spec_b;
    const RefPose pose_a = to_ref_pose(poses.a), pose_b = to_ref_pose(poses.b);
    const auto world_at = [&](const RefPose& pa, const RefPose& pb) {
      RefWorldSetup t = s;
      t.bodies = {polyhedron(0, 0, 1, pa.position, pa.orientation),
                  polyhedron(1, 0, 2, pb.position, pb.orientation)};
      RefWorld world(t);
      world.evaluate_forces(0);
      return world;
    };
    const RefWorld world = world_at(pose_a, pose_b);
    ASSERT_EQ(world.contacts().size(), 1u);
    const RefContact& c = world.contacts()[0];
    ASSERT_EQ(c.body_a, 0);
    const double pressure = c.force_on_a.norm() / c.area;  // at rest, F = F^e = -p S
    // The couple is U(V)'s alone here: -p M.
    EXPECT_LT((c.couple + pressure * overlap.surface_moment_a).norm(),
              1e-12 * pressure * overlap.surface_moment_a.norm());
    const double radius = std::max(a.bounding_radius, b.bounding_radius);
    const double scale = pressure * overlap.boundary_area * radius;
    EXPECT_GT(c.couple.norm(), 1e-3 * scale) << "the surface moment matters here";
    const double h = 1e-6;
    const Eigen::Vector3d tilted = to_eigen(random_direction(rng));
    for (const Eigen::Vector3d& e : turn_axes(tilted)) {
      const auto energy = [](const RefWorld& w) { return w.contacts().at(0).elastic_energy; };
      const double rate_a = (energy(world_at(turned(pose_a, e, h), pose_b)) -
                             energy(world_at(turned(pose_a, e, -h), pose_b))) /
                            (2 * h);
      const double rate_b = (energy(world_at(pose_a, turned(pose_b, e, h))) -
                             energy(world_at(pose_a, turned(pose_b, e, -h)))) /
                            (2 * h);
      const double torque_a = e.dot(world.bodies()[0].state.torque);
      const double torque_b = e.dot(world.bodies()[1].state.torque);
      const double error = std::max(std::abs(torque_a + rate_a), std::abs(torque_b + rate_b));
      worst = std::max(worst, error / scale);
      EXPECT_LT(error, 1e-7 * scale)
          << spec_a << " vs " << spec_b << ": torque on A " << torque_a << " vs " << -rate_a
          << ", on B " << torque_b << " vs " << -rate_b;
      ++checked;
    }
  }
  std::printf("pair torques vs -dU/dtheta: %d axes, worst error %.2e of p A_P R\n", checked, worst);
}

}  // namespace
}  // namespace talus::reference
