// BLAZE-DEM's linear model (`linear`, §3.1, Eqs. 2-3): F^e = K_N delta on the depth, history-free,
// with the normal dashpot eta and the capped tangential dashpot gamma (force_law.hpp's
// linear_contact_force); K_N, eta and gamma are the scene's (PairLawTables::linear).
#pragma once

#include <cmath>

#include "solver/contact/laws/law_common.hpp"

namespace talus {

struct LinearLaw {
  static constexpr const char* kName = "linear";
  static constexpr bool kVolumeGeometry = false;
  static constexpr bool kTangentialHistory = false;
  static constexpr bool kPatchCouple = false;
  static constexpr bool kCalibratedDamping = false;
  static constexpr bool kStiffnessAtLoad = false;

  // One contact of depth delta: K_N delta (Eq. 2) and its energy K_N delta^2 / 2.
  template <class Real>
  TALUS_HD static NormalElastic<Real> contact_elastic(Real stiffness, Real depth) {
    NormalElastic<Real> e;
    e.force = stiffness * depth;
    e.energy = Real(0.5) * e.force * depth;
    return e;
  }

  // One wall facet of area weight w and depth delta: w K_N delta, energy w K_N delta^2 / 2.
  template <class Real>
  TALUS_HD static NormalElastic<Real> facet_elastic(Real weight, Real stiffness, Real depth) {
    NormalElastic<Real> e;
    e.force = weight * stiffness * depth;
    e.energy = weight * Real(0.5) * stiffness * depth * depth;
    return e;
  }

  // K_N, eta, gamma of the scene with material pair `pair`'s mu (no mass: eta is the scene's).
  template <class Tables, class Real>
  TALUS_HD static LinearLawData<Real> parameters(const Tables& t, int pair,
                                                 Real /*effective_mass*/) {
    LinearLawData<Real> law = t.linear;
    law.friction = t.pair_friction[pair];
    law.with_friction = t.with_friction;
    return law;
  }

  // History-free: dt and the history are not read.
  template <class Real>
  TALUS_HD static ContactForceData<Real> force(const NormalContactData<Real>& c,
                                               const LinearLawData<Real>& law,
                                               const Vec3<Real>& v_r, Real /*dt*/,
                                               ContactHistoryData<Real>& /*history*/) {
    return linear_contact_force(c, law, v_r);
  }

  // The advisor's k_n (time_step_advisor.cpp).
  static AdvisedStiffness largest_normal_stiffness(const StiffestContact& c) {
    AdvisedStiffness s;
    s.normal_stiffness = c.linear_stiffness;  // BLAZE-DEM Eq. 2
    return s;
  }

  // The dashpot's own ratio eta / (2 sqrt(k m_eff)).
  static double normal_damping_ratio(const StiffestContact& c, double normal_stiffness,
                                     double /*restitution_ratio*/) {
    return c.linear_damping / (2 * std::sqrt(normal_stiffness * c.effective_mass));
  }
};

}  // namespace talus
