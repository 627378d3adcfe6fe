// The paper's volume law as printed (method paper §2.5, Eqs. 12-13: `volume_paper`):
// p = K V^(1/3), k_n = K A_n (Eq. 13), F^e = k_n V^(1/3) (Eq. 12), K = E_A/R_A + E_B/R_B; the
// calibrated normal damping c_n = eta A_n (force_law.hpp's volume_contact_force) and the
// Cundall-Strack tangential spring of Eqs. 17-20. Its stiffness p' A_n^2 is unbounded as V -> 0
// (docs/contact.md).
#pragma once

#include <cmath>

#include "solver/contact/laws/law_common.hpp"

namespace talus {

struct VolumePaperLaw : VolumeLawBase<VolumePaperLaw> {
  static constexpr const char* kName = "volume_paper";
  static constexpr bool kPatchCouple = false;
  static constexpr bool kCalibratedDamping = true;
  static constexpr bool kStiffnessAtLoad = true;

  // p = K V^(1/3) (Eq. 12 with k_n = K A_n, Eq. 13), p' = K / (3 V^(2/3)), U = 3/4 K V^(4/3), from
  // the cube root c = V^(1/3) (the default law's pressure above its switch volume takes these).
  template <class Real>
  TALUS_HD static VolumePressure<Real> pressure_of_root(Real modulus, Real volume, Real cube_root) {
    VolumePressure<Real> out;
    out.pressure = modulus * cube_root;
    out.slope = cube_root > Real(0) ? modulus / (Real(3) * cube_root * cube_root) : Real(0);
    out.energy = Real(0.75) * modulus * volume * cube_root;
    return out;
  }

  // The pressure of overlap volume V (the reference area is the default law's, unused here).
  template <class Real>
  TALUS_HD static VolumePressure<Real> pressure(Real modulus, Real /*reference_area*/,
                                                Real volume) {
    return pressure_of_root(modulus, volume, std::cbrt(volume));
  }

  // One wall facet of area weight w, section area A and volume V below its plane:
  // k_n = w K A (Eq. 13), |F^e| = k_n V^(1/3) (Eq. 12), U = w U(V).
  template <class Real>
  TALUS_HD static NormalElastic<Real> facet_elastic(Real weight, Real modulus, Real reference_area,
                                                    Real volume, Real area) {
    const VolumePressure<Real> pv = pressure(modulus, reference_area, volume);
    NormalElastic<Real> e;
    e.stiffness = weight * modulus * area;      // Eq. 13
    e.force = e.stiffness * std::cbrt(volume);  // Eq. 12
    e.energy = weight * pv.energy;
    return e;
  }

  // The calibrated damping (or the tables' model) and no bound on the tangential spring's energy.
  template <class Tables, class Real>
  TALUS_HD static VolumeLawData<Real> parameters(const Tables& t, int pair, Real effective_mass) {
    VolumeLawData<Real> law = volume_law_data(t, pair, effective_mass);
    law.damping = t.damping;
    law.bounded_spring_energy = false;
    return law;
  }

  // The advisor's k_n (time_step_advisor.cpp).
  static AdvisedStiffness largest_normal_stiffness(const StiffestContact& c) {
    // F = K A_n V^(1/3) (Eqs. 12-13) has dF/dd = K A^2 / (3 V^(2/3)) face on face (V = A d),
    // unbounded as V -> 0, so the law has no stable step for every state; take the state it
    // rests in. Under gravity: the heavier body's weight W = m_max |g| (a particle deeper in
    // a bed carries more and is softer, since k falls as 1/W^2; a lighter, grazing contact
    // is stiffer still and unbounded). Then V^(1/3) = W/(K A) and k_n = K^3 A^4 / (3 W^2).
    // Without gravity: the peak force of a face-on impact at the scene's largest initial
    // speed v, where the contact is softest: 1/2 m_eff v^2 = U(d) = 3/4 K A^(4/3) d^(4/3),
    // F = K A^(4/3) d^(1/3), i.e. F = K A^(4/3) (2 m_eff v^2 / (3 K A^(4/3)))^(1/4).
    AdvisedStiffness s;
    double load = c.mass_max * c.gravity;
    if (c.gravity == 0) {
      const double a43 = std::pow(c.area, 4.0 / 3.0);
      const double energy = 0.5 * c.speed * c.speed / c.inverse_mass;
      load = c.modulus * a43 * std::pow(4 * energy / (3 * c.modulus * a43), 0.25);
    }
    s.load = load;
    s.normal_stiffness =
        c.modulus * c.modulus * c.modulus * std::pow(c.area, 4) / (3 * load * load);
    return s;
  }
};

}  // namespace talus
