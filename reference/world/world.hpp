// The reference world: particles (polyhedra or spheres), walls, effects and the serial step
// (brute-force broad phase, exact contacts, the force laws of contact/, body forces and the
// integrators of dynamics/). Built from plain lists, so that a scene loader can fill it. The
// contact model is the scene's: the default volume law, the paper's (Eqs. 12-22) or BLAZE-DEM's
// linear law (contact/force_law.hpp says which is which).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "reference/contact/force_law.hpp"
#include "reference/dynamics/integrator.hpp"
#include "reference/dynamics/rigid_body.hpp"
#include "reference/world/wall.hpp"
#include "solver/scene/scene.hpp"
#include "solver/shape/shape.hpp"

namespace talus::reference {

struct RefMaterial {
  std::string name;
  double density = 0;         // kg/m^3
  double youngs_modulus = 0;  // E, Pa (Eqs. 13, 19)
  double poisson_ratio = 0;   // nu (Eq. 19)
  double friction = 0;        // mu (Eq. 17)
  double restitution = 1;     // epsilon (Eqs. 15, 20)
};

struct PairProperties {
  double friction = 0;
  double restitution = 1;
};
// Friction and restitution of a contact between materials a and b (indices; a wall's material
// too). Default: the material's own values when a = b, else the mean of the two (the scene's
// rule without overrides, docs/scenes.md).
using PairRule = std::function<PairProperties(int material_a, int material_b)>;

struct RefBodySpec {
  ParticleShapeKind kind = ParticleShapeKind::polyhedron;
  int shape = -1;            // polyhedron: index into the templates
  double sphere_radius = 0;  // sphere, m
  int material = -1;         // index into the materials
  long long id = 0;          // global id (keys the tangential histories); unique
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // centroid, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body -> world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();               // m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();       // rad/s, WORLD frame
};

struct RefEffects {
  std::optional<Eigen::Vector3d> gravity;  // m/s^2
  bool contacts = true;  // false: no contact model, bodies and walls pass through each other
  // volume: the default volume law; volume_paper: the paper's Eqs. 12-13; linear: BLAZE-DEM
  // (contact/force_law.hpp).
  ContactModel contact = ContactModel::volume;
  LinearContactParameters linear;  // K_N, eta, gamma (linear model)
  bool friction = false;
  bool rotation = true;
  std::optional<double> drag_alpha;  // kg/m
  // The normal damping of the volume laws (force_law.hpp); unset: the law's own, Eq. 15's form
  // on k_n (kPaper) for volume, kCalibrated for volume_paper. volume refuses kCalibrated (it is
  // calibrated on the paper's potential).
  std::optional<NormalDamping> damping;
};

struct RefWorldSetup {
  std::vector<ShapeTemplate> templates;
  std::vector<RefMaterial> materials;
  std::vector<RefBodySpec> bodies;
  std::vector<RefWall> walls;
  RefEffects effects;
  double time_step = 0;  // s
  RotationScheme rotation_scheme = RotationScheme::kImplicitMidpoint;
  PairRule pair_rule;  // empty: the default rule above
};

struct RefBody {
  RigidBody state;
  ParticleShapeKind kind = ParticleShapeKind::polyhedron;
  int shape = -1;
  double sphere_radius = 0;
  double bounding_radius = 0;    // m, about the centroid (broad phase)
  double equivalent_radius = 0;  // R of Eq. 13: the sphere of equal volume, m
  int material = -1;
  long long id = 0;
};

// One contact of the last force evaluation. Pairs: body_a < body_b, wall = -1. Walls: body_a is
// the particle, body_b = -1. The normal points from the particle A into B (or the wall).
struct RefContact {
  int body_a = -1, body_b = -1, wall = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_on_a = Eigen::Vector3d::Zero();  // N (normal + tangential)
  Eigen::Vector3d tangential_force = Eigen::Vector3d::Zero();
  // N m: the torque on A besides (point - x_A) x force_on_a (B or the wall gets its opposite),
  // with rotation: for the default volume law the patch couple (force_law.hpp) and, between
  // particles, U(V)'s couple -p M (PairGeometry::moment); at walls also the facets' forces at
  // their own points, sum (x_i - point) x F_i. Zero without rotation.
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();
  double volume = 0;  // dV (volume laws; walls: sum of w_i dV_i), m^3
  double area = 0;    // A_n (volume laws; walls: sum of w_i A_i), m^2
  double depth = 0;   // delta (linear model; walls: the deepest facet's), m
  double weight = 1;  // walls: sum of the facets' area weights
  // J: the potential of the elastic normal force (volume laws: U(V), walls sum_i w_i U(V_i);
  // linear: K_N delta^2 / 2), and the springs' energy after this step: the tangential spring's
  // |F_t^e|^2 / (2 k_t) (volume laws with friction) plus the rocking spring's |M_e|^2 / (2 k_r)
  // (the default law with rotation; force_law.hpp).
  double elastic_energy = 0;
  double tangential_energy = 0;
  bool sliding = false;
};

class RefWorld {
 public:
  // Checks the setup (indices, positive sizes and materials, unique ids, supported combinations)
  // and throws std::invalid_argument naming what is wrong.
  explicit RefWorld(RefWorldSetup setup);

  // One step of dt: integration (dynamics/integrator.hpp) around one force evaluation.
  void step();
  void run(long long steps) {
    for (long long k = 0; k < steps; ++k) step();
  }

  // A body added between steps (a feed): checked like the setup's bodies; its body forces are
  // accumulated at once so that its first step starts from them. Throws std::invalid_argument.
  void add_body(const RefBodySpec& spec);
  // Drops the last `count` triangles of wall w (a closed outlet's plate that opens).
  void remove_last_wall_triangles(int w, int count);
  // Removes the bodies at the given indices (ascending), between steps: the others keep their
  // order, the last evaluation's contacts of removed bodies are dropped and the rest renumbered;
  // histories are keyed by global ids, so the kept bodies keep theirs.
  void remove_bodies(const std::vector<int>& indices);
  const ShapeTemplate& shape(int index) const { return setup_.templates.at(index); }

  double time() const { return time_; }
  long long steps() const { return steps_; }
  double time_step() const { return setup_.time_step; }
  const std::vector<RefBody>& bodies() const { return bodies_; }
  std::vector<RefBody>& bodies() { return bodies_; }  // to edit states between steps
  const std::vector<RefContact>& contacts() const { return contacts_; }
  const std::vector<RefWall>& walls() const { return setup_.walls; }
  // Total contact force and torque on wall w at the last force evaluation: minus what the wall's
  // contacts gave the particles (the patch couples included); the torque about the wall motion's
  // `point`.
  const Eigen::Vector3d& wall_force(int w) const { return wall_force_.at(w); }
  const Eigen::Vector3d& wall_torque(int w) const { return wall_torque_.at(w); }
  // Wall w's triangles at the current time.
  std::vector<RefTriangle> wall_triangles(int w) const;

  double kinetic_energy() const;             // J, translation + rotation
  double contact_elastic_energy() const;     // J, elastic_energy over the last contacts
  double contact_tangential_energy() const;  // J, tangential_energy over the last contacts
  Eigen::Vector3d momentum() const;          // kg m/s
  Eigen::Vector3d angular_momentum() const;  // about the origin, kg m^2/s
  const ContactHistory* pair_history(long long id_a, long long id_b) const;
  size_t history_count() const { return pair_histories_.size() + wall_histories_.size(); }

  // The force evaluation alone (used by step; public for tests and benchmarks): clears the
  // accumulators, adds body forces and contacts at the current state, records the contacts.
  // `spring_dt` is the time the tangential springs advance by (0: they do not grow).
  void evaluate_forces(double spring_dt);

 private:
  void pair_contact(int i, int j, double spring_dt,
                    std::map<std::pair<long long, long long>, ContactHistory>& next);
  void wall_contact_of(int i, int w, const std::vector<RefTriangle>& triangles, double spring_dt,
                       std::map<std::pair<long long, int>, ContactHistory>& next);
  void sphere_wall_contact(int i, int w, const std::vector<RefTriangle>& triangles);
  void add_body_unchecked(const RefBodySpec& spec);  // checks the body alone
  void apply(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force);
  Eigen::Vector3d point_velocity(int body, const Eigen::Vector3d& point) const;
  PairProperties pair_properties(int material_a, int material_b) const;
  // The linear model's parameters (BLAZE-DEM Eqs. 2-3) for a pair or a wall contact.
  LinearLawParameters linear_law(const PairProperties& props) const;
  // A volume law's normal law and parameters (damping, step limit, friction) for a contact.
  VolumeLaw volume_law() const;
  VolumeLawParameters volume_parameters(const PairProperties& props, double effective_mass) const;

  RefWorldSetup setup_;
  std::vector<RefBody> bodies_;
  std::vector<RefContact> contacts_;
  std::vector<Eigen::Vector3d> wall_force_, wall_torque_;
  std::map<std::pair<long long, long long>, ContactHistory> pair_histories_;
  std::map<std::pair<long long, int>, ContactHistory> wall_histories_;
  std::set<long long> ids_;
  double time_ = 0;
  long long steps_ = 0;
  bool forces_ready_ = false;
};

}  // namespace talus::reference
