#include "solver/app/run_arguments.hpp"

#include "solver/app/arguments.hpp"

#include <cmath>
#include <cstdlib>

namespace talus {

const char* to_string(SolverKind solver) {
  return solver == SolverKind::reference ? "reference" : "production";
}

RunArguments parse_run_arguments(const std::vector<std::string>& operands) {
  static const std::pair<const char*, SolverKind> kSolvers[] = {
      {"production", SolverKind::production}, {"reference", SolverKind::reference}};
  static const std::pair<const char*, Backend> kBackends[] = {
      {"auto", Backend::automatic}, {"cpu", Backend::cpu}, {"cuda", Backend::cuda}};
  static const std::pair<const char*, Precision> kPrecisions[] = {{"double", Precision::float64},
                                                                  {"float", Precision::float32}};

  RunArguments parsed;
  bool have_scene = false;
  std::vector<std::string> fixed_by_checkpoint;  // options --resume does not take
  for (std::size_t i = 0; i < operands.size(); ++i) {
    const std::string& word = operands[i];
    if (word == "--quiet") {
      parsed.quiet = true;
      continue;
    }
    if (word == "--allow-unstable-step") {
      parsed.allow_unstable_step = true;
      continue;
    }
    if (word.rfind("--", 0) != 0) {
      if (have_scene) {
        throw UsageError("run expects one scene file, got '" + parsed.scene_path + "' and '" +
                         word + "'");
      }
      parsed.scene_path = word;
      have_scene = true;
      continue;
    }
    // --name value or --name=value
    std::string name = word, value;
    const std::size_t equals = word.find('=');
    if (equals != std::string::npos) {
      name = word.substr(0, equals);
      value = word.substr(equals + 1);
    } else if (name == "--solver" || name == "--backend" || name == "--precision" ||
               name == "--output" || name == "--threads" || name == "--end" || name == "--resume") {
      if (i + 1 >= operands.size()) throw UsageError(name + " expects a value");
      value = operands[++i];
    }
    if (name == "--solver") {
      parsed.solver = choose(name, value, kSolvers);
    } else if (name == "--backend") {
      parsed.backend = choose(name, value, kBackends);
    } else if (name == "--precision") {
      parsed.precision = choose(name, value, kPrecisions);
    } else if (name == "--output") {
      if (value.empty()) throw UsageError("--output expects a directory");
      parsed.output_root = value;
    } else if (name == "--threads") {
      parsed.threads = parse_positive_count(name, value);
    } else if (name == "--end") {
      char* end = nullptr;
      const double t = std::strtod(value.c_str(), &end);
      if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(t) || t <= 0)
        throw UsageError("--end '" + value + "': expected a positive time in s");
      parsed.end_time = t;
    } else if (name == "--resume") {
      if (value.empty()) throw UsageError("--resume expects a checkpoint directory");
      parsed.resume_directory = value;
    } else {
      throw UsageError("unknown option '" + name +
                       "' for run; expected --solver, --backend, --precision, --output, "
                       "--threads, --end, --resume, --quiet, --allow-unstable-step");
    }
    if (name == "--solver" || name == "--precision" || name == "--output")
      fixed_by_checkpoint.push_back(name);
  }
  if (!parsed.resume_directory.empty()) {
    if (have_scene)
      throw UsageError("--resume continues the run its checkpoint names; drop the scene file '" +
                       parsed.scene_path + "'");
    if (!fixed_by_checkpoint.empty())
      throw UsageError("--resume continues the run as it was set up; drop " +
                       fixed_by_checkpoint.front() +
                       " (the checkpoint fixes the solver, precision and output directory)");
    if (parsed.end_time)
      throw UsageError(
          "--resume runs to the end time of the scene its checkpoint names; drop --end");
  }
  return parsed;
}

}  // namespace talus
