#include "reference/run/scene_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

#include "solver/io/output_files.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus::reference {

namespace {

Eigen::Vector3d to_eigen(const Vec3d& v) {
  return {v.x, v.y, v.z};
}
Vec3d from_eigen(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
Eigen::Quaterniond to_eigen(const Quatd& q) {
  return Eigen::Quaterniond(q.w, q.x, q.y, q.z);
}

// Scene template index -> index into RefWorldSetup::templates (polyhedra only; -1 for spheres).
std::vector<int> polyhedron_slots(const Scene& scene) {
  std::vector<int> slot(scene.templates.size(), -1);
  int next = 0;
  for (std::size_t t = 0; t < scene.templates.size(); ++t) {
    if (scene.templates[t].kind == ParticleShapeKind::polyhedron) slot[t] = next++;
  }
  return slot;
}

RefBodySpec body_spec(const Scene& scene, const std::vector<int>& slot, const ParticleState& p,
                      long long id) {
  const ParticleTemplate& t = scene.templates.at(p.template_index);
  RefBodySpec spec;
  spec.kind = t.kind;
  spec.shape = slot[p.template_index];
  spec.sphere_radius = t.sphere_radius;
  spec.material = t.material;
  spec.id = id;
  spec.position = to_eigen(p.position);
  spec.orientation = to_eigen(p.orientation).normalized();
  spec.velocity = to_eigen(p.velocity);
  spec.angular_velocity = to_eigen(p.angular_velocity);
  return spec;
}

RefWallMotion wall_motion(const WallMotion& m) {
  RefWallMotion r;
  switch (m.kind) {
    case WallMotion::Kind::none:
      r.kind = RefWallMotion::Kind::kNone;
      break;
    case WallMotion::Kind::rotation:
      r.kind = RefWallMotion::Kind::kRotation;
      r.axis = to_eigen(m.axis).normalized();
      r.point = to_eigen(m.point);
      r.angular_speed = m.angular_speed();
      break;
    case WallMotion::Kind::translation:
      r.kind = RefWallMotion::Kind::kTranslation;
      r.velocity = to_eigen(m.velocity);
      break;
    case WallMotion::Kind::oscillation:
      r.kind = RefWallMotion::Kind::kOscillation;
      r.axis = to_eigen(m.direction).normalized();
      r.amplitude = m.amplitude;
      r.frequency = m.frequency;
      r.start = m.start;
      r.cycles = m.cycles;
      break;
  }
  return r;
}

// The walls' meshes where they are at time t, in the feeder's terms.
std::vector<TriangleMesh> wall_meshes_at(const RefWorld& world) {
  std::vector<TriangleMesh> meshes(world.walls().size());
  for (std::size_t w = 0; w < meshes.size(); ++w) {
    for (const RefTriangle& t : world.wall_triangles(static_cast<int>(w))) {
      const int base = static_cast<int>(meshes[w].vertices.size());
      for (const Eigen::Vector3d& v : t) meshes[w].vertices.push_back(from_eigen(v));
      meshes[w].triangles.push_back({base, base + 1, base + 2});
    }
  }
  return meshes;
}

// The energy probe's ledger (dissipated, wall work, fed) is the production solver's; the
// reference has the energies held (RefWorld: kinetic, contact elastic and tangential) only.
constexpr const char* kNoEnergyProbe =
    "reference solver: the energy probe is not written by the reference solver (its energies "
    "held are RefWorld's kinetic_energy, contact_elastic_energy and contact_tangential_energy)";

std::vector<TrajectoryRow> trajectory_rows(const RefWorld& world,
                                           const std::vector<int>& template_of_body) {
  std::vector<TrajectoryRow> rows;
  rows.reserve(world.bodies().size());
  for (std::size_t i = 0; i < world.bodies().size(); ++i) {
    const RefBody& b = world.bodies()[i];
    TrajectoryRow row;
    row.id = b.id;
    row.template_index = template_of_body.at(i);
    row.position = from_eigen(b.state.position);
    const Eigen::Quaterniond& q = b.state.orientation;
    row.orientation = Quatd(q.w(), q.x(), q.y(), q.z());
    row.velocity = from_eigen(b.state.velocity);
    row.angular_velocity = from_eigen(b.state.angular_velocity_world());
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

RefWorldSetup world_setup(const Scene& scene, std::vector<int>& template_of_body) {
  if (scene.outputs.probes) {
    for (const Probe probe : scene.outputs.probes->quantities) {
      if (probe == Probe::energy) throw std::runtime_error(kNoEnergyProbe);
    }
  }
  RefWorldSetup setup;
  const std::vector<int> slot = polyhedron_slots(scene);
  for (const ParticleTemplate& t : scene.templates) {
    if (t.kind == ParticleShapeKind::polyhedron) setup.templates.push_back(t.shape);
  }
  for (const Material& m : scene.materials) {
    setup.materials.push_back(
        {m.name, m.density, m.youngs_modulus, m.poisson_ratio, m.friction, m.restitution});
  }
  setup.pair_rule = [&scene](int a, int b) {
    return PairProperties{scene.pair_friction(a, b), scene.pair_restitution(a, b)};
  };
  // The rule reads the scene by reference: the scene outlives the world in run_scene; callers of
  // world_setup that keep the setup longer than the scene must replace it.

  const std::vector<ParticleState> particles = initial_particles(scene);
  template_of_body.clear();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    setup.bodies.push_back(body_spec(scene, slot, particles[i], static_cast<long long>(i)));
    template_of_body.push_back(particles[i].template_index);
  }

  const std::vector<WallMesh> meshes = make_wall_meshes(scene);
  for (std::size_t w = 0; w < scene.walls.size(); ++w) {
    RefWall wall;
    wall.name = scene.walls[w].name;
    wall.material = scene.walls[w].material;
    wall.motion = wall_motion(scene.walls[w].motion);
    const TriangleMesh& mesh = meshes[w].mesh;
    for (const auto& tri : mesh.triangles) {
      wall.triangles.push_back({to_eigen(mesh.vertices[tri[0]]), to_eigen(mesh.vertices[tri[1]]),
                                to_eigen(mesh.vertices[tri[2]])});
    }
    setup.walls.push_back(std::move(wall));
  }

  const Effects& fx = scene.effects;
  if (fx.gravity) setup.effects.gravity = to_eigen(*fx.gravity);
  setup.effects.contacts = fx.contact.has_value();
  // volume (the default law), volume_paper (Eqs. 12-13) or linear, each with its own normal
  // damping (effects.damping unset; reference/contact/force_law.hpp).
  if (fx.contact) setup.effects.contact = *fx.contact;
  setup.effects.linear = fx.linear;
  setup.effects.friction = fx.friction;
  setup.effects.rotation = fx.rotation;
  setup.effects.drag_alpha = fx.drag_alpha;
  setup.time_step = scene.time_step;
  return setup;
}

double bed_height(const RefWorld& world, const Eigen::Vector3d& gravity) {
  const double g = gravity.norm();
  if (!(g > 0)) throw std::invalid_argument("bed_height needs a non-zero gravity");
  const Eigen::Vector3d up = -gravity / g;
  double highest = 0;
  bool any = false;
  for (const RefBody& b : world.bodies()) {
    double top;
    if (b.kind == ParticleShapeKind::sphere) {
      top = up.dot(b.state.position) + b.sphere_radius;
    } else {
      const Eigen::Matrix3d rotation = b.state.rotation();
      top = -HUGE_VAL;
      for (const Vec3d& v : world.shape(b.shape).vertices) {
        top = std::max(top, up.dot(b.state.position + rotation * to_eigen(v)));
      }
    }
    highest = any ? std::max(highest, top) : top;
    any = true;
  }
  return highest;
}

std::vector<double> probe_values(const Scene& scene, const RefWorld& world) {
  std::vector<double> values;
  if (!scene.outputs.probes) return values;
  for (const Probe probe : scene.outputs.probes->quantities) {
    switch (probe) {
      case Probe::kinetic_energy:
        values.push_back(world.kinetic_energy());
        break;
      case Probe::contact_count: {
        long long pairs = 0;
        for (const RefContact& c : world.contacts()) pairs += c.wall < 0 ? 1 : 0;
        values.push_back(static_cast<double>(pairs));
        break;
      }
      case Probe::bed_height:
        values.push_back(bed_height(world, to_eigen(*scene.effects.gravity)));
        break;
      case Probe::wall_forces:
        for (std::size_t w = 0; w < world.walls().size(); ++w) {
          // RefWorld gives the torque about the motion's point; the file wants it about the
          // origin: T_o = T_p + p x F.
          const Eigen::Vector3d& f = world.wall_force(static_cast<int>(w));
          const Eigen::Vector3d t =
              world.wall_torque(static_cast<int>(w)) + world.walls()[w].motion.point.cross(f);
          values.insert(values.end(), {f.x(), f.y(), f.z(), t.x(), t.y(), t.z()});
        }
        break;
      case Probe::energy:
        throw std::runtime_error(kNoEnergyProbe);  // world_setup refuses it first
    }
  }
  return values;
}

namespace {

double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

SceneRunner::SceneRunner(const Scene& scene, SceneRunSettings settings)
    : scene_(scene),
      settings_(std::move(settings)),
      world_(world_setup(scene, template_of_body_)),
      polyhedron_slot_(polyhedron_slots(scene)) {
  started_ = last_progress_ = clock_seconds();
  // The output root is this run's while it lasts (solver/io/run_directory.hpp).
  lock_ = claim_output_root(scene, settings_.output_root, new_run_id(), false, settings_.overwrite);
  for (std::size_t f = 0; f < scene.feeds.size(); ++f) {
    feeders_.emplace_back(scene, static_cast<int>(f));
  }
  next_id_ = static_cast<long long>(world_.bodies().size());
  const std::vector<WallMesh> meshes = make_wall_meshes(scene);
  for (const WallMesh& mesh : meshes) plate_triangles_.push_back(mesh.plate_triangles);
  total_steps_ = scene_step_count(scene);  // at most kMaxSteps (the loader refused more)

  outputs_ = std::make_unique<OutputSchedule>(scene, settings_.output_root, "reference",
                                              world_.bodies().size());
  // Step 0's outputs need the forces at t = 0 (contacts, wall forces).
  world_.evaluate_forces(0.0);
  write_outputs(done());
}

SceneRunner::~SceneRunner() = default;

void SceneRunner::write_outputs(bool last) {
  // The schedule's view of the world (solver/io/output_schedule.hpp).
  struct Source : OutputSource {
    const SceneRunner& r;
    explicit Source(const SceneRunner& runner) : r(runner) {}
    double time() const override { return r.world_.time(); }
    std::vector<TrajectoryRow> rows() const override {
      return trajectory_rows(r.world_, r.template_of_body_);
    }
    std::vector<double> probe_values() const override {
      return talus::reference::probe_values(r.scene_, r.world_);
    }
  };
  outputs_->write(step_, last, Source(*this));
}

void SceneRunner::report_progress() {
  if (!settings_.progress) return;
  SceneRunProgress p;
  p.step = step_;
  p.total_steps = total_steps_;
  p.time = world_.time();
  p.end_time = scene_.end_time;
  p.particles = world_.bodies().size();
  p.contacts = world_.contacts().size();
  p.wall_seconds = clock_seconds() - started_;
  settings_.progress(p);
}

void SceneRunner::advance() {
  if (done()) return;
  const double t = world_.time();
  for (std::size_t w = 0; w < scene_.walls.size(); ++w) {
    if (plate_triangles_[w] > 0 && !outlet_closed_at(scene_.walls[w], t)) {
      world_.remove_last_wall_triangles(static_cast<int>(w), plate_triangles_[w]);
      plate_triangles_[w] = 0;
    }
  }
  if (!feeders_.empty()) {
    std::vector<Vec3d> positions;
    std::vector<double> radii;
    for (const RefBody& b : world_.bodies()) {
      positions.push_back(from_eigen(b.state.position));
      radii.push_back(b.bounding_radius);
    }
    const std::vector<TriangleMesh> walls_now = wall_meshes_at(world_);
    for (Feeder& feeder : feeders_) {
      for (const ParticleState& p : feeder.insert(t, positions, radii, walls_now)) {
        world_.add_body(body_spec(scene_, polyhedron_slot_, p, next_id_++));
        template_of_body_.push_back(p.template_index);
        positions.push_back(p.position);
        radii.push_back(world_.bodies().back().bounding_radius);
      }
    }
  }
  world_.step();
  if (scene_.domain) {  // the bodies whose centroid left the domain box, as the production step
    std::vector<int> outside;
    for (std::size_t i = 0; i < world_.bodies().size(); ++i) {
      const Vec3d x = from_eigen(world_.bodies()[i].state.position);
      if (!scene_.domain->contains(x) && std::isfinite(x.x + x.y + x.z))
        outside.push_back(static_cast<int>(i));
    }
    if (!outside.empty()) {
      world_.remove_bodies(outside);
      for (auto at = outside.rbegin(); at != outside.rend(); ++at)
        template_of_body_.erase(template_of_body_.begin() + *at);
    }
  }
  ++step_;
  contacts_sum_ += static_cast<double>(world_.contacts().size());
  write_outputs(done());
  const double now = clock_seconds();
  if (now - last_progress_ >= settings_.progress_interval) {
    report_progress();
    last_progress_ = now;
  }
}

SceneRunReport SceneRunner::report() const {
  SceneRunReport report;
  report.steps = step_;
  report.simulated_time = world_.time();
  report.wall_seconds = clock_seconds() - started_;
  report.particles = world_.bodies().size();
  report.mean_contacts = step_ > 0 ? contacts_sum_ / static_cast<double>(step_) : 0;
  report.outputs = outputs_->paths();
  return report;
}

SceneRunReport run_scene(const Scene& scene, const SceneRunSettings& settings) {
  SceneRunner runner(scene, settings);
  while (!runner.done()) runner.advance();
  runner.report_progress();
  return runner.report();
}

}  // namespace talus::reference
