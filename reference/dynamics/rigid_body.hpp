// Rigid-body state of the reference solver (Eigen, double): the independent check of the
// production dynamics. Orientation and inertia follow the paper's §2.5 (Eqs. 23-25).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "solver/shape/shape.hpp"

namespace talus::reference {

struct RigidBody {
  // State. The orientation maps body to world; the angular velocity is in the BODY frame (the
  // omega of Euler's equations and of Eq. 26).
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // centroid, m (world)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m/s (world)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity_body = Eigen::Vector3d::Zero();  // rad/s (body)

  double mass = 1;                                              // kg
  Eigen::Vector3d principal_inertia = Eigen::Vector3d::Ones();  // I^ = diag(Ixx, Iyy, Izz), kg m^2

  // Accumulators, world frame, filled by the effects at the current state.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // N m

  // What the integrator keeps between the two halves of a step (integrator.hpp): the
  // acceleration and the torque that started the step.
  Eigen::Vector3d step_start_acceleration = Eigen::Vector3d::Zero();
  Eigen::Vector3d step_start_torque = Eigen::Vector3d::Zero();

  // A body at rest at the origin with mass rho*V and inertia rho*principal_moments, in the
  // template's body frame (centroid at the origin, principal axes). Throws std::invalid_argument
  // for a density or template without positive mass and moments.
  static RigidBody from_template(const ShapeTemplate& shape, double density);
  // Mass and principal moments given directly; throws std::invalid_argument unless positive.
  static RigidBody with_mass_properties(double mass, const Eigen::Vector3d& principal_inertia);

  void clear_accumulators();

  Eigen::Matrix3d rotation() const;                // H of Eq. 25 (body -> world)
  Eigen::Matrix3d inertia_world() const;           // I = H I^ H^T, Eq. 24
  Eigen::Vector3d angular_velocity_world() const;  // Omega = H omega
  Eigen::Vector3d angular_momentum_body() const;   // I^ omega
  Eigen::Vector3d angular_momentum_world() const;  // L = I Omega, Eq. 23
  Eigen::Vector3d momentum() const;                // m v
  double translational_kinetic_energy() const;     // m v^2 / 2
  double rotational_kinetic_energy() const;        // omega . I^ omega / 2
  double kinetic_energy() const;
};

}  // namespace talus::reference
