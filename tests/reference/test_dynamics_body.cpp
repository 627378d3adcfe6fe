// Reference rigid body: mass properties, frames (paper Eqs. 23-25) and the body forces.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "reference/dynamics/effects.hpp"
#include "reference/dynamics/rigid_body.hpp"
#include "solver/shape/builtins.hpp"

namespace talus::reference {
namespace {

TEST(ReferenceRigidBody, MassAndInertiaOfACuboidTemplate) {
  // A box a x b x c has m = rho a b c and principal moments m (b^2 + c^2) / 12 etc.; the
  // template's are exact up to round-off of the tetrahedron sums, hence 1e-12 relative.
  const double a = 0.01, b = 0.02, c = 0.03, density = 2500;
  const RigidBody body = RigidBody::from_template(make_builtin("cuboid:0.01,0.02,0.03"), density);
  const double mass = density * a * b * c;
  EXPECT_NEAR(body.mass, mass, 1e-12 * mass);
  // Ascending: the smallest moment is about the longest side.
  const Eigen::Vector3d expected(mass * (a * a + b * b) / 12, mass * (a * a + c * c) / 12,
                                 mass * (b * b + c * c) / 12);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(body.principal_inertia[i], expected[i], 1e-12 * expected[i]);
}

TEST(ReferenceRigidBody, RejectsNonPositiveMassProperties) {
  EXPECT_THROW(RigidBody::with_mass_properties(0, Eigen::Vector3d::Ones()), std::invalid_argument);
  EXPECT_THROW(RigidBody::with_mass_properties(1, Eigen::Vector3d(1, -1, 1)),
               std::invalid_argument);
  EXPECT_THROW(RigidBody::from_template(make_builtin("cube:0.01"), -1), std::invalid_argument);
}

TEST(ReferenceRigidBody, RotationIsTheMatrixOfEq25) {
  RigidBody body;
  body.orientation = Eigen::Quaterniond(0.3, -0.5, 0.7, 0.2).normalized();
  const double q0 = body.orientation.w(), q1 = body.orientation.x(), q2 = body.orientation.y(),
               q3 = body.orientation.z();
  Eigen::Matrix3d h;  // Eq. 25 as printed
  h << 1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2),
      2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1),
      2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2);
  // Entries of order 1 from a few products: 1e-15 is a few ulps.
  EXPECT_LT((body.rotation() - h).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ReferenceRigidBody, WorldInertiaAndMomentumAgree) {
  // L = I Omega (Eq. 23) with I = H I^ H^T (Eq. 24) must equal H (I^ omega); both are a few
  // products of order-1 numbers, so 1e-14 absolute.
  RigidBody body = RigidBody::with_mass_properties(2, Eigen::Vector3d(1, 2, 3));
  body.orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 2, -1).normalized()));
  body.angular_velocity_body = Eigen::Vector3d(0.4, -1.1, 0.6);
  const Eigen::Vector3d from_tensor = body.inertia_world() * body.angular_velocity_world();
  EXPECT_LT((from_tensor - body.angular_momentum_world()).cwiseAbs().maxCoeff(), 1e-14);
  // omega . I^ omega / 2 = (0.16 * 1 + 1.21 * 2 + 0.36 * 3) / 2 = 1.83.
  EXPECT_NEAR(body.rotational_kinetic_energy(), 1.83, 1e-14);
}

TEST(ReferenceEffects, GravityAndQuadraticDrag) {
  RigidBody body = RigidBody::with_mass_properties(0.2, Eigen::Vector3d::Ones());
  body.velocity = Eigen::Vector3d(3, 0, -4);  // |v| = 5
  add_gravity(body, Eigen::Vector3d(0, 0, -9.81));
  add_quadratic_drag(body, 0.5);
  // m g = (0, 0, -1.962); -alpha |v| v = -2.5 (3, 0, -4) = (-7.5, 0, 10). Exact to round-off.
  EXPECT_NEAR(body.force.x(), -7.5, 1e-14);
  EXPECT_EQ(body.force.y(), 0);
  EXPECT_NEAR(body.force.z(), 10 - 1.962, 1e-14);
  EXPECT_EQ(body.torque, Eigen::Vector3d::Zero());
  body.clear_accumulators();
  EXPECT_EQ(body.force, Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace talus::reference
