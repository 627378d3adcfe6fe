// The per-(particle, wall) stage of the step: the wall geometry of walls/wall_contact.hpp, the
// force law of the scene's contact model with the wall as an infinitely large rigid body, and
// the contact written to its own slot (accumulated later, in order, with the pair contacts).
// Templated on the law (contact/laws/), as the pair functions are.
#pragma once

#include "solver/contact/laws/linear_law.hpp"
#include "solver/step/pair_kernels.hpp"
#include "solver/walls/wall_contact.hpp"

namespace talus {

template <class Real>
struct WallContactRecord {
  bool in_contact = false;
  bool degenerate = false;
  int particle = -1, wall = -1;
  PairKey key;  // {global id, wall index}
  Vec3<Real> point;
  Vec3<Real> force;   // on the particle, N; the wall gets the opposite
  Vec3<Real> couple;  // N m, a torque on the particle besides (point - x) x force
  ContactHistoryData<Real> history;
  Real normal_energy = 0;      // the normal elastic potential U, J
  Real tangential_energy = 0;  // the tangential and rocking springs' energy, J
  Real dissipation = 0;        // non-conservative power taken from the bodies, W (energy.hpp)
  Real wall_power = 0;         // power the moving wall gives the particle, F . v_wall(point), W
};

// The scales of particle i's facet sums against a wall under Law (WallGeometrySum): K = E/R
// (volume laws) or K_N (linear), G = E / (2 (1 + nu) R), A_ref = pi R^2.
template <class Law, class Real>
TALUS_HD inline WallGeometrySum<Law, Real> wall_geometry_sum(const ParticleView<Real>& p,
                                                             const PairLawTables<Real>& t, int i) {
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  const int material = p.material_id[i];
  const Real youngs = t.youngs_modulus[material];
  const Real stiffness =
      Law::kVolumeGeometry ? youngs / body.equivalent_radius : t.linear.stiffness;
  const Real shear =
      youngs / (Real(2) * (Real(1) + t.poisson_ratio[material]) * body.equivalent_radius);
  const Real reference_area = volume_reference_area(body.equivalent_radius, body.equivalent_radius);
  return WallGeometrySum<Law, Real>(stiffness, shear, reference_area);
}

// The contact of particle i with a wall from its geometry g (sphere_wall_geometry, or a
// polyhedron's WallGeometrySum): the force law with the wall as a rigid body of infinite mass.
template <class Law, class Real>
TALUS_HD inline WallContactRecord<Real> wall_contact_with_geometry(
    const ParticleView<Real>& p, const PairLawTables<Real>& t, int i, int wall, int wall_material,
    const WallMotionData<Real>& motion, Real spring_dt, const PairKey* old_keys,
    const ContactHistoryData<Real>* old_histories, int old_count,
    const WallContactGeometry<Real>& g) {
  WallContactRecord<Real> r;
  r.particle = i;
  r.wall = wall;
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  const int material = p.material_id[i];
  r.degenerate = g.degenerate;
  if (!g.in_contact) return r;
  NormalContactData<Real> c;
  c.normal = g.normal;
  c.point = g.point;
  c.elastic = g.elastic;
  c.normal_stiffness = g.normal_stiffness;
  c.tangential_stiffness = g.tangential_stiffness;
  c.area = g.area;
  c.potential = g.potential;
  const int pair = material * t.materials + wall_material;
  const Vec3<Real> wall_velocity = motion.velocity_at(g.point);
  const Vec3<Real> v_r = point_velocity(p, i, g.point) - wall_velocity;
  ContactForceData<Real> f;
  r.key = PairKey{p.global_id[i], wall};
  ContactHistoryData<Real> history;
  if (!Law::kVolumeGeometry || !body.sphere) {
    const auto law = Law::parameters(t, pair, body.mass);  // 1 / m_wall = 0
    if constexpr (Law::kTangentialHistory) {
      const int found = find_pair_key(old_keys, old_count, r.key);
      if (found >= 0) history = old_histories[found];
    }
    f = Law::force(c, law, v_r, spring_dt, history);
  } else {
    f = LinearLaw::force(c, LinearLaw::parameters(t, pair, body.mass), v_r, spring_dt, history);
  }
  r.in_contact = true;
  r.point = g.point;
  r.force = f.total();
  if constexpr (Law::kPatchCouple) {
    if (!body.sphere && p.angular_velocity.present()) {
      r.couple = patch_couple(f, c.normal, c.area, c.normal_stiffness, t.pair_friction[pair],
                              world_angular_velocity(p, i) - motion.angular_velocity(), spring_dt,
                              history);
    }
  }
  if constexpr (Law::kTangentialHistory) r.history = history;
  // The facets' forces at their own points (for Law::kPatchCouple the sections' centroids: the
  // exact couple of U(V), polyhedron_wall_geometry).
  if (p.angular_velocity.present()) r.couple += g.couple;
  r.normal_energy = c.potential;
  r.tangential_energy = f.spring_energy;
  r.dissipation = f.dissipation;
  // The wall's power: its force and couple on the particle at the wall's velocities.
  r.wall_power = dot(r.force, wall_velocity) + dot(r.couple, motion.angular_velocity());
  return r;
}

// A sphere's contact is the nearest-facet rule's depth under the linear law whatever Law is (the
// volume laws refuse spheres with walls: WallContactStage).
template <class Law, class Real>
TALUS_HD inline WallContactRecord<Real> wall_contact(
    const ParticleView<Real>& p, const PairLawTables<Real>& t, int i, int wall, int wall_material,
    const WallFacets<Real>& facets, const WallMotionData<Real>& motion, Real spring_dt,
    const PairKey* old_keys, const ContactHistoryData<Real>* old_histories, int old_count) {
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  WallContactGeometry<Real> g;
  if (body.sphere) {
    g = sphere_wall_geometry(p.position.get(i), body.sphere_radius, facets, t.linear.stiffness);
  } else {
    const Pose<Real> pose{p.position.get(i), p.orientation.get(i)};
    WallGeometrySum<Law, Real> sum = wall_geometry_sum<Law>(p, t, i);
    visit_wall_facets(pose.position, body.shape.bounding_radius, facets,
                      [&](const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
                        return sum.add(clip_against_triangle_sized(body.shape, pose, a, b, c));
                      });
    g = sum.finish();
  }
  return wall_contact_with_geometry<Law>(p, t, i, wall, wall_material, motion, spring_dt, old_keys,
                                         old_histories, old_count, g);
}

template <class Real>
TALUS_HD inline void add_wall_force(const ParticleView<Real>& p, const WallContactRecord<Real>& c) {
  p.force.set(c.particle, p.force.get(c.particle) + c.force);
  if (p.torque.present()) {
    p.torque.set(c.particle, p.torque.get(c.particle) +
                                 (cross(c.point - p.position.get(c.particle), c.force) + c.couple));
  }
}

}  // namespace talus
