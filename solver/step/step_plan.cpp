#include "solver/step/step_plan.hpp"

#include <algorithm>

namespace talus {

const char* to_string(Stage stage) {
  switch (stage) {
    case Stage::integrate_begin:
      return "integrate_begin";
    case Stage::clear_forces:
      return "clear_forces";
    case Stage::gravity:
      return "gravity";
    case Stage::drag:
      return "drag";
    case Stage::candidate_pairs:
      return "candidate_pairs";
    case Stage::pair_contacts:
      return "pair_contacts";
    case Stage::wall_contacts:
      return "wall_contacts";
    case Stage::accumulate:
      return "accumulate";
    case Stage::integrate_end:
      return "integrate_end";
  }
  return "?";
}

bool StepPlan::has(Stage stage) const {
  return std::find(stages.begin(), stages.end(), stage) != stages.end();
}

StepPlan plan_step(const Scene& scene) {
  const Effects& fx = scene.effects;
  StepPlan plan;
  plan.feed = !scene.feeds.empty();
  plan.gravity = fx.gravity.has_value();
  plan.drag = fx.drag_alpha.has_value();
  plan.contacts = fx.contact.has_value();
  plan.friction = plan.contacts && fx.friction;
  plan.rotation = fx.rotation;
  plan.walls = plan.contacts && !scene.walls.empty();  // without a contact model walls are inert

  const bool any_force = plan.gravity || plan.drag || plan.contacts;
  plan.stages.push_back(Stage::integrate_begin);
  if (any_force) plan.stages.push_back(Stage::clear_forces);
  if (plan.gravity) plan.stages.push_back(Stage::gravity);
  if (plan.drag) plan.stages.push_back(Stage::drag);
  if (plan.contacts) {
    plan.stages.push_back(Stage::candidate_pairs);
    plan.stages.push_back(Stage::pair_contacts);
    if (plan.walls) plan.stages.push_back(Stage::wall_contacts);
    plan.stages.push_back(Stage::accumulate);
  }
  plan.stages.push_back(Stage::integrate_end);

  plan.arrays.force = any_force;
  plan.arrays.angular_velocity = plan.rotation;
  plan.arrays.torque = plan.rotation && plan.contacts;
  plan.arrays.bounding_radius = plan.contacts;
  return plan;
}

std::vector<std::string> particle_array_names(const ParticleArrayNeeds& needs) {
  std::vector<std::string> names;
  const auto soa3 = [&](const std::string& name) {
    for (const char* axis : {".x", ".y", ".z"}) names.push_back(name + axis);
  };
  soa3("position");
  soa3("velocity");
  for (const char* part : {"orientation.w", "orientation.x", "orientation.y", "orientation.z"})
    names.push_back(part);
  if (needs.force) {
    soa3("force");
    soa3("step_start_acceleration");
  }
  if (needs.angular_velocity) soa3("angular_velocity");
  if (needs.torque) {
    soa3("torque");
    soa3("step_start_torque");
  }
  if (needs.bounding_radius) names.push_back("bounding_radius");
  return names;
}

}  // namespace talus
