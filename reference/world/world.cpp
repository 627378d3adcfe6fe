#include "reference/world/world.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "reference/contact/contact_geometry.hpp"
#include "reference/dynamics/effects.hpp"

namespace talus::reference {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("reference world: " + what);
}

bool positive_finite(double x) {
  return std::isfinite(x) && x > 0;
}

double equal_volume_radius(double volume) {
  return std::cbrt(3 * volume / (4 * M_PI));
}

}  // namespace

RefWorld::RefWorld(RefWorldSetup setup) : setup_(std::move(setup)) {
  if (!positive_finite(setup_.time_step)) fail("the time step must be positive");
  const int n_materials = static_cast<int>(setup_.materials.size());
  for (const RefMaterial& m : setup_.materials) {
    if (!positive_finite(m.density) || !positive_finite(m.youngs_modulus) ||
        !(m.poisson_ratio > -1 && m.poisson_ratio < 0.5) || !(m.friction >= 0) ||
        !(m.restitution > 0 && m.restitution <= 1)) {
      fail("material '" + m.name +
           "' needs density > 0, E > 0, nu in (-1, 0.5), mu >= 0, epsilon in (0, 1]");
    }
  }
  for (const ShapeTemplate& t : setup_.templates) {
    if (!positive_finite(t.volume) || t.vertices.size() < 4) {
      fail("template '" + t.name + "' has no volume");
    }
  }
  const RefEffects& fx = setup_.effects;
  if (fx.contact == ContactModel::linear &&
      (!(fx.linear.stiffness > 0) || !(fx.linear.damping >= 0) ||
       !(fx.linear.tangential_damping >= 0))) {
    fail("the linear model needs K_N > 0, eta >= 0 and gamma >= 0");
  }
  if (fx.contact == ContactModel::volume && fx.damping == NormalDamping::kCalibrated) {
    fail(
        "the calibrated normal damping belongs to volume_paper (it is calibrated on the paper's "
        "potential); the default volume law damps with Eq. 15 on its stiffness");
  }
  if (fx.drag_alpha && !(*fx.drag_alpha >= 0)) fail("drag alpha must be >= 0");
  for (const RefBodySpec& spec : setup_.bodies) add_body_unchecked(spec);
  bool any_sphere = false, any_polyhedron = false;
  for (const RefBody& b : bodies_) {
    (b.kind == ParticleShapeKind::sphere ? any_sphere : any_polyhedron) = true;
  }
  if (fx.contacts && is_volume_model(fx.contact) && any_sphere && any_polyhedron) {
    fail(
        "sphere-polyhedron contact in the volume model is not supported by the reference solver "
        "(no exact sphere-polyhedron overlap); use the linear model");
  }
  for (size_t w = 0; w < setup_.walls.size(); ++w) {
    const RefWall& wall = setup_.walls[w];
    if (wall.material < 0 || wall.material >= n_materials) {
      fail("wall '" + wall.name + "': no such material");
    }
    if (fx.contacts && is_volume_model(fx.contact) && any_sphere && !wall.triangles.empty()) {
      fail(
          "sphere-wall contact in the volume model is not supported by the reference solver (no "
          "exact cap-triangle overlap yet); use the linear model");
    }
    for (const RefTriangle& t : wall.triangles) {
      if ((t[1] - t[0]).cross(t[2] - t[0]).norm() == 0) {
        fail("wall '" + wall.name + "' has a degenerate triangle");
      }
    }
    if (wall.motion.kind == RefWallMotion::Kind::kRotation && wall.motion.axis.norm() == 0) {
      fail("wall '" + wall.name + "': the rotation axis is zero");
    }
    if (wall.motion.kind == RefWallMotion::Kind::kOscillation &&
        (wall.motion.axis.norm() == 0 || !(wall.motion.amplitude > 0) ||
         !(wall.motion.frequency > 0) || wall.motion.cycles < 0)) {
      fail("wall '" + wall.name +
           "': an oscillation needs a direction, a positive amplitude and frequency, cycles >= 0");
    }
  }
  wall_force_.assign(setup_.walls.size(), Eigen::Vector3d::Zero());
  wall_torque_.assign(setup_.walls.size(), Eigen::Vector3d::Zero());
}

void RefWorld::add_body_unchecked(const RefBodySpec& spec) {
  const RefEffects& fx = setup_.effects;
  const int n_materials = static_cast<int>(setup_.materials.size());
  const std::string where =
      "body " + std::to_string(bodies_.size()) + " (id " + std::to_string(spec.id) + ")";
  if (spec.material < 0 || spec.material >= n_materials) fail(where + ": no such material");
  if (!ids_.insert(spec.id).second) fail(where + ": the id is used twice");
  const RefMaterial& mat = setup_.materials[spec.material];
  RefBody body;
  body.kind = spec.kind;
  body.material = spec.material;
  body.id = spec.id;
  if (spec.kind == ParticleShapeKind::polyhedron) {
    if (spec.shape < 0 || spec.shape >= static_cast<int>(setup_.templates.size())) {
      fail(where + ": no such template");
    }
    const ShapeTemplate& t = setup_.templates[spec.shape];
    body.state = RigidBody::from_template(t, mat.density);
    body.shape = spec.shape;
    body.bounding_radius = t.bounding_radius;
    body.equivalent_radius = equal_volume_radius(t.volume);
  } else {
    const double r = spec.sphere_radius;
    if (!positive_finite(r)) fail(where + ": a sphere needs a positive radius");
    const double mass = mat.density * 4 * M_PI * r * r * r / 3;
    body.state =
        RigidBody::with_mass_properties(mass, Eigen::Vector3d::Constant(0.4 * mass * r * r));
    body.sphere_radius = r;
    body.bounding_radius = r;
    body.equivalent_radius = r;
  }
  body.state.position = spec.position;
  body.state.orientation = spec.orientation.normalized();
  body.state.velocity = spec.velocity;
  body.state.angular_velocity_body =
      fx.rotation ? Eigen::Vector3d(body.state.orientation.conjugate() * spec.angular_velocity)
                  : Eigen::Vector3d::Zero();
  bodies_.push_back(body);
}

void RefWorld::add_body(const RefBodySpec& spec) {
  const bool polyhedron = spec.kind == ParticleShapeKind::polyhedron;
  for (const RefBody& b : bodies_) {
    if (b.kind != spec.kind && setup_.effects.contacts && is_volume_model(setup_.effects.contact)) {
      fail(
          "sphere-polyhedron contact in the volume model is not supported by the reference "
          "solver (no exact sphere-polyhedron overlap); use the linear model");
    }
  }
  if (!polyhedron && setup_.effects.contacts && is_volume_model(setup_.effects.contact)) {
    for (const RefWall& wall : setup_.walls) {
      if (!wall.triangles.empty()) {
        fail("sphere-wall contact in the volume model is not supported by the reference solver");
      }
    }
  }
  add_body_unchecked(spec);
  // The integrator's first half-step uses the accumulated force: give the new body its body
  // forces now (it touches nothing: insertion places it clear of particles and walls).
  RefBody& b = bodies_.back();
  b.state.clear_accumulators();
  if (setup_.effects.gravity) add_gravity(b.state, *setup_.effects.gravity);
  if (setup_.effects.drag_alpha) add_quadratic_drag(b.state, *setup_.effects.drag_alpha);
}

void RefWorld::remove_last_wall_triangles(int w, int count) {
  std::vector<RefTriangle>& triangles = setup_.walls.at(w).triangles;
  if (count < 0 || count > static_cast<int>(triangles.size())) {
    fail("wall '" + setup_.walls[w].name + "': cannot remove " + std::to_string(count) +
         " of its " + std::to_string(triangles.size()) + " triangles");
  }
  triangles.resize(triangles.size() - count);
}

PairProperties RefWorld::pair_properties(int material_a, int material_b) const {
  if (setup_.pair_rule) return setup_.pair_rule(material_a, material_b);
  const RefMaterial& a = setup_.materials[material_a];
  const RefMaterial& b = setup_.materials[material_b];
  return {0.5 * (a.friction + b.friction), 0.5 * (a.restitution + b.restitution)};
}

std::vector<RefTriangle> RefWorld::wall_triangles(int w) const {
  const RefWall& wall = setup_.walls.at(w);
  std::vector<RefTriangle> out;
  for (const RefTriangle& t : wall.triangles) {
    out.push_back({wall.motion.position(t[0], time_), wall.motion.position(t[1], time_),
                   wall.motion.position(t[2], time_)});
  }
  return out;
}

Eigen::Vector3d RefWorld::point_velocity(int body, const Eigen::Vector3d& point) const {
  const RigidBody& b = bodies_[body].state;
  return b.velocity + b.angular_velocity_world().cross(point - b.position);
}

void RefWorld::apply(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force) {
  RigidBody& b = bodies_[body].state;
  b.force += force;
  b.torque += (point - b.position).cross(force);  // Eqs. 21-22
}

LinearLawParameters RefWorld::linear_law(const PairProperties& props) const {
  const RefEffects& fx = setup_.effects;
  LinearLawParameters law;
  law.stiffness = fx.linear.stiffness;
  law.damping = fx.linear.damping;
  law.tangential_damping = fx.linear.tangential_damping;
  law.friction = props.friction;
  law.with_friction = fx.friction;
  return law;
}

VolumeLaw RefWorld::volume_law() const {
  return setup_.effects.contact == ContactModel::volume_paper ? VolumeLaw::kPaper
                                                              : VolumeLaw::kDefault;
}

VolumeLawParameters RefWorld::volume_parameters(const PairProperties& props,
                                                double effective_mass) const {
  const RefEffects& fx = setup_.effects;
  VolumeLawParameters law;
  // The default law damps with Eq. 15 on its own k_n (force_law.hpp); volume_paper calibrates.
  law.damping = fx.damping.value_or(volume_law() == VolumeLaw::kPaper ? NormalDamping::kCalibrated
                                                                      : NormalDamping::kPaper);
  law.time_step = setup_.time_step;
  law.effective_mass = effective_mass;
  law.restitution = props.restitution;
  law.friction = props.friction;
  law.with_friction = fx.friction;
  // The default law's tangential spring never gains energy from a falling k_t (force_law.hpp).
  law.bounded_spring_energy = volume_law() == VolumeLaw::kDefault;
  return law;
}

void RefWorld::pair_contact(int i, int j, double spring_dt,
                            std::map<std::pair<long long, long long>, ContactHistory>& next) {
  const RefBody& a = bodies_[i];
  const RefBody& b = bodies_[j];
  const RefEffects& fx = setup_.effects;
  const bool sphere_a = a.kind == ParticleShapeKind::sphere;
  const bool sphere_b = b.kind == ParticleShapeKind::sphere;
  // A polyhedron-sphere pair is handled with the polyhedron first (normal from A into B).
  const bool swap = sphere_a && !sphere_b;
  const int ia = swap ? j : i, ib = swap ? i : j;
  const RefBody& pa = bodies_[ia];
  const RefBody& pb = bodies_[ib];
  RefPose pose_a, pose_b;
  pose_a.position = pa.state.position, pose_a.orientation = pa.state.orientation;
  pose_b.position = pb.state.position, pose_b.orientation = pb.state.orientation;

  PairGeometry g;
  if (is_volume_model(fx.contact)) {
    g = (sphere_a && sphere_b) ? sphere_lens_geometry(pose_a.position, pa.sphere_radius,
                                                      pose_b.position, pb.sphere_radius)
                               : volume_geometry(setup_.templates[pa.shape], pose_a,
                                                 setup_.templates[pb.shape], pose_b);
  } else if (sphere_a && sphere_b) {
    g = linear_sphere_geometry(pose_a.position, pa.sphere_radius, pose_b.position,
                               pb.sphere_radius);
  } else if (sphere_a || sphere_b) {
    g = linear_polyhedron_sphere_geometry(setup_.templates[pa.shape], pose_a, pose_b.position,
                                          pb.sphere_radius);
  } else {
    g = linear_polyhedra_geometry(setup_.templates[pa.shape], pose_a, setup_.templates[pb.shape],
                                  pose_b);
  }
  if (!g.in_contact) return;

  const RefMaterial& ma = setup_.materials[pa.material];
  const RefMaterial& mb = setup_.materials[pb.material];
  const PairProperties props = pair_properties(pa.material, pb.material);
  const Eigen::Vector3d v_r = point_velocity(ia, g.point) - point_velocity(ib, g.point);
  RefContact c;
  c.body_a = ia, c.body_b = ib;
  c.point = g.point, c.normal = g.normal;
  ContactForce f;
  if (is_volume_model(fx.contact)) {
    VolumeModuli moduli;
    moduli.normal = ma.youngs_modulus / pa.equivalent_radius +
                    mb.youngs_modulus / pb.equivalent_radius;  // Eq. 13 / A_n
    moduli.shear = ma.youngs_modulus / (2 * (1 + ma.poisson_ratio) * pa.equivalent_radius) +
                   mb.youngs_modulus / (2 * (1 + mb.poisson_ratio) * pb.equivalent_radius);
    moduli.reference_area = volume_law_reference_area(pa.equivalent_radius, pb.equivalent_radius);
    const VolumeElastic e = volume_elastic(volume_law(), moduli, g.volume, g.area);
    NormalContact nc;
    nc.normal = g.normal, nc.point = g.point;
    nc.elastic = e.force;                             // Eq. 12 (paper) or p(V) A_n (default)
    nc.normal_stiffness = e.stiffness;                // Eq. 13 (paper) or p'(V) A_n^2 (default)
    nc.tangential_stiffness = moduli.shear * g.area;  // Eq. 19
    nc.area = g.area;
    const VolumeLawParameters law =
        volume_parameters(props, pa.state.mass * pb.state.mass / (pa.state.mass + pb.state.mass));
    const auto key = std::minmax(pa.id, pb.id);
    ContactHistory history;
    if (auto it = pair_histories_.find(key); it != pair_histories_.end()) history = it->second;
    // The springs' force and moment are stored for the lower id as A: flip them for the other
    // order (both are A's, odd in the swap).
    const double sign = pa.id == key.first ? 1.0 : -1.0;
    const auto flip = [&history, sign] {
      history.elastic_force *= sign;
      history.rocking_moment *= sign;
    };
    flip();
    f = volume_contact_force(nc, law, v_r, spring_dt, history);
    double rocking_energy = 0;
    if (fx.contact == ContactModel::volume && fx.rotation) {
      // The default law's couples on A (B gets their opposite): its patch couple (force_law.hpp)
      // and the exact couple of U(V) about the point, -p M with p = |F^e| / A_n (F^e = -p S).
      const PatchCouple pc =
          patch_couple(f, g.normal, g.area, nc.normal_stiffness, props.friction,
                       pa.state.angular_velocity_world() - pb.state.angular_velocity_world(),
                       spring_dt, history);
      c.couple = pc.total();
      if (g.area > 0) c.couple -= (e.force / g.area) * g.moment;
      rocking_energy = pc.spring_energy;
    }
    flip();
    // The elastic tangential force (with friction), v0 (kCalibrated) and the rocking spring.
    next[key] = history;
    // Feng's potential: F_A = -U'(V) S (force_law.hpp).
    c.elastic_energy = e.energy;
    c.tangential_energy =
        tangential_spring_energy(history.elastic_force, nc.tangential_stiffness) + rocking_energy;
    c.volume = g.volume, c.area = g.area;
  } else {
    NormalContact nc;
    nc.normal = g.normal, nc.point = g.point;
    nc.elastic = fx.linear.stiffness * g.depth;
    f = linear_contact_force(nc, linear_law(props), v_r);
    c.elastic_energy = 0.5 * fx.linear.stiffness * g.depth * g.depth;
    c.depth = g.depth;
  }
  const Eigen::Vector3d force = f.total();
  apply(ia, g.point, force);
  apply(ib, g.point, -force);
  bodies_[ia].state.torque += c.couple;  // zero but for the default law with rotation
  bodies_[ib].state.torque -= c.couple;
  c.force_on_a = force;
  c.tangential_force = f.tangential_force;
  c.sliding = f.sliding;
  contacts_.push_back(c);
}

void RefWorld::evaluate_forces(double spring_dt) {
  const RefEffects& fx = setup_.effects;
  contacts_.clear();
  for (size_t w = 0; w < wall_force_.size(); ++w) {
    wall_force_[w].setZero();
    wall_torque_[w].setZero();
  }
  for (RefBody& b : bodies_) {
    b.state.clear_accumulators();
    if (fx.gravity) add_gravity(b.state, *fx.gravity);
    if (fx.drag_alpha) add_quadratic_drag(b.state, *fx.drag_alpha);
  }
  if (!fx.contacts) {  // the scene names no contact model: bodies pass through each other
    if (!fx.rotation) {
      for (RefBody& b : bodies_) b.state.torque.setZero();
    }
    return;
  }
  // Brute-force broad phase: every pair whose bounding spheres meet.
  std::map<std::pair<long long, long long>, ContactHistory> next_pairs;
  const int n = static_cast<int>(bodies_.size());
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double reach = bodies_[i].bounding_radius + bodies_[j].bounding_radius;
      if ((bodies_[i].state.position - bodies_[j].state.position).norm() > reach) continue;
      pair_contact(i, j, spring_dt, next_pairs);
    }
  }
  std::map<std::pair<long long, int>, ContactHistory> next_walls;
  for (int w = 0; w < static_cast<int>(setup_.walls.size()); ++w) {
    const std::vector<RefTriangle> triangles = wall_triangles(w);
    for (int i = 0; i < n; ++i) wall_contact_of(i, w, triangles, spring_dt, next_walls);
  }
  // Histories of contacts that ended are dropped.
  pair_histories_ = std::move(next_pairs);
  wall_histories_ = std::move(next_walls);
  if (!fx.rotation) {
    for (RefBody& b : bodies_) b.state.torque.setZero();
  }
}

void RefWorld::step() {
  const double dt = setup_.time_step;
  if (!forces_ready_) {
    evaluate_forces(0);  // F_0, T_0 for the first half-step; springs do not grow
    forces_ready_ = true;
  }
  for (RefBody& b : bodies_) begin_step(b.state, dt, setup_.rotation_scheme);
  time_ += dt;
  ++steps_;
  evaluate_forces(dt);
  for (RefBody& b : bodies_) end_step(b.state, dt, setup_.rotation_scheme);
}

void RefWorld::remove_bodies(const std::vector<int>& indices) {
  std::vector<int> renumbered(bodies_.size(), -1);
  std::vector<RefBody> kept;
  std::size_t next = 0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (next < indices.size() && indices[next] == static_cast<int>(i)) {
      ++next;
      continue;
    }
    renumbered[i] = static_cast<int>(kept.size());
    kept.push_back(std::move(bodies_[i]));
  }
  bodies_ = std::move(kept);
  std::vector<RefContact> contacts;
  for (RefContact c : contacts_) {
    if (renumbered[c.body_a] < 0 || (c.body_b >= 0 && renumbered[c.body_b] < 0)) continue;
    c.body_a = renumbered[c.body_a];
    if (c.body_b >= 0) c.body_b = renumbered[c.body_b];
    contacts.push_back(c);
  }
  contacts_ = std::move(contacts);
}

double RefWorld::kinetic_energy() const {
  double e = 0;
  for (const RefBody& b : bodies_) e += b.state.kinetic_energy();
  return e;
}

double RefWorld::contact_elastic_energy() const {
  double e = 0;
  for (const RefContact& c : contacts_) e += c.elastic_energy;
  return e;
}

Eigen::Vector3d RefWorld::momentum() const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (const RefBody& b : bodies_) p += b.state.momentum();
  return p;
}

Eigen::Vector3d RefWorld::angular_momentum() const {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (const RefBody& b : bodies_) {
    l += b.state.position.cross(b.state.momentum()) + b.state.angular_momentum_world();
  }
  return l;
}

double RefWorld::contact_tangential_energy() const {
  double e = 0;
  for (const RefContact& c : contacts_) e += c.tangential_energy;
  return e;
}

const ContactHistory* RefWorld::pair_history(long long id_a, long long id_b) const {
  const auto it = pair_histories_.find(std::minmax(id_a, id_b));
  return it == pair_histories_.end() ? nullptr : &it->second;
}

}  // namespace talus::reference
