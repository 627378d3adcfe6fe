// `talus accuracy`: the accuracy-against-time study (experiments/accuracy/README.md) on the
// production solver.
#include <fmt/format.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "experiments/accuracy/accuracy.hpp"
#include "solver/app/arguments.hpp"
#include "solver/app/commands.hpp"
#include "solver/io/json.hpp"
#include "solver/run/any_step.hpp"

namespace talus {
namespace {

// The host's processor and thread count, and the GPU's name on the CUDA backend: what the
// study's times were measured on.
std::string machine_of(const std::string& backend) {
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon != std::string::npos) cpu = line.substr(colon + 2);
    break;
  }
  std::string text = fmt::format("{} ({} threads)", cpu, std::thread::hardware_concurrency());
  if (backend == "cuda") {
    const std::string gpu =
        first_line_of("nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null");
    text = (gpu.empty() ? std::string("a CUDA GPU") : gpu) + "; host " + text;
  }
  return text;
}

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

std::string joined(const std::vector<std::string>& words, const char* none) {
  if (words.empty()) return none;
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : ",") + w;
  return text;
}

}  // namespace

std::string accuracy_json(const AccuracyArguments& args) {
  accuracy::StudyOptions options;
  options.scenes = args.scenes;
  options.knobs = args.knobs;
  options.quick = args.quick;
  options.quiet = args.quiet;
  options.output_directory = args.output;
  options.make_step = step_factory(args.backend, options.backend);
  options.commit = commit_of(TALUS_SOURCE_DIR);
  options.machine = machine_of(options.backend);
  options.date = utc_now();
  options.command =
      fmt::format("talus accuracy{} --scenes {} --knobs {} --backend {} --output {}",
                  args.quick ? " --quick" : "", joined(args.scenes, "impact,packing,drum"),
                  joined(args.knobs, "all"), options.backend, args.output);
  if (!args.quiet)
    fmt::print(stderr, "talus accuracy: {} study on the {} backend ({}), commit {}, into {}\n",
               args.quick ? "quick" : "full", options.backend, options.machine, options.commit,
               args.output);
  accuracy::StudyResult result;
  try {
    result = accuracy::run_study(options);
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  Json json;
  json["csv"] = result.csv_file;
  json["backend"] = options.backend;
  json["commit"] = options.commit;
  json["machine"] = options.machine;
  Json rows = Json::array();
  for (const accuracy::Row& r : result.rows) {
    Json row;
    row["knob"] = r.knob;
    row["setting"] = r.setting;
    row["scene"] = r.scene;
    row["error"] = r.error;
    row["wall_seconds_per_simulated_second"] =
        r.simulated_seconds > 0 ? r.wall_seconds / r.simulated_seconds : 0.0;
    rows.push_back(row);
  }
  json["rows"] = rows;
  if (!args.quiet)
    fmt::print(stderr, "talus accuracy: {} rows in {}\n", result.rows.size(), result.csv_file);
  return json_text(json);
}

}  // namespace talus
