// `talus run [options] scene.yaml`: loads the scene and runs it with the chosen solver. The
// reference solver is linked in where CMake found CGAL and Eigen (TALUS_HAVE_REFERENCE); the
// production solver's step arrives with issue 4.
#include <cstdio>
#include <stdexcept>
#include <string>

#include "solver/app/commands.hpp"
#include "solver/app/json_writer.hpp"
#include "solver/app/run_arguments.hpp"
#include "solver/scene/scene_loader.hpp"

#if TALUS_HAVE_REFERENCE
#include "reference/run/scene_run.hpp"
#endif

namespace talus {

namespace {

#if TALUS_HAVE_REFERENCE
void print_progress(const reference::SceneRunProgress& p) {
  const double fraction = p.total_steps > 0 ? double(p.step) / double(p.total_steps) : 1.0;
  const double left = fraction > 0 ? p.wall_seconds * (1 - fraction) / fraction : 0;
  std::fprintf(stderr,
               "talus run: %5.1f%%  t = %.6g of %.6g s  step %lld of %lld  %.3g steps/s  "
               "%zu particles  %zu contacts  about %.0f s left\n",
               100 * fraction, p.time, p.end_time, p.step, p.total_steps,
               p.wall_seconds > 0 ? double(p.step) / p.wall_seconds : 0.0, p.particles, p.contacts,
               left);
}
#endif

}  // namespace

std::string run_json(const RunArguments& args) {
  Scene scene = load_scene(args.scene_path);  // SceneError: file:line:column: key: message
  if (args.backend) scene.backend = *args.backend;
  if (args.precision) scene.precision = *args.precision;

  if (args.solver == SolverKind::production) {
    throw RunError(
        "the production solver's time step is not built yet (issue 4); run this scene with the "
        "reference solver: talus run --solver reference " +
        args.scene_path);
  }
#if TALUS_HAVE_REFERENCE
  if (scene.precision != Precision::float64) {
    throw RunError(
        "--solver reference computes in double only; drop --precision float or set "
        "precision: double in " +
        args.scene_path);
  }
  reference::SceneRunSettings settings;
  settings.output_root = args.output_root;
  if (!args.quiet) settings.progress = print_progress;
  const reference::SceneRunReport report = reference::run_scene(scene, settings);
  JsonWriter json;
  json.begin_object();
  json.member("solver", "reference");
  json.member("scene", args.scene_path);
  json.member("steps", static_cast<double>(report.steps));
  json.member("simulated_time", report.simulated_time);
  json.member("wall_seconds", report.wall_seconds);
  json.member("particles", static_cast<int>(report.particles));
  json.member("mean_contacts_per_step", report.mean_contacts);
  json.key("outputs");
  json.begin_array(JsonWriter::Layout::multi_line);
  for (const std::string& output : report.outputs) json.value(output);
  json.end_array();
  json.end_object();
  return json.str();
#else
  throw RunError(
      "this talus was built without the reference solver (CMake did not find CGAL and "
      "Eigen; scripts/setup installs them)");
#endif
}

}  // namespace talus
