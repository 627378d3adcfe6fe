// What the contact-law types (volume_law.hpp, volume_paper_law.hpp, linear_law.hpp) share: the
// normal elastic part they return, the volume laws' parameters read from the law tables and their
// common members (VolumeLawBase), and what the time-step advisor tells a law about the stiffest
// contact of one kind. Each law is a
// stateless type whose static members the pair and wall kernels (step/pair_kernels.hpp,
// step/wall_kernels.hpp) are templated on; contact/contact_laws.hpp maps the scene's contact
// model to it. A law type has:
//   kName                  the scene's name of the law ("volume");
//   kVolumeGeometry        its geometry is the overlap volume (polyhedra: an overlap workspace;
//                          spheres: the lens; walls: the volume below each facet), else the depth;
//   kTangentialHistory     a tangential spring carried across steps (ContactHistoryData, kept in
//                          stores sorted by global-id keys);
//   kPatchCouple           on rotating bodies: the exact torque of U(V) (the overlap's surface
//                          moment; at walls the sections' centroids) and force_law.hpp's
//                          patch_couple (the rocking spring, the patch's dashpots);
//   kCalibratedDamping     reads beta(eps) of the calibrated damping per material pair;
//   kStiffnessAtLoad       its stiffness is unbounded as the overlap vanishes: the advisor
//                          evaluates it at the load a contact carries (none: no limit);
//   contact_elastic(...)   the normal elastic part of one contact (a pair);
//   facet_elastic(w, ...)  the same for one wall facet of area weight w (wall_contact.hpp);
//   parameters(t, pair, m) its per-contact parameters from the law tables (material pair `pair`,
//                          effective mass m);
//   force(c, law, v_r, dt, history)  the contact's force (force_law.hpp's functions);
//   largest_normal_stiffness(c), normal_damping_ratio(c, k_n, zeta)  host, for the advisor.
#pragma once

#include "solver/contact/force_law.hpp"

namespace talus {

// The normal elastic part of one contact (or of one wall facet, weighted by its area weight).
template <class Real>
struct NormalElastic {
  Real force = 0;      // |F_n^e|, N
  Real stiffness = 0;  // k_n, N/m (the volume laws'; the linear law leaves it 0)
  Real energy = 0;     // the normal elastic potential U, J
};

// The parameters both volume laws read from the law tables (step/pair_kernels.hpp's
// PairLawTables) for material pair `pair` and effective mass m; the damping model and the
// spring's energy bound are each law's own.
template <class Tables, class Real>
TALUS_HD inline VolumeLawData<Real> volume_law_data(const Tables& t, int pair,
                                                    Real effective_mass) {
  VolumeLawData<Real> law;
  law.effective_mass = effective_mass;
  law.restitution = t.pair_restitution[pair];
  law.friction = t.pair_friction[pair];
  law.damping_ratio = t.pair_damping_ratio[pair];
  law.time_step = t.time_step;
  law.with_friction = t.with_friction;
  return law;
}

// What the time-step advisor (time_step_advisor.cpp, host, double) knows of one kind of contact
// at its stiffest: a face on a face of area A (the smaller of the two largest faces; at a wall
// the particle's).
struct StiffestContact {
  double modulus = 0;           // K = E_a/R_a + E_b/R_b (Eq. 13 without A_n), Pa/m
  double area = 0;              // A, m^2
  double radius_min = 0;        // the smaller equivalent radius, m
  double mass_max = 0;          // the heavier body's mass, kg
  double inverse_mass = 0;      // 1/m_a + 1/m_b (translational), 1/kg
  double effective_mass = 0;    // m_eff = 1 / inverse_mass, kg
  double gravity = 0;           // |g|, m/s^2
  double speed = 0;             // the scene's largest initial speed, m/s
  double linear_stiffness = 0;  // the scene's K_N (linear law), N/m
  double linear_damping = 0;    // the scene's eta (linear law), N s/m
};

// A law's normal stiffness for the advisor, and the load it was evaluated at (0: none).
struct AdvisedStiffness {
  double normal_stiffness = 0;  // N/m
  double load = 0;              // N
};

// What the volume laws (volume_law.hpp, volume_paper_law.hpp) share, as a base of Law: the
// overlap volume's geometry with a tangential history, a pair's elastic part as a wall facet's of
// weight 1 (1 x = x: the same bits), force_law.hpp's volume_contact_force, and Eqs. 15 and 20's
// zeta(eps) as the advisor's normal damping ratio. Law gives the rest.
template <class Law>
struct VolumeLawBase {
  static constexpr bool kVolumeGeometry = true;
  static constexpr bool kTangentialHistory = true;

  // One contact of overlap volume V and area A_n.
  template <class Real>
  TALUS_HD static NormalElastic<Real> contact_elastic(Real modulus, Real reference_area,
                                                      Real volume, Real area) {
    return Law::facet_elastic(Real(1), modulus, reference_area, volume, area);
  }

  template <class Real>
  TALUS_HD static ContactForceData<Real> force(const NormalContactData<Real>& c,
                                               const VolumeLawData<Real>& law,
                                               const Vec3<Real>& v_r, Real dt,
                                               ContactHistoryData<Real>& history) {
    return volume_contact_force(c, law, v_r, dt, history);
  }

  // Eqs. 15 and 20's zeta(eps) (volume_paper's calibrated c_n rebounds with the same eps).
  static double normal_damping_ratio(const StiffestContact& /*c*/, double /*normal_stiffness*/,
                                     double restitution_ratio) {
    return restitution_ratio;
  }
};

}  // namespace talus
