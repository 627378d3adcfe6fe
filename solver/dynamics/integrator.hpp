// Time integration of one rigid particle, as stateless TALUS_HD functions on values.
//
// Translation: velocity Verlet (BLAZE-DEM Eqs. 5-6), split around the force evaluation:
//   begin:  x_{k+1} = x_k + v_k dt + a_k dt^2 / 2,  v* = v_k + a_k dt   (keeps a_k)
//   forces: F_{k+1} at x_{k+1} and the predicted v*, so that a velocity-dependent force (drag,
//           damping) is taken O(dt^2) from v_{k+1} and the scheme stays second order for it;
//   end:    v_{k+1} = v* + (a_{k+1} - a_k) dt / 2.
//
// Rotation (paper §2.5, Eqs. 21-26): Euler's equations in the body frame, integrated by the
// implicit-midpoint splitting: a half kick of the body-frame angular velocity by T_k, the
// torque-free rotation over dt solved by the implicit midpoint rule (the orientation turns by
// 2 atan(|w_m| dt / 2) about w_m, which carries the body-frame angular momentum exactly), the
// other half kick by T_k at q_{k+1} as a prediction, which end_rotation replaces by T_{k+1}.
// Second order; a free body keeps its energy and angular momentum to round-off. The quaternion
// rate is Eq. 26 read as the Hamilton product q' = q (0, w) / 2 (as printed, Eq. 26 has two sign
// errors); here the rotation is applied as that product with the finite rotation's quaternion.
#pragma once

#include <cmath>

#include "solver/core/math.hpp"
#include "solver/core/quat.hpp"

namespace talus {

// What the translation keeps between the two halves of a step.
template <class Real>
TALUS_HD inline void begin_translation(Vec3<Real>& position, Vec3<Real>& velocity,
                                       const Vec3<Real>& force, Real mass, Real dt,
                                       Vec3<Real>& step_start_acceleration) {
  const Vec3<Real> acceleration = force / mass;
  position += velocity * dt + acceleration * (Real(0.5) * dt * dt);  // Eq. 5
  velocity += acceleration * dt;
  step_start_acceleration = acceleration;
}

template <class Real>
TALUS_HD inline void end_translation(Vec3<Real>& velocity, const Vec3<Real>& force, Real mass,
                                     Real dt, const Vec3<Real>& step_start_acceleration) {
  velocity += (force / mass - step_start_acceleration) * (Real(0.5) * dt);  // Eq. 6
}

// Componentwise division of a body-frame vector by the principal moments.
template <class Real>
TALUS_HD inline Vec3<Real> divide_by_inertia(const Vec3<Real>& v, const Vec3<Real>& inertia) {
  return {v.x / inertia.x, v.y / inertia.y, v.z / inertia.z};
}

// Change of the body-frame angular velocity from a world-frame angular impulse at orientation q:
// I^ dw = H^T impulse (Eqs. 23-25).
template <class Real>
TALUS_HD inline Vec3<Real> body_omega_change(const Quat<Real>& q, const Vec3<Real>& inertia,
                                             const Vec3<Real>& impulse) {
  return divide_by_inertia(rotate_inverse(q, impulse), inertia);
}

// w x (I^ w), the gyroscopic term of Euler's equations (body frame).
template <class Real>
TALUS_HD inline Vec3<Real> gyroscopic_term(const Vec3<Real>& inertia, const Vec3<Real>& w) {
  return cross(w, Vec3<Real>(inertia.x * w.x, inertia.y * w.y, inertia.z * w.z));
}

// The torque-free rotation over dt by the implicit midpoint rule: I^ (w1 - w0) / dt =
// -w_m x I^ w_m, w_m = (w0 + w1) / 2, by fixed-point iteration (it contracts by about |w| dt, so
// a few iterations reach round-off). Returns false, leaving the state unchanged, when it does not
// converge (|w| dt far above 1: the time step is too long for the spin).
template <class Real>
TALUS_HD inline bool rotate_torque_free_midpoint(Quat<Real>& orientation, Vec3<Real>& omega_body,
                                                 const Vec3<Real>& inertia, Real dt) {
  const Vec3<Real> w0 = omega_body;
  const Real tolerance = Real(8) * Eps<Real>::value * norm(w0);
  Vec3<Real> w1 = w0;
  bool converged = false;
  for (int iteration = 0; iteration < 100 && !converged; ++iteration) {
    const Vec3<Real> w_mid = (w0 + w1) * Real(0.5);
    const Vec3<Real> next = w0 - divide_by_inertia(gyroscopic_term(inertia, w_mid), inertia) * dt;
    converged = norm(next - w1) <= tolerance;
    w1 = next;
  }
  if (!converged) return false;
  const Vec3<Real> w_mid = (w0 + w1) * Real(0.5);
  const Real speed = norm(w_mid);
  if (speed > Real(0)) {
    const Real angle = Real(2) * std::atan(Real(0.5) * speed * dt);
    orientation = (orientation * Quat<Real>::from_axis_angle(w_mid / speed, angle)).normalized();
  }
  omega_body = w1;
  return true;
}

// The first half of the rotation step; keeps T_k. Returns false when the free rotation did not
// converge (the particle is then left where it was; the step reports it).
template <class Real>
TALUS_HD inline bool begin_rotation(Quat<Real>& orientation, Vec3<Real>& omega_body,
                                    const Vec3<Real>& torque, const Vec3<Real>& inertia, Real dt,
                                    Vec3<Real>& step_start_torque) {
  const Vec3<Real> half_impulse = torque * (Real(0.5) * dt);
  omega_body += body_omega_change(orientation, inertia, half_impulse);
  const bool ok = rotate_torque_free_midpoint(orientation, omega_body, inertia, dt);
  omega_body += body_omega_change(orientation, inertia, half_impulse);
  step_start_torque = torque;
  return ok;
}

template <class Real>
TALUS_HD inline void end_rotation(const Quat<Real>& orientation, Vec3<Real>& omega_body,
                                  const Vec3<Real>& torque, const Vec3<Real>& inertia, Real dt,
                                  const Vec3<Real>& step_start_torque) {
  omega_body +=
      body_omega_change(orientation, inertia, (torque - step_start_torque) * (Real(0.5) * dt));
}

}  // namespace talus
