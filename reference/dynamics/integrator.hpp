// Time integration of the reference solver's rigid bodies.
//
// Translation: velocity Verlet (BLAZE-DEM Eqs. 5-6), which the method paper does not restate:
//   x_{k+1} = x_k + v_k dt + a_k dt^2 / 2,   v_{k+1} = v_k + (a_k + a_{k+1}) dt / 2,
// split around the force evaluation. Between the halves the body carries the predicted velocity
// v_k + a_k dt, so a velocity-dependent force (drag, damping) is evaluated O(dt^2) from v_{k+1}
// and the scheme stays second order for it (with the half-step velocity it would be first order).
//
// Rotation: Euler's equations in the body frame, I^ w' + w x (I^ w) = T^ with T^ = H^T T
// (paper §2.5 after Eq. 24), and the quaternion rate of Eq. 26, q' = q (0, w) / 2, renormalised.
// The paper gives the rates but not their discretisation; two are offered:
//   kExplicitEuler    the paper's equations stepped as BLAZE-DEM does (Eq. 7 forward Euler for w,
//                     then the orientation with the new w): first order, and the free-body
//                     energy grows by dt^2/2 |w'|^2_I each step.
//   kImplicitMidpoint half-kicks of L by the torque around a torque-free rotation solved by the
//                     implicit midpoint rule; the orientation turns by 2 atan(|w_m| dt / 2) about
//                     w_m, the rotation that carries the body-frame L. Second order; for a free
//                     body energy, |L| and world-frame L are conserved to round-off.
#pragma once

#include "reference/dynamics/rigid_body.hpp"

namespace talus::reference {

enum class RotationScheme { kExplicitEuler, kImplicitMidpoint };

// One step is begin_step, then the forces and torques at the new state, then end_step:
//
//   body.clear_accumulators(); apply_effects(body);      // once, before the first step
//   for each step:
//     begin_step(body, dt, scheme);                       // x, q at k+1; v, w predicted
//     body.clear_accumulators(); apply_effects(body);     // F, T at k+1
//     end_step(body, dt, scheme);                         // v, w at k+1
//
// so that on entry to begin_step body.force and body.torque hold F_k and T_k.
void begin_step(RigidBody& body, double dt, RotationScheme scheme);
void end_step(RigidBody& body, double dt, RotationScheme scheme);

// The step above with the effects as a callable `void(RigidBody&)`.
template <class ApplyEffects>
void step(RigidBody& body, double dt, RotationScheme scheme, ApplyEffects&& apply_effects) {
  begin_step(body, dt, scheme);
  body.clear_accumulators();
  apply_effects(body);
  end_step(body, dt, scheme);
}

// The torque-free rotation over dt by the implicit midpoint rule (the drift of kImplicitMidpoint):
// updates angular_velocity_body and orientation. Throws std::runtime_error when the fixed-point
// iteration does not converge (|w| dt far above 1).
void rotate_torque_free_midpoint(RigidBody& body, double dt);

}  // namespace talus::reference
