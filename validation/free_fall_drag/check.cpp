// BLAZE-DEM §5.1: one sphere falling from rest under gravity and quadratic drag; its speed and
// drop against the closed forms every 0.1 s, at the paper's two time steps, on the production
// solver and, where talus is built with it, the reference solver. README.md here.
#include <cmath>

#include <fmt/format.h>

#include "solver/io/output_files.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The scene run to its end time at step dt by the production solver (`reference` false: the
// chosen backend) or the reference solver, sampled every 0.1 s: speed and drop against
// v(t) = v_t tanh(g t / v_t) and x(t) = (v_t^2 / g) ln cosh(g t / v_t).
void fall(const CaseContext& context, CaseResult& result, double dt, const std::string& suffix,
          bool reference) {
  const Scene scene =
      load_case_scene(joined_path(context.case_directory, "scene.yaml"), result, dt);
  const ExpectedQuantity& speed_q = context.expected.quantity("speed" + suffix);
  const ExpectedQuantity& drop_q = context.expected.quantity("drop" + suffix);
  const double g = std::abs(scene.effects.gravity.value().z);
  const ParticleTemplate& ball = scene.templates.at(scene.particles.at(0).template_index);
  const double mass =
      scene.materials.at(ball.material).density * 4.0 / 3.0 * kPi * std::pow(ball.sphere_radius, 3);
  const double alpha = scene.effects.drag_alpha.value();
  const double v_t = std::sqrt(mass * g / alpha);  // terminal speed
  const double z0 = scene.particles.at(0).position.z;
  const long long steps = std::llround(scene.end_time / dt);
  const long long every = std::llround(0.1 / dt);
  const char* solver = reference ? "reference" : "production";
  const auto sample = [&](long long k, const std::vector<TrajectoryRow>& rows) {
    const double t = double(k) * dt;
    const TrajectoryRow& row = rows.at(0);
    add_check(result, speed_q, t, -row.velocity.z, v_t * std::tanh(g * t / v_t), solver);
    add_check(result, drop_q, t, z0 - row.position.z,
              v_t * v_t / g * std::log(std::cosh(g * t / v_t)), solver);
  };
  if (reference) {
    context.run_reference(scene, steps, every, sample);
  } else {
    std::unique_ptr<AnyStep> step = context.make_step(scene);
    for (long long k = 1; k <= steps; ++k) {
      step->step();
      if (k % every == 0) sample(k, step->rows());
    }
  }
  result.notes.push_back(fmt::format(
      "dt {} s: {} steps of the {} solver{}; m = {:.4g} kg, alpha = {} kg/m, v_t = {:.4g} m/s", dt,
      steps, solver, reference ? "" : " on the " + context.backend + " backend", mass, alpha, v_t));
}

void run_case(const CaseContext& context, CaseResult& result) {
  for (bool reference : {false, true}) {
    if (reference && !context.run_reference) {
      result.notes.push_back(
          "the reference solver is not built into this talus (it needs CGAL "
          "and Eigen): its runs are left out");
      continue;
    }
    fall(context, result, 1e-3, "_dt1e-3", reference);
    if (context.full) fall(context, result, 1e-4, "_dt1e-4", reference);
  }
}

}  // namespace

extern const ValidationCase kFreeFallDrag{
    "free_fall_drag",
    "Free fall with quadratic drag (BLAZE-DEM section 5.1)",
    {"speed_dt1e-3", "drop_dt1e-3", "speed_dt1e-4", "drop_dt1e-4"},
    run_case};

}  // namespace talus::validation
