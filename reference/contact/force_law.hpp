// Contact force laws of the reference solver, in Eigen/double. Three laws (docs/contact.md; the
// scene's ContactModel):
//   volume        the default volume law: the method paper's Eqs. 12-13 made linear in the
//                 overlap volume where that is softer, p(V) = K min(V / A_ref, V^(1/3)), with
//                 Eq. 15's damping form on its bounded stiffness (volume_elastic, VolumeLaw).
//   volume_paper  the paper's law (§2.5, Eqs. 12-22; walls §2.4) exactly: F^e = K A_n V^(1/3),
//                 with the calibrated damping (NormalDamping::kCalibrated) by default.
//   linear        BLAZE-DEM (§3.1, Eqs. 2-4).
// Both volume laws share the tangential spring of Eqs. 17-20 (volume_contact_force). The default
// law adds, with rotation, the exact couple of its potential (the overlap's surface moment; at a
// wall each facet's force at its section's centroid) and the patch couple: a rocking spring and
// dashpot and a twisting dashpot over the contact area (patch_couple).
//
// Conventions, for one contact between a body A and a body B (B may be a wall):
//   n        unit normal from A into B (for the volume laws n = S / |S|, S the vector area of
//            the overlap on A's surface, dV/dx_A = +S: moving A along n deepens the overlap);
//   v_r      v_A(c) - v_B(c), the velocity of A's material point at the contact point c relative
//            to B's; v_r . n > 0 while the bodies approach;
//   force    the force on A; B gets its opposite, and each body the torque (c - x) x F about its
//            own centroid (Eqs. 21-22), plus, for the default law, U(V)'s couple -p M and the
//            patch couple (A: +, B: -).
#pragma once

#include <Eigen/Core>

namespace talus::reference {

// The elastic part of one normal contact, as the geometry gives it (per pair, or a wall's facets
// combined, world.cpp).
struct NormalContact {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // n, unit, from A into B
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // c, m (world)
  double elastic = 0;               // |F_n^e|, N (volume_elastic's force; linear: K_N delta)
  double normal_stiffness = 0;      // k_n, N/m (volume_elastic's stiffness)
  double tangential_stiffness = 0;  // k_t of Eq. 19, N/m (volume laws)
  double area = 0;                  // A_n, m^2 (volume laws)
};

// The elastic normal law of the two volume models.
//   kDefault  p(V) = K min(V / A_ref, V^(1/3)), A_ref = pi R_min^2: |F^e| = p(V) A_n along -n,
//             k_n = p'(V) A_n^2 (bounded: K A_n^2 / A_ref at most), U(V) = integral of p.
//             Feng's construction (the paper's §2.5: F_A = -U'(V) S, dV/dx_A = S) with a pressure
//             whose slope is bounded, so that a face contact (V = A delta) is a linear spring
//             K A^2 / A_ref that a practical step can resolve and rest on; above the switch
//             volume V_s = A_ref^(3/2) (beyond any real overlap: V_s = 1.33 times the equal-volume
//             sphere of the smaller body) it is the paper's law.
//   kPaper    Eqs. 12-13 as printed: |F^e| = k_n V^(1/3), k_n = K A_n, U = 3/4 K V^(4/3); its
//             face-contact stiffness dF/d delta ~ delta^(-2/3) is unbounded (docs/contact.md).
enum class VolumeLaw { kDefault, kPaper };

// The material constants of a volume-law contact (the wall's terms vanish: it is rigid and flat).
struct VolumeModuli {
  double normal = 0;          // K = E_A/R_A + E_B/R_B, Pa/m (Eq. 13 without A_n)
  double shear = 0;           // G = E_A / (2 (1 + nu_A) R_A) + ..., Pa/m (Eq. 19 without A_n)
  double reference_area = 0;  // A_ref = pi R_min^2, m^2 (kDefault only)
};

// A_ref of the default law: pi min(R_A, R_B)^2 (at a wall: pass the particle's R twice).
double volume_law_reference_area(double radius_a, double radius_b);

// The default law's pressure p(V) = K min(V / A_ref, V^(1/3)) (Pa), its slope p'(V) = K / A_ref
// below V_s = A_ref^(3/2) and K / (3 V^(2/3)) above (Pa/m^3; the left slope at V_s), and its
// potential U(V) = K V^2 / (2 A_ref) below V_s, 3/4 K V^(4/3) - K A_ref^2 / 4 above (J; continuous
// at V_s, U' = p). V <= 0 gives 0.
double volume_law_pressure(double modulus, double reference_area, double volume);
double volume_law_pressure_slope(double modulus, double reference_area, double volume);
double volume_law_energy(double modulus, double reference_area, double volume);

// The paper law's potential 3/4 K V^(4/3) (J): Eq. 12's force is its gradient, K V^(1/3) S.
double paper_law_energy(double modulus, double volume);

// One overlap region under a volume law: a pair's overlap, or one wall facet's (the wall sums
// them with the area weights of §2.4).
struct VolumeElastic {
  double force = 0;      // |F^e|, N: p(V) A_n (kDefault), K A_n V^(1/3) (kPaper, Eqs. 12-13)
  double stiffness = 0;  // k_n, N/m: p'(V) A_n^2 (kDefault), K A_n (kPaper, Eq. 13)
  double energy = 0;     // U(V), J
};
VolumeElastic volume_elastic(VolumeLaw law, const VolumeModuli& moduli, double volume, double area);

// The energy stored in the tangential spring of Eq. 18, |F_t^e|^2 / (2 k_t) (J; 0 when k_t = 0).
double tangential_spring_energy(const Eigen::Vector3d& elastic_force, double tangential_stiffness);

// The normal damping of the volume laws (Eqs. 14-15).
//
//   kPaper       Eq. 15 (with the dissipating sign, damping_coefficient) on the contact's current
//                k_n (NormalContact::normal_stiffness). The default law's damping, always: its
//                k_n = p'(V) A_n^2 makes a face contact a LINEAR spring, for which Eq. 15 gives
//                restitution epsilon (a little more with the no-tension rule; measured in
//                test_default_volume_law.cpp). For volume_paper, Eq. 15 as printed on Eq. 13's
//                k_n = (E1/R1 + E2/R2) A_n: the paper's law is not linear in the penetration d
//                (F ~ d^(1/3) face to face, ~ d^3 corner first), and k_n grows with A_n, so the
//                restitution that results is not epsilon: measured in test_world_collisions.cpp
//                (0.96-0.99 face first for every epsilon).
//   kCalibrated  (volume_paper's default; it is calibrated on the paper's potential and means
//                nothing for the default law) a dashpot proportional to the contact area,
//                    c_n = eta A_n,   eta = beta(eps) m_eff^(1/4) K^(3/4) / sqrt(v0),
//                with K = E1/R1 + E2/R2 (Eq. 13 without A_n), v0 the largest normal approach
//                speed of the contact so far (its first touch, in an impact; kept in the pair's
//                history) and beta(eps) calibrated once (calibrated_damping_ratio). Why:
//                - Feng's construction makes the elastic force the gradient of a potential in
//                  the overlap volume alone: dV/dx = S, F^e = K dV^(1/3) S, so the stored energy
//                  is U = 3/4 K dV^(4/3) whatever the shapes. With the dashpot F^d = -eta A_n
//                  v_n n, along a head-on impact dV' = A_n v_n, and Newton's law divided by dV'
//                  is m v dv/d(dV) = -(K dV^(1/3) + eta v): A_n cancels. The impact in the
//                  variable dV is the same 1-D problem for faces, edges and corners, so one eta
//                  gives one restitution for every shape and orientation (the test measures
//                  it; rotation and friction couple in and make it approximate).
//                - With dV* = (m v0^2 / K)^(3/4), the scale of the largest overlap, the problem
//                  is q'' = -max(0, q^(1/3) + beta q'), q(0) = 0, q'(0) = 1 (q = dV/dV*): the
//                  restitution is a function of beta alone, and eta = beta m v0 / dV* (the
//                  expression above). The max(0, .) is the no-tension rule, so beta(eps) is
//                  solved for the contact that cannot pull (eps = 0.1 needs beta = 4.81, not
//                  the linear oscillator's value), and the result is eps at every impact speed.
//                - The coefficient is fixed by the approach, not by the current overlap: the
//                  overlap-based analogue (Tsuji's construction for Hertz) here needs eta ~
//                  dV^(-1/3), infinite at first touch, which stops a face dead in one step (the
//                  fate of the secant stiffness |F^e| / (dV / A_n) that preceded this). eta is
//                  finite for v0 > 0; a contact that has never approached (v0 = 0: placed in
//                  contact at rest) would have eta = infinity, so v0 is at least the speed
//                  sqrt(2 U(dV) / m_eff) that would have made the current overlap, U = 3/4 K
//                  dV^(4/3): never above the approach speed in an impact (so impacts keep the
//                  calibration), finite for a contact formed at rest. Known limit: at very low
//                  eps (0.1) a loaded contact at rest is damped ~4 times critically, above the
//                  step limit m_eff / dt of a resolved step, so the normal force alternates
//                  between steps (averaging right: a resting body stays at rest; a body dragged
//                  by friction on it is dragged too weakly). test_world_collisions.cpp shows it.
//                - It dissipates (c_n >= 0; with the no-tension rule the force stays between 0
//                  and the undamped one on the side that removes energy), leaves a contact at
//                  rest at rest (v_n = 0: no damping force), and needs one number per contact
//                  (v0) in the pair's history: the production solver can carry it as it
//                  carries the tangential spring.
//                The tangential damping (Eq. 20) keeps Eq. 15's form on k_t of Eq. 19: the
//                Cundall-Strack spring is linear, which is what Eq. 15 is for.
enum class NormalDamping { kPaper, kCalibrated };

// beta(eps) of kCalibrated: the damping of q'' = -max(0, q^(1/3) + beta q'), q(0) = 0,
// q'(0) = 1, whose rebound speed -q' at the end of the contact is eps. Solved by bisection on
// an RK4 integration (step 2e-4: within 3e-7 of a 4 times finer step; the test
// CalibratedDampingRatioGivesTheRestitution checks it) and cached per eps. beta(1) = 0.
// Throws std::invalid_argument unless eps is in (0, 1].
double calibrated_damping_ratio(double restitution);

// The rebound speed of that problem for a given beta (the function calibrated_damping_ratio
// inverts), for tests.
double clamped_volume_oscillator_restitution(double beta);

// Per pair material constants of a volume law.
struct VolumeLawParameters {
  double effective_mass = 0;  // m_eff = (1/m_A + 1/m_B)^-1, kg; the particle's mass at a wall
  double restitution = 1;     // epsilon in (0, 1] of Eqs. 15 and 20
  double friction = 0;        // mu of Eq. 17
  bool with_friction = false;
  NormalDamping damping = NormalDamping::kCalibrated;
  // The default law (kDefault) keeps the tangential spring's energy from growing when k_t falls:
  // volume_contact_force scales F_t^e by sqrt(k_t / k_t,before) then. volume_paper: false.
  bool bounded_spring_energy = false;
  // The time step, s (0: no limit). The normal damping coefficient is limited to m_eff / dt:
  // above it an explicit step would reverse v_n instead of damping it. In a resolved impact
  // (hundreds of steps in contact) kCalibrated never reaches it; it binds for a contact that
  // has never approached (v0 = 0) and for kPaper at very stiff faces.
  double time_step = 0;
};

// What a contact carries across steps: the elastic tangential force F_t^e = -k_t Delta-s of
// Eq. 18 (N, advanced incrementally: volume_contact_force), the largest normal approach speed
// v0 seen since it began (m/s; kCalibrated; < 0 before the first force evaluation), the k_t
// of the last evaluation with friction (N/m; 0 before it; bounded_spring_energy), and the default
// law's rocking spring (patch_couple): its moment M_e on A (N m, in the contact plane) and its
// k_r at the last evaluation (N m/rad; 0 before the first).
struct ContactHistory {
  Eigen::Vector3d elastic_force = Eigen::Vector3d::Zero();
  double approach_speed = -1;
  double spring_stiffness = 0;
  Eigen::Vector3d rocking_moment = Eigen::Vector3d::Zero();
  double rocking_stiffness = 0;
};

struct ContactForce {
  Eigen::Vector3d normal_force = Eigen::Vector3d::Zero();      // on A, N
  Eigen::Vector3d tangential_force = Eigen::Vector3d::Zero();  // on A, N
  bool sliding = false;                                        // the Coulomb cap bound this step
  // The dashpots this evaluation used (volume laws): c_n after the m_eff / dt limit, and c_t of
  // Eq. 20 (0 without friction), N s/m. The default law's patch couple reads them.
  double normal_damping = 0;
  double tangential_damping = 0;
  Eigen::Vector3d total() const { return normal_force + tangential_force; }
};

// Damping coefficient of Eqs. 15 and 20 for stiffness k and mass m, with the sign that
// dissipates: c = -2 ln(eps) sqrt(k m) / sqrt(ln(eps)^2 + pi^2) >= 0. As printed, Eq. 15 has
// +2 ln(eps), which is negative for eps < 1; with F^d = -c (v_r . n) n (Eq. 14) a negative c
// would push the bodies together faster and add energy. The magnitude is the printed one.
// Throws std::invalid_argument unless eps is in (0, 1] and k, m >= 0.
double damping_coefficient(double restitution, double stiffness, double mass);

// Either volume law (Eqs. 14-20) for one contact, given its elastic part (volume_elastic):
//   F_n = -(|F_n^e| + c_n v_n) n, with v_n = v_r . n, and no tension: a contact never pulls,
//         so F_n . n is kept <= 0 (when the damping would exceed the elastic force near the end
//         of an impact, the normal force is zero instead);
//   F_t = F_t^e - c_t v_t, |F_t| <= mu |F_n| (Eqs. 17-20), F_t^e = -k_t Delta-s (Eq. 18).
// F_t^e is advanced by increments: its previous value is turned onto the plane normal to n
// keeping its length (the contact frame turned with the bodies), then changes by -k_t v_t dt
// with the present k_t; where the cap binds, it is reset to the capped force plus c_t v_t.
// For a constant k_t that is Eq. 18; with k_t proportional to the overlap's area (Eq. 19), Eq. 18
// taken literally would change the force at a fixed Delta-s whenever the area changes, which
// creates elastic energy (a rocking polyhedron gains energy without bound). dt = 0 leaves
// F_t^e's length unchanged (the force evaluation before the first step).
// With law.bounded_spring_energy (the default law), before the increment F_t^e is scaled by
// sqrt(k_t / k_t,before) where k_t fell since the last evaluation (k_t,before in the history):
// the spring's energy |F_t^e|^2 / (2 k_t) is then the one it held, where at a fixed force it
// would grow as 1 / k_t, energy from nothing that the spring gives back as motion as a contact
// ends (k_t = G A_n -> 0). A rising k_t keeps the force (its energy falls: dissipated).
// volume_paper keeps the force as before.
ContactForce volume_contact_force(const NormalContact& contact, const VolumeLawParameters& law,
                                  const Eigen::Vector3d& relative_velocity, double dt,
                                  ContactHistory& history);

// The default volume law's patch couple: what one contact point leaves out of a pressure and a
// shear spread over the contact patch A_n. A torque on A besides (c - x_A) x F and the exact couple
// of U(V) (the overlap's surface moment, applied by world.cpp), B (or the wall) getting its
// opposite; only for `volume`, with rotation.
//   w_rel = w_A - w_B (world; a rotating wall's w_B = its axis times its angular speed),
//   n the contact normal, w_n = w_rel . n, w_perp = w_rel - w_n n.
//   Rocking spring: U(V) alone gives a face resting on a face no tilt stiffness (tilting it at a
//   fixed volume leaves V unchanged: a cube on a cube is an inverted pendulum). Read the contact's
//   k_n as a Winkler foundation spread evenly over the patch, k_n / A_n per unit area: a tilt
//   theta about an axis through the centre in the patch's plane meets the moment
//   k_n (I / A_n) theta, I the second moment of the patch about that axis, A_n^2 / 12 for a square
//   (a disc: A_n^2 / (4 pi), 5% less). So k_r = k_n A_n / 12, and the spring's moment M_e is kept
//   in the history and advanced as the tangential spring is: turned into the plane normal to the
//   current n with its length kept, scaled by sqrt(k_r / k_before) where k_r fell (its energy
//   |M_e|^2 / (2 k_r) never grows from nothing), then M_e -= k_r w_perp dt.
//   Rocking dashpot: the normal dashpot spread alike, c_r = c_n A_n / 12, in parallel:
//       M_rock = M_e - c_r w_perp,
//   scaled down to |F_n| sqrt(A_n) / 2 at most (a pressure that cannot pull moves its resultant
//   at most to the patch's edge, half a side from the centre); where that binds the spring slips,
//   M_e = M_rock + c_r w_perp, as the tangential spring at Coulomb's cap.
//   Twisting: the tangential dashpot c_t (Eq. 20) spread alike meets the in-plane speed
//   w_n |r| of a twist, a moment -c_t (J / A_n) w_n about n, J = A_n^2 / 6 the polar moment of
//   the square:
//       M_twist = -c_t (A_n / 6) w_n,
//   clamped to +-mu |F_n| (2/3) sqrt(A_n / pi): Coulomb's mu |F_n| at the mean radius of a disc
//   of area A_n.
// Why the dashpots: at one contact point neither dashpot sees a rotation about that point, so a
// face resting on a face rocks and spins undamped (a stack of cubes never settles, a tetrahedron
// spins on its face for ever: the production solver's tests/step/test_hard_cases.cpp).
// `force` is the law's result for the contact (its normal force and its dashpots), `area` A_n
// (walls: sum_i w_i A_i, the area of k_t), `normal_stiffness` the contact's k_n, `friction` the
// pair's mu, `dt` the time the spring advances by (0 in the evaluation before the first step),
// `history` the contact's (M_e and k_r are read and written; A's view, see world.cpp). No area:
// the rocking history is cleared and the couple is zero.
struct PatchCouple {
  Eigen::Vector3d rocking = Eigen::Vector3d::Zero();   // N m, in the contact plane
  Eigen::Vector3d twisting = Eigen::Vector3d::Zero();  // N m, along n
  Eigen::Vector3d total() const { return rocking + twisting; }
  // -total() . w_rel, W: the power the couple takes from the relative rotation. Not a loss: it
  // is negative while the rocking spring gives back the energy it holds.
  double dissipation = 0;
  double spring_energy = 0;  // |M_e|^2 / (2 k_r) after this evaluation, J (0 when k_r = 0)
};
PatchCouple patch_couple(const ContactForce& force, const Eigen::Vector3d& normal, double area,
                         double normal_stiffness, double friction,
                         const Eigen::Vector3d& relative_angular_velocity, double dt,
                         ContactHistory& history);

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
