#include "reference/dynamics/integrator.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace talus::reference {
namespace {

// w x (I^ w), the gyroscopic term of Euler's equations (body frame).
Eigen::Vector3d gyroscopic(const Eigen::Vector3d& inertia, const Eigen::Vector3d& omega) {
  return omega.cross(inertia.cwiseProduct(omega));
}

// Change of the body-frame angular velocity from the world-frame angular impulse `impulse` at
// the current orientation: I^ dw = H^T impulse.
Eigen::Vector3d body_omega_change(const RigidBody& body, const Eigen::Vector3d& impulse) {
  return (body.orientation.conjugate() * impulse).cwiseQuotient(body.principal_inertia);
}

// Eq. 26: q' = q (0, w) / 2 with w in the body frame (Hamilton product). As printed, Eq. 26 has
// -q3 wx in q2' and -q1 wy in q3'; the product gives +q3 wx and +q1 wy, and only that sign keeps
// the world-frame angular momentum of a free body constant (test FreeRotation*WorldMomentum*).
Eigen::Vector4d quaternion_rate(const Eigen::Quaterniond& q, const Eigen::Vector3d& w) {
  const double q0 = q.w(), q1 = q.x(), q2 = q.y(), q3 = q.z();
  return Eigen::Vector4d(-0.5 * (q1 * w.x() + q2 * w.y() + q3 * w.z()),
                         0.5 * (q0 * w.x() + q2 * w.z() - q3 * w.y()),
                         0.5 * (q0 * w.y() + q3 * w.x() - q1 * w.z()),
                         0.5 * (q0 * w.z() + q1 * w.y() - q2 * w.x()));  // (q0, q1, q2, q3)
}

void rotate_explicit_euler(RigidBody& body, double dt) {
  const Eigen::Vector3d& inertia = body.principal_inertia;
  Eigen::Vector3d& w = body.angular_velocity_body;
  const Eigen::Vector3d torque_body = body.orientation.conjugate() * body.torque;
  w += dt * (torque_body - gyroscopic(inertia, w)).cwiseQuotient(inertia);
  const Eigen::Vector4d rate = quaternion_rate(body.orientation, w);
  Eigen::Quaterniond& q = body.orientation;
  q = Eigen::Quaterniond(q.w() + dt * rate[0], q.x() + dt * rate[1], q.y() + dt * rate[2],
                         q.z() + dt * rate[3]);
  q.normalize();
}

}  // namespace

void rotate_torque_free_midpoint(RigidBody& body, double dt) {
  const Eigen::Vector3d& inertia = body.principal_inertia;
  const Eigen::Vector3d w0 = body.angular_velocity_body;
  // I^ (w1 - w0) / dt = -w_m x I^ w_m with w_m = (w0 + w1) / 2, by fixed-point iteration: the map
  // contracts by about |w| dt (times inertia ratios), so a few iterations reach round-off.
  constexpr int kMaxIterations = 100;
  const double tolerance = 8 * std::numeric_limits<double>::epsilon() * w0.norm();
  Eigen::Vector3d w1 = w0;
  bool converged = false;
  for (int iteration = 0; iteration < kMaxIterations && !converged; ++iteration) {
    const Eigen::Vector3d w_mid = 0.5 * (w0 + w1);
    const Eigen::Vector3d next = w0 - dt * gyroscopic(inertia, w_mid).cwiseQuotient(inertia);
    converged = (next - w1).norm() <= tolerance;
    w1 = next;
  }
  if (!converged) {
    throw std::runtime_error("reference rotation: implicit midpoint did not converge, |w| dt = " +
                             std::to_string(w0.norm() * dt));
  }
  // The body-frame L turned by the Cayley map of -dt [w_m x], a rotation by 2 atan(|w_m| dt / 2)
  // about -w_m; turning the body by the opposite keeps world-frame L = H L^ fixed.
  const Eigen::Vector3d w_mid = 0.5 * (w0 + w1);
  const double speed = w_mid.norm();
  if (speed > 0) {
    const double angle = 2 * std::atan(0.5 * speed * dt);
    body.orientation =
        body.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(angle, w_mid / speed));
    body.orientation.normalize();
  }
  body.angular_velocity_body = w1;
}

void begin_step(RigidBody& body, double dt, RotationScheme scheme) {
  // Translation, Eq. 5, and the velocity predicted for the force evaluation.
  const Eigen::Vector3d acceleration = body.force / body.mass;
  body.position += dt * body.velocity + 0.5 * dt * dt * acceleration;
  body.velocity += dt * acceleration;
  body.step_start_acceleration = acceleration;
  body.step_start_torque = body.torque;

  switch (scheme) {
    case RotationScheme::kExplicitEuler:
      rotate_explicit_euler(body, dt);
      break;
    case RotationScheme::kImplicitMidpoint:
      // Half-kick with T_k at q_k, free rotation, then the other half of T_k at q_{k+1} as the
      // prediction that end_step replaces by T_{k+1}.
      body.angular_velocity_body += body_omega_change(body, 0.5 * dt * body.torque);
      rotate_torque_free_midpoint(body, dt);
      body.angular_velocity_body += body_omega_change(body, 0.5 * dt * body.torque);
      break;
  }
}

void end_step(RigidBody& body, double dt, RotationScheme scheme) {
  // Eq. 6: v_{k+1} = v_k + (a_k + a_{k+1}) dt / 2 = predicted + (a_{k+1} - a_k) dt / 2.
  body.velocity += 0.5 * dt * (body.force / body.mass - body.step_start_acceleration);
  if (scheme == RotationScheme::kImplicitMidpoint) {
    body.angular_velocity_body +=
        body_omega_change(body, 0.5 * dt * (body.torque - body.step_start_torque));
  }
}

}  // namespace talus::reference
