// Real scenes end to end: each scene file of scene_cases.hpp loaded as `talus run` loads it
// (load_scene, the time-step advisor's check, the initial-state check) and run by the same runner
// (ProductionRunner) with the outputs and probes the scene writes, into a temporary output root.
// One benchmark per scene and backend, registered at run time: scenes/<name>/cpu and, in CUDA
// builds, scenes/<name>/cuda (Google Benchmark adds /iterations:<timed steps>). Each iteration is
// one step (runner.advance(): the step, the energy watchdog, the outputs due); the Time column is
// wall-clock time per step, the counters' rates too.
//
// Per scene, once per process: the scene's first settle_steps steps run from its initial state to
// the state the benchmark measures (the CUDA backend where a device is usable, else the host),
// ending in a checkpoint; each variant copies that run's output root and resumes from the
// checkpoint (as `talus run --resume` does), runs warmup_steps untimed and then the timed steps.
//
// Counters: steps_per_s, particle_steps_per_s (polyhedron-steps per second), stage_<name>_ms
// (the runner's stage_seconds over the timed steps, per step), output_ms (the outputs' time per
// step), particles, contacts_per_particle (pair and wall contacts per step, over the particles),
// threads (the host step's; 0 on the CUDA backend), settle_steps (0: the scene's initial state),
// timed_steps.
//
// Environment: TALUS_BENCH_SCENE_STEPS=f multiplies every step count of the table (settle,
// warm-up, timed; each at least 1 timed step), e.g. 0.01 for a smoke run; TALUS_BENCH_SCENE_DIR
// the folder for the output roots (default: the system's temporary folder; removed at the end);
// TALUS_BENCH_SCENE_HOST_SETTLE=1 settles the large scenes on the host when no GPU is usable
// (else they are timed from their initial state, and the label says so);
// TALUS_BENCH_SCENE_SETTLE_SECONDS ends a settle early, at the step where that much wall time
// has passed (default 180 s on the GPU, no limit on the host; the label and settle_steps say
// where). Pick scenes with
// --benchmark_filter (e.g. 'scenes/(bed_1e4|hopper)/cpu').
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "benchmarks/scene_cases.hpp"
#include "solver/contact/time_step_advisor.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_loader.hpp"

#if TALUS_HAVE_CUDA
#include "solver/core/cuda_device.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#endif

namespace {

namespace fs = std::filesystem;
using talus_bench::SceneCase;

const char* const kSettleDirectory = "bench_settle";  // the settle run's checkpoint folder

double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(value >= 0) || !std::isfinite(value))
    throw std::runtime_error(std::string(name) + "='" + text + "': expected a number >= 0");
  return value;
}

double step_scale() {
  static const double scale = env_number("TALUS_BENCH_SCENE_STEPS", 1.0);
  return scale;
}

long long scaled(long long steps, long long at_least) {
  return std::max(at_least, static_cast<long long>(std::llround(double(steps) * step_scale())));
}

// Where the output roots go: one folder per process, made at the first use (a std::exception
// when it cannot be) and removed by main at the end.
fs::path made_output_base;

const fs::path& output_base() {
  if (made_output_base.empty()) {
    const char* dir = std::getenv("TALUS_BENCH_SCENE_DIR");
    const fs::path parent =
        dir != nullptr && *dir != '\0' ? fs::path(dir) : fs::temp_directory_path();
    const fs::path path = parent / ("talus-bench-scenes-" + std::to_string(::getpid()));
    fs::create_directories(path);
    made_output_base = path;
  }
  return made_output_base;
}

// The CUDA step where this build has it and a device is usable (why not in `why`), else empty.
talus::StepFactory cuda_factory(std::string* why) {
#if TALUS_HAVE_CUDA
  if (talus::cuda_device_available(why)) return talus::make_cuda_step;
  return {};
#else
  *why = "this build has no CUDA backend";
  return {};
#endif
}

// A scene, loaded and checked as `talus run` checks it, and the state its variants start from.
struct Prepared {
  std::string error;  // non-empty: what stopped the load, the checks or the settle
  talus::Scene scene;
  std::string settle_root;  // the settle run's output root; empty: the variants start fresh
  long long settle_steps = 0;
  std::string settled_on;  // "cpu", "cuda", or why it was not settled
  double settle_seconds = 0;
};

std::string scene_path(const SceneCase& c) {
  return (fs::path(talus_bench::source_root()) / c.file).string();
}

// talus run's refusals before it steps (solver/app/run_command.cpp): a time step above the
// advisor's critical step, an initial state that cannot run (SceneError); its warnings printed.
void check_like_talus_run(const talus::Scene& scene) {
  const talus::TimeStepAdvice advice = talus::advise_time_step(scene);
  if (scene.time_step > advice.critical_step)
    throw std::runtime_error(scene.file + ": time.step " + std::to_string(scene.time_step) +
                             " s is above the critical step " +
                             std::to_string(advice.critical_step) + " s (" + advice.describe() +
                             "); talus run refuses it");
  for (const std::string& warning :
       talus::check_initial_state(scene, talus::initial_particles(scene)))
    std::fprintf(stderr, "bench_scenes: %s\n", warning.c_str());
}

// Runs the scene's first `steps` steps into `root`, or fewer when `max_seconds` of wall time
// have passed, and stops there with a checkpoint; returns the steps run.
long long settle(const talus::Scene& scene, long long steps, double max_seconds,
                 const fs::path& root, talus::StepFactory make_step) {
  talus::Scene with_checkpoint = scene;
  talus::CheckpointOutput checkpoint;
  checkpoint.every = steps;
  checkpoint.directory = kSettleDirectory;
  checkpoint.keep = 1;
  with_checkpoint.outputs.checkpoint = checkpoint;
  talus::ProductionSettings settings;
  settings.output_root = root.string();
  settings.overwrite = true;
  settings.make_step = std::move(make_step);
  talus::ProductionRunner runner(with_checkpoint, settings);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  while (runner.step() < steps && !runner.done() && elapsed() < max_seconds) runner.advance();
  if (runner.step() == 0) runner.advance();  // a checkpoint is never written at step 0
  runner.interrupt();                        // writes the checkpoint unless the last step wrote it
  if (runner.report().last_checkpoint.empty())
    throw std::runtime_error(scene.file + ": the settle run wrote no checkpoint");
  return runner.step();
}

const Prepared& prepare(const SceneCase& c) {
  static std::map<std::string, Prepared> prepared;
  auto found = prepared.find(c.name);
  if (found != prepared.end()) return found->second;
  Prepared& p = prepared[c.name];
  try {
    p.scene = talus::load_scene(scene_path(c));
    check_like_talus_run(p.scene);
    p.settle_steps = scaled(c.settle_steps, 0);
    if (p.settle_steps == 0) {
      p.settled_on = "not settled: the scene's start is measured";
      return p;
    }
    std::string why;
    talus::StepFactory make_step = cuda_factory(&why);
    if (!make_step && c.large && env_number("TALUS_BENCH_SCENE_HOST_SETTLE", 0) == 0) {
      p.settled_on = "not settled (no usable GPU: " + why + ")";
      p.settle_steps = 0;
      return p;
    }
    p.settled_on = make_step ? "cuda" : "cpu";
    const fs::path root = output_base() / (std::string(c.name) + "-settle");
    const long long asked = p.settle_steps;
    const auto start = std::chrono::steady_clock::now();
    // A bound on the device time by default (gpu-check's calls are limited to 10 minutes).
    const double max_seconds =
        env_number("TALUS_BENCH_SCENE_SETTLE_SECONDS",
                   make_step ? 180 : std::numeric_limits<double>::infinity());
    p.settle_steps = settle(p.scene, asked, max_seconds, root, std::move(make_step));
    if (p.settle_steps < asked)
      p.settled_on += " (" + std::to_string(p.settle_steps) + " of " + std::to_string(asked) +
                      " steps: TALUS_BENCH_SCENE_SETTLE_SECONDS)";
    p.settle_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    p.settle_root = root.string();
    std::fprintf(stderr, "bench_scenes: %s settled, %lld steps on %s in %.1f s\n", c.name,
                 p.settle_steps, p.settled_on.c_str(), p.settle_seconds);
  } catch (const std::exception& e) {
    p.error = e.what();
  }
  return p;
}

// Stage seconds by name (the plan's stages, then "output").
std::map<std::string, double> stage_map(const talus::ProductionReport& r) {
  std::map<std::string, double> stages(r.stage_seconds.begin(), r.stage_seconds.end());
  stages["output"] = r.output_seconds;
  return stages;
}

double contact_sum(const talus::ProductionReport& r) {
  return r.mean_contacts * double(r.steps);
}

void run_scene(benchmark::State& state, const SceneCase& c, bool cuda) {
  const Prepared& p = prepare(c);
  if (!p.error.empty()) {
    state.SkipWithError(p.error.c_str());
    return;
  }
  talus::ProductionSettings settings;
  if (cuda) {
    std::string why;
    settings.make_step = cuda_factory(&why);
    if (!settings.make_step) {
      state.SkipWithError(why.c_str());
      return;
    }
  }
  static int runs = 0;
  const std::string run_name =
      std::string(c.name) + (cuda ? "-cuda-" : "-cpu-") + std::to_string(++runs);
  const long long warmup = scaled(c.warmup_steps, 0);
  const long long timed = scaled(cuda ? c.cuda_steps : c.host_steps, 1);
  const talus::Scene& scene = p.scene;
  fs::path root;
  // The run's output root goes when the benchmark ends, however it ends.
  const std::unique_ptr<fs::path, void (*)(fs::path*)> remove_root(&root, [](fs::path* path) {
    std::error_code ignored;
    if (!path->empty()) fs::remove_all(*path, ignored);
  });
  try {
    root = output_base() / run_name;
    std::error_code ignored;
    fs::remove_all(root, ignored);
    settings.overwrite = true;
    settings.output_root = root.string();
    if (!p.settle_root.empty()) {
      fs::copy(p.settle_root, root, fs::copy_options::recursive);
      const talus::ResumePoint point = talus::read_resume_point((root / kSettleDirectory).string());
      settings.resume = point.checkpoint;
      settings.output_root = point.output_root;
    }
    talus::ProductionRunner runner(scene, settings);
    if (runner.step() + warmup + timed > talus::scene_step_count(scene)) {
      state.SkipWithError((scene.file + ": the scene ends before the benchmark's last step " +
                           std::to_string(runner.step() + warmup + timed))
                              .c_str());
      return;
    }
    for (long long k = 0; k < warmup; ++k) runner.advance();
    const talus::ProductionReport before = runner.report();
    const auto start = std::chrono::steady_clock::now();
    for (auto _ : state) runner.advance();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const talus::ProductionReport after = runner.report();
    const long long steps = after.steps - before.steps;
    if (steps <= 0 || seconds <= 0) {
      state.SkipWithError("no steps were timed");
      return;
    }
    const double per_step = 1.0 / double(steps);
    const double particles = 0.5 * double(before.particles + after.particles);
    state.counters["steps_per_s"] = double(steps) / seconds;
    state.counters["particle_steps_per_s"] = particles * double(steps) / seconds;
    state.counters["particles"] = particles;
    state.counters["contacts_per_particle"] =
        particles > 0 ? (contact_sum(after) - contact_sum(before)) * per_step / particles : 0;
    const std::map<std::string, double> was = stage_map(before);
    for (const auto& [stage, total] : stage_map(after)) {
      const auto old = was.find(stage);
      const double spent = total - (old != was.end() ? old->second : 0.0);
      const std::string key = stage == "output" ? "output_ms" : "stage_" + stage + "_ms";
      state.counters[key] = 1e3 * spent * per_step;
    }
    state.counters["threads"] = after.host_threads;
    state.counters["settle_steps"] = double(p.settle_steps);
    state.counters["timed_steps"] = double(steps);
    state.SetLabel(std::string(after.backend) + ", from step " + std::to_string(before.steps) +
                   (p.settle_root.empty() ? ", " + p.settled_on : ", settled on " + p.settled_on));
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

void register_scenes() {
  for (const SceneCase& c : talus_bench::kSceneCases) {
    const auto add = [&](bool cuda) {
      const std::string name = std::string("scenes/") + c.name + (cuda ? "/cuda" : "/cpu");
      const long long timed = scaled(cuda ? c.cuda_steps : c.host_steps, 1);
      benchmark::RegisterBenchmark(
          name.c_str(), [&c, cuda](benchmark::State& state) { run_scene(state, c, cuda); })
          ->Iterations(timed)
          ->Unit(benchmark::kMillisecond);
    };
#if TALUS_HAVE_CUDA
    add(true);
#endif
    add(false);
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    step_scale();  // a bad TALUS_BENCH_SCENE_STEPS stops here, before anything runs
    register_scenes();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_scenes: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ignored;
  if (!made_output_base.empty()) fs::remove_all(made_output_base, ignored);
  return 0;
}
