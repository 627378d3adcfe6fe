// The default volume law (`volume`): p(V) = K min(V / A_ref, V^(1/3)), linear below the switch
// volume V_s = A_ref^(3/2) (the paper's, volume_paper_law.hpp, above it), so p' <= K / A_ref:
// bounded stiffness (docs/contact.md); A_ref = pi min(R_A, R_B)^2 (volume_reference_area). The
// elastic force on A is -p(V) S with k_n = p' A_n^2, Eq. 15's damping on that k_n, the patch
// couple (exact torque, rocking spring, dashpots) on rotating bodies, and a tangential spring
// whose energy does not grow as k_t falls
// (force_law.hpp's volume_contact_force and patch_couple).
#pragma once

#include <cmath>

#include "solver/contact/laws/law_common.hpp"
#include "solver/contact/laws/volume_paper_law.hpp"

namespace talus {

struct VolumeLaw : VolumeLawBase<VolumeLaw> {
  static constexpr const char* kName = "volume";
  static constexpr bool kPatchCouple = true;
  static constexpr bool kCalibratedDamping = false;
  static constexpr bool kStiffnessAtLoad = false;

  // p = K min(V / A_ref, V^(1/3)), its slope and potential (VolumePressure). K = E_A/R_A + E_B/R_B.
  template <class Real>
  TALUS_HD static VolumePressure<Real> pressure(Real modulus, Real reference_area, Real volume) {
    VolumePressure<Real> out;
    const Real cube_root = std::cbrt(volume);
    if (volume < reference_area * cube_root) {
      out.pressure = modulus * volume / reference_area;
      out.slope = modulus / reference_area;
      out.energy = Real(0.5) * modulus * volume * volume / reference_area;
    } else {
      out = VolumePaperLaw::pressure_of_root(modulus, volume, cube_root);
      // U continuous at V_s: 1/2 K A_ref^2 below, 3/4 K A_ref^2 from the paper's expression.
      out.energy -= Real(0.25) * modulus * reference_area * reference_area;
    }
    return out;
  }

  // One wall facet of area weight w, section area A and volume V below its plane:
  // |F^e| = w p(V) A, k_n = w p'(V) A^2 (bounded), U = w U(V).
  template <class Real>
  TALUS_HD static NormalElastic<Real> facet_elastic(Real weight, Real modulus, Real reference_area,
                                                    Real volume, Real area) {
    const VolumePressure<Real> pv = pressure(modulus, reference_area, volume);
    NormalElastic<Real> e;
    e.force = weight * pv.pressure * area;
    e.stiffness = weight * pv.slope * area * area;  // p' A_n^2, bounded
    e.energy = weight * pv.energy;
    return e;
  }

  // The default law's damping is Eq. 15's on its bounded stiffness (docs/contact.md), and its
  // tangential spring keeps its energy as k_t falls.
  template <class Tables, class Real>
  TALUS_HD static VolumeLawData<Real> parameters(const Tables& t, int pair, Real effective_mass) {
    VolumeLawData<Real> law = volume_law_data(t, pair, effective_mass);
    law.damping = NormalDampingModel::paper;
    law.bounded_spring_energy = true;
    return law;
  }

  // The advisor's k_n (time_step_advisor.cpp).
  static AdvisedStiffness largest_normal_stiffness(const StiffestContact& c) {
    // p(V) = K min(V/A_ref, V^(1/3)): below the switch k_n = K A_n^2 / A_ref, its largest
    // value (docs/contact.md); above it the paper's K A_n^2 / (3 V^(2/3)) is softer.
    AdvisedStiffness s;
    s.normal_stiffness = c.modulus * c.area * c.area / (M_PI * c.radius_min * c.radius_min);
    return s;
  }
};

}  // namespace talus
