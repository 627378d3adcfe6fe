// Contact force laws of the production solver, as stateless TALUS_HD functions on one contact:
// the volume laws of the method paper (§2.5, Eqs. 12-20: `volume`, the default, made linear in
// the overlap volume where that is softer, and `volume_paper`, Eqs. 12-13 as printed;
// docs/contact.md derives both) and the linear model of BLAZE-DEM (§3.1, Eqs. 2-3). The laws
// themselves are types (contact/laws/: each one's pressure, parameters and choice of these
// functions; contact/contact_laws.hpp maps the scene's model to one).
// Conventions, for a contact between A and B (B may be a wall):
//   n    unit normal from A into B (volume model: n = S / |S|, S the overlap's vector area on A);
//   v_r  v_A(c) - v_B(c) at the contact point c; v_r . n > 0 while the bodies approach;
//   the force returned acts on A; B gets its opposite; torques (c - x) x F (Eqs. 21-22).
#pragma once

#include <cmath>

#include "solver/core/math.hpp"
#include "solver/core/vec3.hpp"

namespace talus {

// A volume law's pressure p(V) = dU/dV, its slope p'(V) and its potential U(V): Feng's
// construction (the paper's Eqs. 12-13 are of this form) makes the elastic force on A -p(V) S, the
// gradient of U, whatever the shapes, so an elastic collision conserves energy.
template <class Real>
struct VolumePressure {
  Real pressure = 0;  // p, Pa
  Real slope = 0;     // p', Pa/m^3: the face-on-face stiffness is p' A_n^2
  Real energy = 0;    // U, J
};

// A_ref of the default volume law: the cross-section of the smaller body's equivalent sphere.
template <class Real>
TALUS_HD inline Real volume_reference_area(Real radius_a, Real radius_b) {
  const Real r = min_of(radius_a, radius_b);
  return Real(3.14159265358979323846) * r * r;
}

template <class Real>
struct NormalContactData {
  Vec3<Real> normal;              // n, unit, from A into B
  Vec3<Real> point;               // c, m (world)
  Real elastic = 0;               // |F_n^e|: k_n dV^(1/3) (volume) or K_N delta (linear), N
  Real normal_stiffness = 0;      // k_n = K A_n (Eq. 13), N/m
  Real tangential_stiffness = 0;  // k_t (Eq. 19), N/m
  Real area = 0;                  // A_n, m^2
  Real potential = 0;             // the normal elastic energy U, J
};

// What a contact carries across steps (keyed by the global ids, tangential_history.hpp): the
// elastic part of the Cundall-Strack force, F_t^e = -k_t Delta-s (Eq. 18), N, kept in its
// incremental form (see volume_contact_force), the largest normal approach speed since the
// contact began, m/s (< 0 before the first evaluation), which fixes the calibrated damping, and
// the tangential stiffness it was last evaluated with.
template <class Real>
struct ContactHistoryData {
  Vec3<Real> elastic_force;
  Real approach_speed = -1;
  // k_t at the last evaluation, N/m (0 before the first): the default law keeps the spring's
  // energy from growing when k_t falls (volume_contact_force).
  Real spring_stiffness = 0;
  // The default law's rocking spring (patch_couple): its couple on A, N m, in the contact plane,
  // and its stiffness k_r at the last evaluation, N m/rad (0 before the first).
  Vec3<Real> rocking_moment;
  Real rocking_stiffness = 0;
};

template <class Real>
struct ContactForceData {
  Vec3<Real> normal_force;      // on A, N
  Vec3<Real> tangential_force;  // on A, N
  bool sliding = false;         // the Coulomb cap bound
  // Power the non-conservative forces take from the bodies' relative motion now (damping,
  // friction and the springs: negative while a spring gives energy back), W, and the springs'
  // energy after the step, J: the tangential |F_t^e|^2 / (2 k_t) and, with the patch couple,
  // the rocking |M_e|^2 / (2 k_r). The energy ledger counts as dissipated the power's integral
  // less the springs' gain (energy.hpp).
  Real dissipation = 0;
  Real spring_energy = 0;
  Real normal_damping = 0;      // c_n of this evaluation, N s/m
  Real tangential_damping = 0;  // c_t of this evaluation (0 without friction), N s/m
  TALUS_HD Vec3<Real> total() const { return normal_force + tangential_force; }
};

// Normal damping of the volume model. paper: Eq. 15 (with the dissipating sign) on the current
// k_n (the default volume law's damping, on its bounded p' A_n^2). calibrated: c_n = eta A_n, eta =
// beta(eps) m^(1/4) K^(3/4) / sqrt(v0), K = E1/R1 + E2/R2, v0 the contact's largest approach speed,
// beta(eps) from damping_calibration.hpp; A_n cancels in the impact's equation in dV, so one eta
// gives restitution eps for every shape. v0 is at least the speed that would have made the current
// overlap (finite for a contact formed at rest).
enum class NormalDampingModel : int { paper = 0, calibrated = 1 };

template <class Real>
struct VolumeLawData {
  Real effective_mass = 0;  // (1/m_A + 1/m_B)^-1; the particle's mass at a wall, kg
  Real restitution = 1;     // eps in (0, 1], Eqs. 15 and 20
  Real friction = 0;        // mu, Eq. 17
  Real damping_ratio = 0;   // beta(eps) of the calibrated damping
  Real time_step = 0;       // s; c_n <= m_eff / dt (0: no limit)
  bool with_friction = false;
  NormalDampingModel damping = NormalDampingModel::calibrated;
  bool bounded_spring_energy = false;  // the default law: see volume_contact_force
};

// Eqs. 15 and 20 with the sign that dissipates: c = -2 ln(eps) sqrt(k m) / sqrt(ln^2 eps + pi^2).
template <class Real>
TALUS_HD inline Real dissipative_damping(Real restitution, Real stiffness, Real mass) {
  const Real log_e = std::log(restitution);
  const Real pi = Real(3.14159265358979323846);
  return Real(-2) * log_e * std::sqrt(stiffness * mass) / std::sqrt(log_e * log_e + pi * pi);
}

// Eqs. 14, 16 with the no-tension rule: the push along -n is at least zero.
template <class Real>
TALUS_HD inline Vec3<Real> no_tension_normal_force(const Vec3<Real>& n, Real elastic, Real damping,
                                                   Real normal_speed) {
  const Real push = elastic + damping * normal_speed;
  return push > Real(0) ? n * (-push) : Vec3<Real>();
}

// The power the normal force's non-elastic part takes from the approach, W (>= 0): the dashpot's
// c_n v_n^2, or, where the no-tension rule dropped the force, the elastic power not returned.
template <class Real>
TALUS_HD inline Real normal_dissipation(const Vec3<Real>& normal_force, const Vec3<Real>& n,
                                        Real elastic, Real normal_speed) {
  return (-dot(normal_force, n) - elastic) * normal_speed;
}

// The volume model for one contact: F_n = -(|F^e| + c_n v_n) n, never pulling; the tangential
// force of Eqs. 17-20, F_t = F_t^e - c_t v_t capped at mu |F_n|, with the elastic part
// F_t^e = -k_t Delta-s (Eq. 18) advanced incrementally: turned onto the current tangent plane
// with its length kept, then dF_t^e = -k_t v_t dt with the current k_t; where the cap binds,
// F_t^e is reset to the capped force plus c_t v_t. The increments are Eq. 18's for a constant
// k_t. Eq. 18 taken literally with the current k_t (Eq. 19: proportional to the overlap's area)
// would change the stored force whenever the area changes at a fixed Delta-s, i.e. make elastic
// energy out of nothing: a polyhedron rocking from an edge onto a face multiplies its area, and
// with rotation that pumped a dodecahedron on a floor from 1.8 mJ to 130 mJ in 0.4 s at any time
// step, and blew a 63-particle pour up to 1 kJ (tests/step/test_friction_energy.cpp).
template <class Real>
TALUS_HD inline ContactForceData<Real> volume_contact_force(const NormalContactData<Real>& c,
                                                            const VolumeLawData<Real>& law,
                                                            const Vec3<Real>& v_r, Real dt,
                                                            ContactHistoryData<Real>& history) {
  const Vec3<Real>& n = c.normal;
  const Real v_n = dot(v_r, n);
  history.approach_speed = max_of(history.approach_speed, max_of(v_n, Real(0)));
  const Real m = law.effective_mass;
  Real c_n = 0;
  bool unlimited = false;  // v0 = 0: the coefficient is infinite, i.e. the step's limit
  if (law.damping == NormalDampingModel::paper) {
    c_n = dissipative_damping(law.restitution, c.normal_stiffness, m);  // Eq. 15
  } else if (law.restitution < Real(1) && c.area > Real(0)) {
    // v0 is at least the speed that would have made the current overlap, m v^2 / 2 = U(dV) =
    // 3/4 K dV^(4/3) (the potential of Eqs. 12-13): never above the approach speed of an impact
    // (damping only removes energy), so impacts keep the calibration, while a contact formed at
    // rest gets the finite eta of its load rather than the step limit m / dt (which chatters).
    if (c.elastic > Real(0)) {
      const Real cube_root = c.elastic / c.normal_stiffness;  // dV^(1/3)
      const Real energy = Real(0.75) * (c.normal_stiffness / c.area) * std::pow(cube_root, Real(4));
      history.approach_speed = max_of(history.approach_speed, std::sqrt(Real(2) * energy / m));
    }
    const Real v0 = history.approach_speed;
    if (v0 > Real(0)) {
      const Real modulus = c.normal_stiffness / c.area;  // K
      c_n = law.damping_ratio * std::pow(m, Real(0.25)) * std::pow(modulus, Real(0.75)) /
            std::sqrt(v0) * c.area;
    } else {
      unlimited = true;
    }
  }
  if (law.time_step > Real(0)) {
    c_n = unlimited ? m / law.time_step : min_of(c_n, m / law.time_step);
  } else if (unlimited) {
    c_n = 0;  // no approach to damp and no step to limit by
  }
  ContactForceData<Real> out;
  out.normal_force = no_tension_normal_force(n, c.elastic, c_n, v_n);
  out.dissipation = normal_dissipation(out.normal_force, n, c.elastic, v_n);
  out.normal_damping = c_n;
  if (!law.with_friction) {
    history.elastic_force = Vec3<Real>();
    return out;
  }
  Vec3<Real>& f_e = history.elastic_force;
  const Real length = norm(f_e);
  f_e -= n * dot(f_e, n);
  const Real projected = norm(f_e);
  if (projected > Real(0)) f_e *= length / projected;
  const Vec3<Real> v_t = v_r - n * v_n;
  const Real k_t = c.tangential_stiffness;
  const Real k_before = history.spring_stiffness;  // k_t at the last evaluation
  // k_t = G A_n follows the contact's area. At a fixed force a falling k_t would raise the
  // stored |F|^2 / (2 k_t), energy from nothing that the spring then gives back as motion (an
  // ending contact's k_t -> 0). The default law scales the force by sqrt(k_t / k_before) when k_t
  // falls (the energy kept); a rising k_t keeps the force (the energy falls, dissipated).
  if (law.bounded_spring_energy && k_before > k_t && k_before > Real(0))
    f_e *= std::sqrt(k_t / k_before);
  history.spring_stiffness = k_t;
  f_e -= v_t * (k_t * dt);                                        // Eq. 18, incremental
  const Real c_t = dissipative_damping(law.restitution, k_t, m);  // Eq. 20
  out.tangential_damping = c_t;
  Vec3<Real> f_t = f_e - v_t * c_t;  // Eqs. 17, 20
  const Real cap = law.friction * norm(out.normal_force);
  const Real f_t_norm = norm(f_t);
  if (f_t_norm > cap) {
    out.sliding = true;
    f_t *= f_t_norm > Real(0) ? cap / f_t_norm : Real(0);
    f_e = f_t + v_t * c_t;
  }
  out.tangential_force = f_t;
  // The power the tangential force takes from the relative motion now. What of it the spring
  // keeps is the change of the springs' energy, which the energy ledger takes off (energy.hpp):
  // a per-step difference here, added as a rate, would lag the trapezoid by half a step.
  out.spring_energy = k_t > Real(0) ? norm2(f_e) / (Real(2) * k_t) : Real(0);
  out.dissipation -= dot(f_t, v_t);
  return out;
}

// The default volume law's couples on rotating bodies, besides its force at the point c.
// The exact couple of the potential U(V) (the overlap's surface moment, applied by the caller)
// leaves a face resting on a face without tilt stiffness: V does not change when the face tilts
// at a fixed volume, so a cube on a cube is an inverted pendulum on its contact. A real patch's
// pressure is not uniform: as a Winkler foundation of the contact's stiffness k_n spread over A_n
// it resists a tilt theta with the moment k_n (I / A_n) theta, I the patch's second moment about
// the tilt's axis (A_n^2 / 12 for a square). That is the rocking spring, k_r = k_n A_n / 12, kept
// in the history as the tangential spring is (Eq. 18's incremental form, turned with the normal
// and scaled by sqrt(k_r / k_before) when k_r falls, so that its energy |M_e|^2 / (2 k_r) never
// grows from nothing), in parallel with the rocking dashpot, the normal dashpot c_n spread alike:
// -c_n (A_n / 12) w_perp, w_perp the relative rotation about axes in the contact plane. Their sum
// is capped by what a pressure that cannot pull gives, |F_n| sqrt(A_n) / 2 (the whole force at
// the patch's edge); the spring slips there, as the tangential one at Coulomb's cap. The
// tangential dashpot c_t (Eq. 20) spread over the patch resists twisting, w_n about the normal,
// with -c_t (J / A_n) w_n, J = A_n^2 / 6 the polar moment, capped by mu |F_n| times the mean
// radius 2/3 sqrt(A_n / pi) of a disc (Coulomb). Without the dashpots a face resting on a face
// rocks and spins undamped (tests/step/test_hard_cases.cpp). Returns the couple on A (B gets its
// opposite); adds the power it takes from the relative rotation, -couple . w_rel, to
// f.dissipation and the rocking spring's energy to f.spring_energy (the energy ledger takes the
// springs' change off the power, step/energy.hpp). w_rel: w_A - w_B, world frame; dt: the time the
// spring advances by; normal_stiffness: k_n.
template <class Real>
TALUS_HD inline Vec3<Real> patch_couple(ContactForceData<Real>& f, const Vec3<Real>& n, Real area,
                                        Real normal_stiffness, Real friction,
                                        const Vec3<Real>& w_rel, Real dt,
                                        ContactHistoryData<Real>& history) {
  if (!(area > Real(0))) {
    history.rocking_moment = Vec3<Real>();
    history.rocking_stiffness = 0;
    return Vec3<Real>();
  }
  const Real pushing = norm(f.normal_force);
  const Real w_n = dot(w_rel, n);
  const Vec3<Real> w_perp = w_rel - n * w_n;
  // The spring turned into the current contact plane, its length kept.
  Vec3<Real>& m_e = history.rocking_moment;
  const Real length = norm(m_e);
  m_e -= n * dot(m_e, n);
  const Real projected = norm(m_e);
  if (projected > Real(0)) m_e *= length / projected;
  const Real k_r = normal_stiffness * area / Real(12);
  const Real k_before = history.rocking_stiffness;
  if (k_before > k_r && k_before > Real(0)) m_e *= std::sqrt(k_r / k_before);
  history.rocking_stiffness = k_r;
  m_e -= w_perp * (k_r * dt);
  const Real c_r = f.normal_damping * area / Real(12);
  Vec3<Real> rocking = m_e - w_perp * c_r;
  const Real rocking_cap = Real(0.5) * pushing * std::sqrt(area), rocking_size = norm(rocking);
  if (rocking_size > rocking_cap) {
    rocking *= rocking_cap / rocking_size;
    m_e = rocking + w_perp * c_r;
  }
  f.spring_energy += k_r > Real(0) ? norm2(m_e) / (Real(2) * k_r) : Real(0);
  Real twisting = -f.tangential_damping * area / Real(6) * w_n;
  const Real twisting_cap =
      friction * pushing * Real(2) / Real(3) * std::sqrt(area / Real(3.14159265358979323846));
  twisting = max_of(-twisting_cap, min_of(twisting, twisting_cap));
  const Vec3<Real> couple = rocking + n * twisting;
  f.dissipation -= dot(couple, w_rel);
  return couple;
}

template <class Real>
struct LinearLawData {
  Real stiffness = 0;           // K_N, N/m
  Real damping = 0;             // eta, N s/m (on the normal relative velocity)
  Real tangential_damping = 0;  // gamma, N s/m
  Real friction = 0;            // mu
  bool with_friction = false;
};

// BLAZE-DEM Eqs. 2-3, history-free: F_N = -(K_N delta + eta v_n) n with no tension;
// F_T = -min(mu K_N delta, gamma |v_T|) v_T / |v_T| (the cap is the elastic normal force).
template <class Real>
TALUS_HD inline ContactForceData<Real> linear_contact_force(const NormalContactData<Real>& c,
                                                            const LinearLawData<Real>& law,
                                                            const Vec3<Real>& v_r) {
  const Vec3<Real>& n = c.normal;
  const Real v_n = dot(v_r, n);
  ContactForceData<Real> out;
  out.normal_force = no_tension_normal_force(n, c.elastic, law.damping, v_n);  // Eq. 2
  out.dissipation = normal_dissipation(out.normal_force, n, c.elastic, v_n);
  if (!law.with_friction) return out;
  const Vec3<Real> v_t = v_r - n * v_n;
  const Real speed = norm(v_t);
  if (speed == Real(0)) return out;
  const Real cap = law.friction * c.elastic, viscous = law.tangential_damping * speed;
  out.sliding = cap < viscous;
  out.tangential_force = v_t * (-min_of(cap, viscous) / speed);  // Eq. 3
  out.dissipation += min_of(cap, viscous) * speed;               // history-free: all of it
  return out;
}

}  // namespace talus
