// Contact force laws of the reference solver, in Eigen/double: the volume model of the method
// paper (§2.5, Eqs. 12-22; walls §2.4) and the linear model of BLAZE-DEM (§3.1, Eqs. 2-4).
//
// Conventions, for one contact between a body A and a body B (B may be a wall):
//   n        unit normal from A into B (for the volume model n = S / |S|, S the vector area of
//            the overlap on A's surface, dV/dx_A = +S: moving A along n deepens the overlap);
//   v_r      v_A(c) - v_B(c), the velocity of A's material point at the contact point c relative
//            to B's; v_r . n > 0 while the bodies approach;
//   force    the force on A; B gets its opposite, and each body the torque (c - x) x F about its
//            own centroid (Eqs. 21-22).
#pragma once

#include <Eigen/Core>

namespace talus::reference {

// The elastic part of one normal contact, as the geometry gives it (per pair, or a wall's facets
// combined, world.cpp).
struct NormalContact {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // n, unit, from A into B
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // c, m (world)
  double elastic = 0;               // |F_n^e|, N: k_n dV^(1/3) (volume) or K_N delta (linear)
  double normal_stiffness = 0;      // k_n of Eq. 13, N/m (volume model: enters Eq. 15 only)
  double tangential_stiffness = 0;  // k_t of Eq. 19, N/m (volume model)
  double mean_depth = 0;  // dV / A_n, m: the mean penetration (volume model, kLinearised damping)
};

// Which stiffness enters the damping coefficient of Eqs. 15 and 20 (volume model).
//   kPaper       k_n of Eq. 13 (and k_t of Eq. 19), as printed. The elastic force is not linear
//                in the penetration (F ~ d^(1/3) face to face, ~ d^3 corner first), so the
//                restitution that results is not epsilon: face to face it is close to 1.
//   kLinearised  the secant stiffness of the elastic force, k = |F_n^e| / d with d = dV / A_n
//                the mean penetration (and k_t scaled by the same k / k_n). For a power law
//                F ~ d^p this damping ~ d^((p-1)/2) makes the restitution independent of the
//                impact speed (as Tsuji's Hertz damping does for p = 3/2), and for p = 1 it is
//                Eq. 15 exactly. The tests measure the restitution that results (within 3% of
//                epsilon for epsilon >= 0.5, faces and corners; 0.2 for epsilon = 0.1, where the
//                no-tension rule ends the contact early): test_world_collisions.cpp.
enum class DampingStiffness { kPaper, kLinearised };

// Per pair material constants of the volume model.
struct VolumeLawParameters {
  double effective_mass = 0;  // m_eff = (1/m_A + 1/m_B)^-1, kg; the particle's mass at a wall
  double restitution = 1;     // epsilon in (0, 1] of Eqs. 15 and 20
  double friction = 0;        // mu of Eq. 17
  bool with_friction = false;
  DampingStiffness damping = DampingStiffness::kLinearised;
  // The time step, s (0: no limit). The normal damping force is limited to m_eff |v_n| / dt, the
  // force that stops the normal approach within one step: the secant stiffness is unbounded at
  // the first touch of two faces (F ~ d^(1/3)), and an explicit step with c dt / m_eff > 2 would
  // reverse and amplify v_n instead of damping it.
  double time_step = 0;
};

// The tangential spring Delta-s of Eqs. 17-20 (m), kept per contact across steps.
struct TangentialHistory {
  Eigen::Vector3d spring = Eigen::Vector3d::Zero();
};

struct ContactForce {
  Eigen::Vector3d normal_force = Eigen::Vector3d::Zero();      // on A, N
  Eigen::Vector3d tangential_force = Eigen::Vector3d::Zero();  // on A, N
  bool sliding = false;                                        // the Coulomb cap bound this step
  Eigen::Vector3d total() const { return normal_force + tangential_force; }
};

// Damping coefficient of Eqs. 15 and 20 for stiffness k and mass m, with the sign that
// dissipates: c = -2 ln(eps) sqrt(k m) / sqrt(ln(eps)^2 + pi^2) >= 0. As printed, Eq. 15 has
// +2 ln(eps), which is negative for eps < 1; with F^d = -c (v_r . n) n (Eq. 14) a negative c
// would push the bodies together faster and add energy. The magnitude is the printed one.
// Throws std::invalid_argument unless eps is in (0, 1] and k, m >= 0.
double damping_coefficient(double restitution, double stiffness, double mass);

// Volume model (Eqs. 14-20) for one contact, given its elastic part:
//   F_n = -(|F_n^e| + c_n v_n) n, with v_n = v_r . n, and no tension: a contact never pulls,
//         so F_n . n is kept <= 0 (when the damping would exceed the elastic force near the end
//         of an impact, the normal force is zero instead);
//   F_t = -k_t Delta-s - c_t v_t, |F_t| <= mu |F_n| (Eqs. 17-20).
// The spring: its previous value is turned onto the plane normal to n keeping its length (the
// contact frame turned with the bodies), then grows by v_t dt; where the cap binds, it is reset
// to the value that gives the capped force, Delta-s = -(F_t + c_t v_t) / k_t. dt = 0 leaves the
// spring's length unchanged (the force evaluation before the first step).
ContactForce volume_contact_force(const NormalContact& contact, const VolumeLawParameters& law,
                                  const Eigen::Vector3d& relative_velocity, double dt,
                                  TangentialHistory& history);

// Linear model (BLAZE-DEM Eqs. 2-3), history-free:
//   F_N = -(K_N delta + eta v_n) n on A, with the same no-tension rule;
//   F_T = -min(mu K_N delta, gamma |v_T|) v_T / |v_T| (on A), with friction.
// Eq. 2 damps the whole relative velocity v21; here eta acts on its normal part only, so that the
// tangential direction is governed by Eq. 3 alone (as the paper's own Eq. 14 does).
struct LinearLawParameters {
  double stiffness = 0;           // K_N, N/m
  double damping = 0;             // eta, N s/m
  double tangential_damping = 0;  // gamma, N s/m
  double friction = 0;            // mu
  bool with_friction = false;
};
// `contact.elastic` is K_N delta (summed over a wall's facets with their weights).
ContactForce linear_contact_force(const NormalContact& contact, const LinearLawParameters& law,
                                  const Eigen::Vector3d& relative_velocity);

}  // namespace talus::reference
