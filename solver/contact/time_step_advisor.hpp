// The time-step advisor (host, double): the largest stable explicit step of a scene, from its
// contact law's largest stiffness at the loads the contacts will carry, the particles' masses and
// moments, and the materials (docs/contact.md, "Time step"). `talus run` prints dt / dt_crit and
// refuses a step above dt_crit; `time: {step: auto}` takes recommended_step.
#pragma once

#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

// What the advisor reads of one particle template.
struct TemplateProperties {
  double mass = 0;               // kg
  double smallest_moment = 0;    // I_min, kg m^2 (principal, about the centroid)
  double bounding_radius = 0;    // R_b, m: the largest lever arm of a contact point
  double equivalent_radius = 0;  // R, m: the sphere of equal volume (paper Eq. 13)
  double largest_face_area = 0;  // A_face, m^2 (a sphere: pi r^2)
  double youngs_modulus = 0;     // E, Pa
  double poisson_ratio = 0;      // nu
  double density = 0;            // kg/m^3
};
TemplateProperties template_properties(const Scene& scene, int template_index);

// T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu)): the time a Rayleigh
// wave takes to cross a sphere of radius R (the usual Hertzian DEM step bound; reported only).
double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio);

// One kind of contact that can occur: two templates, or a template and a wall.
struct ContactKindAdvice {
  std::string name;  // "cube-cube", "cube-wall 'floor'"
  int template_a = -1;
  int template_b = -1;              // -1: a wall
  int wall = -1;                    // index into Scene::walls, or -1
  double normal_stiffness = 0;      // k_n at the contact's stiffest state, N/m
  double tangential_stiffness = 0;  // k_t, N/m (0: no tangential spring)
  double load = 0;                  // N: the force k_n is evaluated at (volume_paper only)
  double stiffness = 0;             // k of the limiting mode (normal or tangential), N/m
  double inverse_mass = 0;          // of that mode along the contact, 1/kg
  double omega = 0;                 // sqrt(k * inverse_mass), rad/s
  double damping_ratio = 0;         // zeta of that mode
  double critical_step = 0;         // s
};

struct TimeStepAdvice {
  double critical_step = 0;     // dt_crit, s; +infinity when nothing limits it
  double rayleigh_time = 0;     // s, the smallest over the templates present; +inf without any
  double recommended_step = 0;  // what `step: auto` takes: kAutoStepFraction dt_crit
  // What limits dt_crit ("cube-cube contacts"), or why nothing does ("no contacts:
  // effects.contact is absent").
  std::string limit;
  std::string model;  // the contact law as written in scenes ("volume"); empty without one
  std::vector<ContactKindAdvice> kinds;
  int limiting_kind = -1;  // index into kinds, -1 when nothing limits
  bool limited() const { return limiting_kind >= 0; }
  // "cube-cube contacts, contact: volume"
  std::string describe() const;
};

// The fraction of dt_crit that `step: auto` takes (why 0.2: time_step_advisor.cpp).
constexpr double kAutoStepFraction = 0.2;

// The advice for a loaded scene (templates built, effects and particles read; scene.time_step
// is not read).
TimeStepAdvice advise_time_step(const Scene& scene);

// A SceneError at the scene's time.step when scene.time_step is above advice.critical_step, naming
// the largest stable step (rounded down) and how to get it; nothing otherwise. `talus run`
// (without --allow-unstable-step) and the validation cases refuse a scene through it.
void refuse_unstable_step(const Scene& scene, const TimeStepAdvice& advice);

// `value` rounded down to two significant digits (2.149e-9 -> 2.1e-9): a step we may print as
// stable. Infinity and 0 stay as they are.
double round_down_two_digits(double value);

}  // namespace talus
