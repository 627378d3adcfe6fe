// The reference world's particle-wall contacts (world.hpp): a polyhedron against a wall's
// triangles by the area-weighted sections of §2.4 (wall_area.hpp) under the volume or linear
// law, and a sphere by the nearest-facet rule. Split from world.cpp by idea; the same class.
#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/contact/contact_geometry.hpp"
#include "reference/geometry/wall_area.hpp"
#include "reference/world/world.hpp"

namespace talus::reference {

void RefWorld::wall_contact_of(int i, int w, const std::vector<RefTriangle>& triangles,
                               double spring_dt,
                               std::map<std::pair<long long, int>, ContactHistory>& next) {
  const RefBody& p = bodies_[i];
  if (p.kind == ParticleShapeKind::sphere) {
    sphere_wall_contact(i, w, triangles);
    return;
  }
  const RefWall& wall = setup_.walls[w];
  const ShapeTemplate& shape = setup_.templates[p.shape];
  const RefEffects& fx = setup_.effects;
  RefPose pose;
  pose.position = p.state.position, pose.orientation = p.state.orientation;
  const RefMaterial& mp = setup_.materials[p.material];
  // The wall is infinitely large and rigid: R_wall = infinity, so its term E/R in Eqs. 13 and 19
  // vanishes whatever its E (the wall adds no compliance and no curvature), m_eff of Eq. 15
  // is the particle's mass (1/m_wall = 0), and A_ref is the particle's own pi R^2.
  VolumeModuli moduli;
  moduli.normal = mp.youngs_modulus / p.equivalent_radius;
  moduli.shear = mp.youngs_modulus / (2 * (1 + mp.poisson_ratio) * p.equivalent_radius);
  moduli.reference_area = volume_law_reference_area(p.equivalent_radius, p.equivalent_radius);
  const bool volume_model = is_volume_model(fx.contact);

  // Area weighting (§2.4): each facet reached contributes its half-space contact times
  // w = overlap area / section area, so a section spread over coplanar facets counts once.
  Eigen::Vector3d elastic = Eigen::Vector3d::Zero();  // on the particle
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  // Each facet's elastic force acts at its own point: sum of x_i x F_i, about the origin.
  Eigen::Vector3d force_moment = Eigen::Vector3d::Zero();
  double k_n = 0, k_t = 0, area_sum = 0, weight = 0, volume = 0, area = 0, depth = 0;
  double energy = 0;
  for (const RefTriangle& t : triangles) {
    const Eigen::Vector3d q = closest_point_on_triangle(p.state.position, t[0], t[1], t[2]);
    if ((q - p.state.position).norm() > p.bounding_radius) continue;
    const RefWallContact wc = wall_contact(shape, pose, t[0], t[1], t[2]);
    if (!wc.reaches_plane || !(wc.overlap_area > 0) || !(wc.section_area > 0)) continue;
    const double wt = wc.overlap_area / wc.section_area;
    const Eigen::Vector3d elastic_before = elastic;
    if (volume_model) {
      if (!(wc.volume_below > 0)) continue;
      // Facet i: w_i F^e(V_i, A_i) along n_i, k_n and U summed with the same weights.
      const VolumeElastic e =
          volume_elastic(volume_law(), moduli, wc.volume_below, wc.section_area);
      elastic += wt * e.force * wc.normal;
      k_n += wt * e.stiffness;
      k_t += wt * moduli.shear * wc.section_area;  // Eq. 19
      energy += wt * e.energy;
    } else {
      if (!(wc.depth > 0)) continue;
      elastic += wt * fx.linear.stiffness * wc.depth * wc.normal;
      energy += wt * 0.5 * fx.linear.stiffness * wc.depth * wc.depth;
    }
    // The point of this facet's force. The default law: the clipped section's centroid, the
    // exact torque of U(V): turning the particle by theta about an axis through x_A changes the
    // volume below a plane by theta times the section's moment about that axis (the section
    // sweeps it), so -U'(V) dV/dtheta is the force at the section's centroid. Its tilt stiffness
    // is the patch couple's rocking spring (force_law.hpp). volume_paper: the section's centroid
    // moved by the offset of the volume below the plane from the whole section's centroid
    // (wall_area.hpp), so that a facet holding the whole section puts the force at the volume's
    // centroid, as the overlap polytope's centroid does between particles: a tilted face is
    // pushed back level. The linear law keeps the section's centroid (its force is the depth's).
    const Eigen::Vector3d facet_point =
        fx.contact == ContactModel::volume_paper
            ? Eigen::Vector3d(wc.overlap_centroid + wc.volume_offset)
            : wc.overlap_centroid;
    moment += wc.overlap_area * facet_point;
    force_moment += facet_point.cross(elastic - elastic_before);
    area_sum += wc.overlap_area;
    weight += wt;
    volume += wt * wc.volume_below;
    area += wt * wc.section_area;
    depth = std::max(depth, wc.depth);
  }
  const double magnitude = elastic.norm();
  if (!(area_sum > 0) || !(magnitude > 0)) return;

  NormalContact nc;
  nc.normal = -elastic / magnitude;  // from the particle into the wall
  nc.point = moment / area_sum;      // the facets' points, weighted by their clipped areas
  nc.elastic = magnitude;
  nc.normal_stiffness = k_n;
  nc.tangential_stiffness = k_t;
  nc.area = area;
  const PairProperties props = pair_properties(p.material, wall.material);
  const Eigen::Vector3d v_r =
      point_velocity(i, nc.point) - wall.motion.velocity_at(nc.point, time_);
  ContactForce f;
  double tangential_energy = 0;  // the tangential spring's and the rocking spring's
  PatchCouple patch;             // zero but for the default law with rotation
  if (volume_model) {
    const VolumeLawParameters law = volume_parameters(props, p.state.mass);
    const std::pair<long long, int> key(p.id, w);
    ContactHistory history;
    if (auto it = wall_histories_.find(key); it != wall_histories_.end()) history = it->second;
    f = volume_contact_force(nc, law, v_r, spring_dt, history);
    tangential_energy = tangential_spring_energy(history.elastic_force, k_t);
    if (fx.contact == ContactModel::volume && fx.rotation) {
      // The default law's patch couple (force_law.hpp) against the wall's own rotation, the
      // particle as A: the particle gets it, the wall its opposite.
      patch = patch_couple(f, nc.normal, area, k_n, props.friction,
                           p.state.angular_velocity_world() - wall.motion.angular_velocity(),
                           spring_dt, history);
      tangential_energy += patch.spring_energy;
    }
    next[key] = history;
  } else {
    f = linear_contact_force(nc, linear_law(props), v_r);
  }
  const Eigen::Vector3d force = f.total();
  apply(i, nc.point, force);
  wall_force_[w] -= force;
  wall_torque_[w] -= (nc.point - wall.motion.point).cross(force);
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();
  if (fx.rotation) {
    // The facets' forces at their own points rather than their sum at nc.point: the couple
    // sum (x_i - point) x F_i, zero for coplanar facets; at a wall's edge or corner one force at
    // one point would turn the particle by work from nothing.
    couple = force_moment - nc.point.cross(elastic) + patch.total();
  }
  bodies_[i].state.torque += couple;
  wall_torque_[w] -= couple;
  RefContact c;
  c.body_a = i, c.wall = w;
  c.couple = couple;
  c.point = nc.point, c.normal = nc.normal;
  c.force_on_a = force, c.tangential_force = f.tangential_force;
  c.volume = volume, c.area = area, c.depth = depth, c.weight = weight;
  c.elastic_energy = energy;
  c.tangential_energy = tangential_energy;
  c.sliding = f.sliding;
  contacts_.push_back(c);
}

void RefWorld::sphere_wall_contact(int i, int w, const std::vector<RefTriangle>& triangles) {
  // Linear model only (the constructor refuses the volume model). Nearest-facet rule: the point
  // q of the wall's surface (the union of its triangles) closest to the centre c, over all
  // triangles; delta = r - |c - q|, n = (q - c) / |c - q|, one contact per particle and wall.
  // This is the sphere's exact penetration of the wall's surface: sliding across an edge
  // between coplanar facets, or onto a vertex shared by several, it neither doubles nor drops
  // (the closest point is continuous there), which the area weighting of §2.4 only approximates
  // and needs the disc-triangle area for. It is docs/geometry.md's sphere-polyhedron simple
  // contact with the wall's triangles as the surface. The point is midway between q and the
  // sphere's deepest point c + r n, as for sphere-polyhedron.
  const RefBody& p = bodies_[i];
  const RefWall& wall = setup_.walls[w];
  const Eigen::Vector3d& c = p.state.position;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d q = c;
  for (const RefTriangle& t : triangles) {
    const Eigen::Vector3d x = closest_point_on_triangle(c, t[0], t[1], t[2]);
    const double d = (x - c).norm();
    if (d < best) best = d, q = x;
  }
  if (!(best < p.sphere_radius) || !(best > 0)) return;  // apart, or the centre on the surface
  NormalContact nc;
  nc.normal = (q - c) / best;
  const double depth = p.sphere_radius - best;
  nc.point = 0.5 * (q + (c + p.sphere_radius * nc.normal));
  nc.elastic = setup_.effects.linear.stiffness * depth;
  const PairProperties props = pair_properties(p.material, wall.material);
  const Eigen::Vector3d v_r =
      point_velocity(i, nc.point) - wall.motion.velocity_at(nc.point, time_);
  const ContactForce f = linear_contact_force(nc, linear_law(props), v_r);
  const Eigen::Vector3d force = f.total();
  apply(i, nc.point, force);
  wall_force_[w] -= force;
  wall_torque_[w] -= (nc.point - wall.motion.point).cross(force);
  RefContact rc;
  rc.body_a = i, rc.wall = w;
  rc.point = nc.point, rc.normal = nc.normal;
  rc.force_on_a = force, rc.tangential_force = f.tangential_force;
  rc.depth = depth;
  rc.elastic_energy = 0.5 * setup_.effects.linear.stiffness * depth * depth;
  rc.sliding = f.sliding;
  contacts_.push_back(rc);
}

}  // namespace talus::reference
