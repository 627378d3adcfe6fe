#include "reference/dynamics/rigid_body.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace talus::reference {

RigidBody RigidBody::with_mass_properties(double mass, const Eigen::Vector3d& principal_inertia) {
  const bool finite = std::isfinite(mass) && principal_inertia.allFinite();
  if (!finite || mass <= 0 || (principal_inertia.array() <= 0).any()) {
    throw std::invalid_argument("rigid body: mass and principal moments must be positive, got m=" +
                                std::to_string(mass));
  }
  RigidBody body;
  body.mass = mass;
  body.principal_inertia = principal_inertia;
  return body;
}

RigidBody RigidBody::from_template(const ShapeTemplate& shape, double density) {
  if (!(density > 0)) {
    throw std::invalid_argument("rigid body from template '" + shape.name +
                                "': density must be positive, got " + std::to_string(density));
  }
  const Vec3d& moments = shape.principal_moments;  // per unit density, m^5
  return with_mass_properties(density * shape.volume,
                              density * Eigen::Vector3d(moments.x, moments.y, moments.z));
}

void RigidBody::clear_accumulators() {
  force.setZero();
  torque.setZero();
}

// Eigen's matrix of a unit quaternion is the H of Eq. 25 (checked in the tests).
Eigen::Matrix3d RigidBody::rotation() const {
  return orientation.toRotationMatrix();
}

Eigen::Matrix3d RigidBody::inertia_world() const {
  const Eigen::Matrix3d h = rotation();
  return h * principal_inertia.asDiagonal() * h.transpose();
}

Eigen::Vector3d RigidBody::angular_velocity_world() const {
  return orientation * angular_velocity_body;
}

Eigen::Vector3d RigidBody::angular_momentum_body() const {
  return principal_inertia.cwiseProduct(angular_velocity_body);
}

Eigen::Vector3d RigidBody::angular_momentum_world() const {
  return orientation * angular_momentum_body();
}

Eigen::Vector3d RigidBody::momentum() const {
  return mass * velocity;
}

double RigidBody::translational_kinetic_energy() const {
  return 0.5 * mass * velocity.squaredNorm();
}

double RigidBody::rotational_kinetic_energy() const {
  return 0.5 * angular_velocity_body.dot(angular_momentum_body());
}

double RigidBody::kinetic_energy() const {
  return translational_kinetic_energy() + rotational_kinetic_energy();
}

}  // namespace talus::reference
