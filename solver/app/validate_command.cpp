// `talus validate`: the validation cases (validation/README.md) on the production solver.
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "solver/app/commands.hpp"
#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"
#include "solver/run/any_step.hpp"
#include "validation/framework/validation.hpp"

#if TALUS_HAVE_REFERENCE
#include "reference/run/scene_run.hpp"
#include "reference/world/world.hpp"
#endif
#if TALUS_HAVE_CUDA
#include "solver/core/cuda_device.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#endif

namespace talus {

std::string first_line_of(const std::string& command) {
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return "";
  char buffer[256] = {};
  std::string line;
  if (std::fgets(buffer, sizeof buffer, pipe)) line = buffer;
  const int status = ::pclose(pipe);
  if (status != 0) return "";
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return line;
}

StepFactory step_factory(Backend backend, std::string& name) {
  name = "cpu";
#if TALUS_HAVE_CUDA
  std::string why;
  if (backend != Backend::cpu && cuda_device_available(&why)) {
    name = "cuda";
    return make_cuda_step;
  }
  if (backend == Backend::cuda) throw RunError("--backend cuda: " + why);
#else
  if (backend == Backend::cuda)
    throw RunError("--backend cuda: this talus was built without the CUDA backend");
#endif
  return [](const Scene& scene) { return make_host_step(scene); };
}

std::string commit_of(const std::string& source) {
  if (const char* given = std::getenv("TALUS_COMMIT"); given && *given) return given;
  const std::string git = "git -C '" + source + "' ";
  const std::string head = first_line_of(git + "rev-parse --short=12 HEAD 2>/dev/null");
  if (head.empty()) return "unknown";
  const std::string changes =
      first_line_of(git + "status --porcelain --untracked-files=no 2>/dev/null | head -1");
  return changes.empty() ? head : head + "-dirty";
}

namespace {

// A Python with matplotlib for the figures: Debian's (scripts/setup installs it), else the
// python3 on PATH (the GPU machine's); "" without.
std::string figure_python() {
  for (const std::string& python : {std::string("/usr/bin/python3"), std::string("python3")}) {
    if (python[0] == '/' && !input_file_problem(python).empty()) continue;
    if (std::system((python + " -c 'import matplotlib' > /dev/null 2>&1").c_str()) == 0)
      return python;
  }
  return "";
}

#if TALUS_HAVE_REFERENCE
// The reference solver's world of the scene, stepped, its particles sampled as trajectory rows.
void run_reference(
    const Scene& scene, long long steps, long long every,
    const std::function<void(long long, const std::vector<TrajectoryRow>&)>& sample) {
  std::vector<int> template_of_body;
  reference::RefWorld world(reference::world_setup(scene, template_of_body));
  for (long long k = 1; k <= steps; ++k) {
    world.step();
    if (k % every != 0) continue;
    std::vector<TrajectoryRow> rows;
    for (std::size_t b = 0; b < world.bodies().size(); ++b) {
      const reference::RefBody& body = world.bodies()[b];
      const Eigen::Vector3d& x = body.state.position;
      const Eigen::Vector3d& v = body.state.velocity;
      const Eigen::Vector3d w = body.state.angular_velocity_world();
      const Eigen::Quaterniond& q = body.state.orientation;
      TrajectoryRow row;
      row.id = body.id;
      row.template_index = template_of_body.at(b);
      row.position = {x.x(), x.y(), x.z()};
      row.orientation = {q.w(), q.x(), q.y(), q.z()};
      row.velocity = {v.x(), v.y(), v.z()};
      row.angular_velocity = {w.x(), w.y(), w.z()};
      rows.push_back(row);
    }
    sample(k, rows);
  }
}
#endif

}  // namespace

std::string validate_json(const ValidateArguments& args, bool& passed) {
  validation::ValidationOptions options;
  options.cases = args.cases;
  options.full = args.full;
  options.quiet = args.quiet;
  options.output_directory = args.output;
  const std::string source = TALUS_SOURCE_DIR;
  options.cases_directory =
      args.cases_directory.empty() ? joined_path(source, "validation") : args.cases_directory;
  options.commit = commit_of(source);
  options.make_step = step_factory(args.backend, options.backend);
#if TALUS_HAVE_REFERENCE
  options.run_reference = run_reference;
#endif
  options.python = figure_python();
  if (!args.quiet) {
    fmt::print(stderr, "talus validate: {} versions on the {} backend, commit {}, into {}/{}\n",
               args.full ? "full" : "small", options.backend, options.commit,
               options.output_directory,
               options.python.empty() ? "; no figures (no python3 with matplotlib)" : "");
  }
  const validation::ValidationRun run = validation::run_validation(options);
  passed = run.passed();
  if (!args.quiet) {
    fmt::print(stderr, "talus validate: {}; {} and {}\n",
               passed ? "every case passed" : "SOME CASE FAILED", run.results_file,
               run.summary_file);
  }
  return validation::results_json(run, options);
}

}  // namespace talus
