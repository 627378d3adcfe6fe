// The per-pair stage of the step (one thread per candidate pair on the GPU, a loop on the host):
// the pair's geometry, its previous history looked up by global ids, the force law of the
// scene's contact model, and the contact written to the pair's own slot. The functions are
// templated on the law (contact/laws/; the host picks it once per stage call through
// contact/contact_laws.hpp). Nothing is accumulated
// here, so the result does not depend on the order in which pairs run; accumulate_pair_forces
// then sums per particle in pair order.
#pragma once

#include "solver/contact/laws/law_common.hpp"
#include "solver/contact/pair_geometry.hpp"
#include "solver/contact/tangential_history.hpp"
#include "solver/step/particle_kernels.hpp"
#include "solver/step/template_table.hpp"

namespace talus {

// The per-material and per-model constants every pair reads (device-copyable: raw pointers).
template <class Real>
struct PairLawTables {
  TemplateTable<Real> bodies;            // per template
  const Real* youngs_modulus = nullptr;  // per material, Pa
  const Real* poisson_ratio = nullptr;   // per material
  // Per material pair (a * materials + b): mu, eps and the calibrated beta(eps).
  const Real* pair_friction = nullptr;
  const Real* pair_restitution = nullptr;
  const Real* pair_damping_ratio = nullptr;
  int materials = 0;
  bool with_friction = false;
  NormalDampingModel damping = NormalDampingModel::calibrated;
  Real time_step = 0;          // s
  LinearLawData<Real> linear;  // K_N, eta, gamma (friction filled per pair)
};

template <class Real>
struct PairContactRecord {
  bool in_contact = false;
  bool degenerate = false;
  int a = -1, b = -1;  // particle indices; A is the polyhedron of a polyhedron-sphere pair
  PairKey key;
  Vec3<Real> point;       // m
  Vec3<Real> force_on_a;  // N; B gets the opposite
  Vec3<Real> couple;      // N m, a torque on A besides (point - x_a) x force_on_a; B gets -couple
  ContactHistoryData<Real> history;
  Real normal_energy = 0;      // the normal elastic potential U, J
  Real tangential_energy = 0;  // the tangential and rocking springs' energy, J
  Real dissipation = 0;        // non-conservative power taken from the bodies, W (energy.hpp)
};

// Particle i's angular velocity in the world frame (zero without rotation).
template <class Real>
TALUS_HD inline Vec3<Real> world_angular_velocity(const ParticleView<Real>& p, int i) {
  if (!p.angular_velocity.present()) return Vec3<Real>();
  return rotate(p.orientation.get(i), p.angular_velocity.get(i));
}

template <class Real>
TALUS_HD inline Vec3<Real> point_velocity(const ParticleView<Real>& p, int i,
                                          const Vec3<Real>& point) {
  Vec3<Real> v = p.velocity.get(i);
  if (p.angular_velocity.present()) {
    const Vec3<Real> w = rotate(p.orientation.get(i), p.angular_velocity.get(i));
    v += cross(w, point - p.position.get(i));
  }
  return v;
}

// Which particle of the candidate (i, j) is A: a polyhedron-sphere pair has the polyhedron first
// (the simple contact's normal from it into the sphere).
template <class Real>
TALUS_HD inline void order_pair(const ParticleView<Real>& p, const PairLawTables<Real>& t, int i,
                                int j, int& ia, int& ib) {
  // A sphere second; otherwise the lower global id first, so that the pair's arithmetic does not
  // depend on the particles' order in memory or the ranks they are spread over.
  const bool si = t.bodies[p.template_id[i]].sphere, sj = t.bodies[p.template_id[j]].sphere;
  const bool swap = si != sj ? si : p.global_id[j] < p.global_id[i];
  ia = swap ? j : i;
  ib = swap ? i : j;
}

// Geometry for the ordered pair (ia, ib) except polyhedra under a law of volume geometry, which
// need an overlap workspace (polyhedra_volume_geometry, called by the backend with the capacity
// of the two templates).
template <class Law, class Real>
TALUS_HD inline PairGeometryData<Real> simple_pair_geometry(const ParticleView<Real>& p,
                                                            const PairLawTables<Real>& t, int ia,
                                                            int ib) {
  const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
  const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
  const Vec3<Real> xa = p.position.get(ia), xb = p.position.get(ib);
  if (a.sphere && b.sphere) {
    if constexpr (Law::kVolumeGeometry) {
      return sphere_lens_geometry(xa, a.sphere_radius, xb, b.sphere_radius);
    } else {
      return from_simple_contact(sphere_sphere_contact(xa, a.sphere_radius, xb, b.sphere_radius));
    }
  }
  const Pose<Real> pose_a{xa, p.orientation.get(ia)};
  if (b.sphere) {
    return from_simple_contact(polyhedron_sphere_contact(a.shape, pose_a, xb, b.sphere_radius));
  }
  const Pose<Real> pose_b{xb, p.orientation.get(ib)};
  return from_simple_contact(polyhedron_polyhedron_contact(a.shape, pose_a, b.shape, pose_b));
}

// The force of the ordered pair (ia, ib) with geometry g and `previous`, the pair's history from
// the step before (stored as seen from the lower global id as A; the default when the pair was
// not touching). `spring_dt` is the time the spring advances by (0 for the evaluation before the
// first step). The record's history is the one to keep for the next step.
template <class Law, class Real>
TALUS_HD inline PairContactRecord<Real> pair_contact_force(const ParticleView<Real>& p,
                                                           const PairLawTables<Real>& t, int ia,
                                                           int ib, const PairGeometryData<Real>& g,
                                                           Real spring_dt,
                                                           ContactHistoryData<Real> previous) {
  PairContactRecord<Real> r;
  r.a = ia;
  r.b = ib;
  r.degenerate = g.degenerate;
  if (!g.in_contact) return r;
  const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
  const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
  const int ma = p.material_id[ia], mb = p.material_id[ib];
  const int pair = ma * t.materials + mb;
  const Vec3<Real> v_r = point_velocity(p, ia, g.point) - point_velocity(p, ib, g.point);
  NormalContactData<Real> c;
  c.normal = g.normal;
  c.point = g.point;
  ContactForceData<Real> f;
  r.key = make_pair_key(p.global_id[ia], p.global_id[ib]);
  if constexpr (Law::kVolumeGeometry) {
    const Real ea = t.youngs_modulus[ma], eb = t.youngs_modulus[mb];
    const Real stiffness = ea / a.equivalent_radius + eb / b.equivalent_radius;  // Eq. 13 / A_n
    const Real shear =
        ea / (Real(2) * (Real(1) + t.poisson_ratio[ma]) * a.equivalent_radius) +
        eb / (Real(2) * (Real(1) + t.poisson_ratio[mb]) * b.equivalent_radius);  // Eq. 19 / A_n
    const NormalElastic<Real> e = Law::contact_elastic(
        stiffness, volume_reference_area(a.equivalent_radius, b.equivalent_radius), g.volume,
        g.area);
    c.normal_stiffness = e.stiffness;
    c.elastic = e.force;
    c.tangential_stiffness = shear * g.area;  // Eq. 19
    c.area = g.area;
    c.potential = e.energy;
  } else {
    const NormalElastic<Real> e = Law::contact_elastic(t.linear.stiffness, g.depth);
    c.elastic = e.force;
    c.potential = e.energy;
  }
  const auto law = Law::parameters(t, pair, a.mass * b.mass / (a.mass + b.mass));
  ContactHistoryData<Real> history;
  // The history's force and couple are stored as on the lower id as A.
  const Real sign = p.global_id[ia] == r.key.low ? Real(1) : Real(-1);
  if constexpr (Law::kTangentialHistory) {
    history = previous;
    history.elastic_force *= sign;
    history.rocking_moment *= sign;
  }
  f = Law::force(c, law, v_r, spring_dt, history);
  r.in_contact = true;
  r.point = g.point;
  r.force_on_a = f.total();
  if constexpr (Law::kPatchCouple) {
    if (p.angular_velocity.present()) {
      // The exact couple of U(V), -p M (OverlapResult::surface_moment; F^e = -p S, |S| = A_n),
      // and the patch's rocking spring and dashpots.
      r.couple = patch_couple(f, c.normal, c.area, c.normal_stiffness, t.pair_friction[pair],
                              world_angular_velocity(p, ia) - world_angular_velocity(p, ib),
                              spring_dt, history);
      if (c.area > Real(0)) r.couple -= g.moment * (c.elastic / c.area);
    }
  }
  if constexpr (Law::kTangentialHistory) {
    history.elastic_force *= sign;
    history.rocking_moment *= sign;
    r.history = history;
  }
  r.normal_energy = c.potential;
  r.tangential_energy = f.spring_energy;
  r.dissipation = f.dissipation;
  return r;
}

// The same, with the previous history found among old_keys[0 .. old_count) (sorted by key).
template <class Law, class Real>
TALUS_HD inline PairContactRecord<Real> pair_contact_force(
    const ParticleView<Real>& p, const PairLawTables<Real>& t, int ia, int ib,
    const PairGeometryData<Real>& g, Real spring_dt, const PairKey* old_keys,
    const ContactHistoryData<Real>* old_histories, int old_count) {
  ContactHistoryData<Real> previous;
  if constexpr (Law::kTangentialHistory) {
    if (g.in_contact) {
      const int found =
          find_pair_key(old_keys, old_count, make_pair_key(p.global_id[ia], p.global_id[ib]));
      if (found >= 0) previous = old_histories[found];
    }
  }
  return pair_contact_force<Law>(p, t, ia, ib, g, spring_dt, previous);
}

// Adds one contact's force and torques (Eqs. 21-22) to its two particles. Called over the
// contacts in pair order, it defines the sums' order; the host's and the CUDA step's per-particle
// accumulations make the same additions in that order (tests/step/test_host_threads.cpp).
template <class Real>
TALUS_HD inline void add_pair_force(const ParticleView<Real>& p, const PairContactRecord<Real>& c) {
  p.force.set(c.a, p.force.get(c.a) + c.force_on_a);
  p.force.set(c.b, p.force.get(c.b) - c.force_on_a);
  if (p.torque.present()) {
    p.torque.set(
        c.a, p.torque.get(c.a) + (cross(c.point - p.position.get(c.a), c.force_on_a) + c.couple));
    p.torque.set(
        c.b, p.torque.get(c.b) + (cross(c.point - p.position.get(c.b), -c.force_on_a) - c.couple));
  }
}

}  // namespace talus
