// The step assembled from the scene's effects (docs/design.md, "Simulate only the effects a
// scene calls for"): the ordered list of stages that run and the particle arrays they need. An
// effect the scene does not name has no stage and no array; the tests read the plan (and the host
// step's allocations) to show it.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

// A scene asks for something the production step does not provide (yet): the message names the
// scene item and says what to do instead. `talus run` reports it as a setting, exit status 2.
class StepNotSupported : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where the scene wrote effects.contact ("scene.yaml:14:12: effects.contact"), for the step's
// refusals of a contact model; the file and the key for a scene built in code.
inline std::string contact_place(const Scene& scene) {
  return scene.contact_source.line > 0 ? scene.contact_source.where()
                                       : scene.file + ": effects.contact";
}

enum class Stage {
  integrate_begin,  // x_{k+1}, predicted v (and, with rotation, q_{k+1} and predicted w)
  clear_forces,     // forces (and torques) to zero
  gravity,          // m g
  drag,             // -alpha |v| v
  candidate_pairs,  // broad phase: bounding spheres (neighbor/)
  pair_contacts,    // narrow phase, overlap, force laws, tangential history
  wall_contacts,    // particle-wall facets, area weighting
  accumulate,       // contact forces summed per particle in pair order (deterministic)
  integrate_end,    // v_{k+1} (and w_{k+1})
};

constexpr int kStageCount = static_cast<int>(Stage::integrate_end) + 1;

// Wall time per stage (s), indexed by Stage, as both backends keep it.
using StageSeconds = std::array<double, kStageCount>;

const char* to_string(Stage stage);

// The particle arrays a step needs beyond the always-present state (ParticleView).
struct ParticleArrayNeeds {
  bool force = false;             // force, step_start_acceleration
  bool angular_velocity = false;  // rotation
  bool torque = false;            // torque, step_start_torque: rotation with contacts
  bool bounding_radius = false;   // contacts
};

// The names of the per-particle Real arrays of a plan ("position.x", ...), in the order both
// steps allocate them, which is the order of a StepState's arrays: the state (position,
// velocity, orientation), then force and step_start_acceleration, angular_velocity, torque and
// step_start_torque, bounding_radius, each as its needs say.
std::vector<std::string> particle_array_names(const ParticleArrayNeeds& needs);

struct StepPlan {
  bool gravity = false, drag = false, contacts = false, friction = false, rotation = false;
  bool walls = false;
  bool feed = false;          // feeds insert particles between steps (both backends)
  std::vector<Stage> stages;  // in the order they run within one step
  ParticleArrayNeeds arrays;
  bool has(Stage stage) const;
};

// The plan of a scene. Both steps run the scene's feeds before a step's integrate_begin (the
// stages do not name them: a feed changes the particle count, not what a stage does).
StepPlan plan_step(const Scene& scene);

}  // namespace talus
