// The effect-cost table (issue 20): one scene file, benchmarks/scenes/effects.yaml, with every
// effect and every output on, run end to end by `talus run`'s runner (ProductionRunner) as
// bench_scenes runs its scenes, and then with each effect or output taken away in turn
// (effect_cases.hpp: the loaded Scene edited, not other files). What an effect costs a step is
// the difference of its variant's time from `all`'s. Benchmarks effects/<backend>/<variant>,
// backend cpu and, in CUDA builds, cuda (Google Benchmark adds /iterations:<steps>/manual_time).
//
// A fair comparison needs the same state in every variant, and taking gravity or rotation away
// from the start would change it. So the whole scene runs once per process for its settle steps
// (on the GPU where one is usable, else on the host), its outputs written only at its first and
// last step, and ends in a checkpoint; each variant copies that run's output root, resumes from
// the checkpoint made to fit it (checkpoint_for_variant), runs warmup_steps untimed (the pair list
// rebuilt, a GPU's graph captured, the jolt of what was taken away) and times a fixed number of
// steps, one per iteration (runner.advance(): the step, the energy watchdog, the outputs due).
// The scene's feed starts where the settle ends, so every variant starts with the same particles.
//
// Counters: ms_per_step (wall ms a step), steps_per_s, particles (the mean over the timed steps),
// particle_steps_per_s, stage_<stage>_ms and output_ms (the runner's stage and output seconds per
// step), contacts_per_particle, threads (the host step's; 0 on the GPU), timed_steps and, where
// `all` ran before on the same backend in this process, cost_ms_per_step (all's ms_per_step less
// this variant's: what the taken-away effect costs, within the machine's noise).
//
// Environment: TALUS_BENCH_EFFECTS_STEPS=f multiplies every step count (settle, warm-up, timed;
// at least 1 timed step), e.g. 0.01 for a smoke run; TALUS_BENCH_EFFECTS_DIR the folder for the
// output roots (default: the system's temporary folder; removed at the end). Pick variants with
// --benchmark_filter (e.g. 'effects/cpu/(all|without_drag)$').
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "benchmarks/effect_cases.hpp"
#include "benchmarks/scene_cases.hpp"
#include "solver/contact/time_step_advisor.hpp"
#include "solver/io/output_files.hpp"
#include "solver/io/probes.hpp"
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
using talus_bench::EffectVariant;
using talus_bench::kEffectsCase;

const char* const kSettleCheckpoints = "bench_settle";

double steps_factor() {
  static const double factor = [] {
    const char* text = std::getenv("TALUS_BENCH_EFFECTS_STEPS");
    if (text == nullptr || *text == '\0') return 1.0;
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(value > 0) || !std::isfinite(value))
      throw std::runtime_error(std::string("TALUS_BENCH_EFFECTS_STEPS='") + text +
                               "': expected a number > 0");
    return value;
  }();
  return factor;
}

long long steps_of(long long steps, long long at_least) {
  return std::max(at_least, static_cast<long long>(std::llround(double(steps) * steps_factor())));
}

fs::path output_folder;  // made at first use, removed by main

fs::path output_root(const std::string& name) {
  if (output_folder.empty()) {
    const char* dir = std::getenv("TALUS_BENCH_EFFECTS_DIR");
    const fs::path parent = dir && *dir ? fs::path(dir) : fs::temp_directory_path();
    output_folder = parent / ("talus-bench-effects-" + std::to_string(::getpid()));
    fs::create_directories(output_folder);
  }
  return output_folder / name;
}

talus::StepFactory gpu_step(std::string* why) {
#if TALUS_HAVE_CUDA
  if (talus::cuda_device_available(why)) return talus::make_cuda_step;
#else
  *why = "this build has no CUDA backend";
#endif
  return {};
}

// The scene as `talus run` takes it, settled once per process.
struct Settled {
  std::string error;  // what stopped the load, the checks or the settle
  talus::Scene scene;
  std::vector<EffectVariant> variants;
  fs::path root;  // the settle run's output root; its checkpoint in kSettleCheckpoints
  long long steps = 0;
  std::string on;  // "cpu" or "cuda"
};

void refuse_like_talus_run(const talus::Scene& scene) {
  const talus::TimeStepAdvice advice = talus::advise_time_step(scene);
  if (scene.time_step > advice.critical_step)
    throw std::runtime_error(scene.file + ": talus run refuses the time step, above the critical " +
                             std::to_string(advice.critical_step) + " s (" + advice.describe() +
                             ")");
  for (const std::string& warning :
       talus::check_initial_state(scene, talus::initial_particles(scene)))
    std::fprintf(stderr, "bench_effects: %s\n", warning.c_str());
}

// The whole scene's first `steps` steps into `root`: each output written at step 0 and at the
// last step only (the variants' files then continue the series), and a checkpoint there.
void settle_scene(const talus::Scene& scene, long long steps, const fs::path& root,
                  talus::StepFactory make_step) {
  talus::Scene quiet = scene;
  talus::Outputs& o = quiet.outputs;
  if (o.trajectories) o.trajectories->every = steps;
  if (o.vtk) o.vtk->every = steps;
  if (o.probes) o.probes->every = steps;
  o.checkpoint = talus::CheckpointOutput{steps, kSettleCheckpoints, 1};
  talus::ProductionSettings settings;
  settings.output_root = root.string();
  settings.overwrite = true;
  settings.make_step = std::move(make_step);
  talus::ProductionRunner runner(quiet, settings);
  while (runner.step() < steps && !runner.done()) runner.advance();
  runner.interrupt();  // the checkpoint, unless the last step wrote it
  if (runner.report().last_checkpoint.empty())
    throw std::runtime_error(scene.file + ": the settle wrote no checkpoint");
}

Settled& settled() {
  static Settled s;
  static bool tried = false;
  if (tried) return s;
  tried = true;
  try {
    s.scene =
        talus::load_scene((fs::path(talus_bench::source_root()) / kEffectsCase.file).string());
    refuse_like_talus_run(s.scene);
    s.variants = talus_bench::effect_variants(s.scene);
    s.steps = steps_of(kEffectsCase.settle_steps, 1);
    std::string why;
    talus::StepFactory make_step = gpu_step(&why);
    s.on = make_step ? "cuda" : "cpu";
    s.root = output_root("settle");
    const auto start = std::chrono::steady_clock::now();
    settle_scene(s.scene, s.steps, s.root, std::move(make_step));
    std::fprintf(stderr, "bench_effects: settled %lld steps on %s in %.1f s\n", s.steps,
                 s.on.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } catch (const std::exception& e) {
    s.error = e.what();
  }
  return s;
}

// all's ms a step by backend, for cost_ms_per_step.
std::map<bool, double> all_ms;

void run_variant(benchmark::State& state, std::size_t index, bool cuda) {
  const Settled& s = settled();
  std::string why = s.error;
  talus::ProductionSettings settings;
  if (why.empty() && cuda) settings.make_step = gpu_step(&why);  // why not, when it cannot
  if (!why.empty()) {
    state.SkipWithError(why.c_str());
    return;
  }
  const EffectVariant& variant = s.variants.at(index);
  static int runs = 0;
  const fs::path root =
      output_root(variant.name + (cuda ? "-cuda-" : "-cpu-") + std::to_string(++runs));
  // The copy goes when the benchmark ends, however it ends.
  const std::unique_ptr<const fs::path, void (*)(const fs::path*)> remove_root(
      &root, [](const fs::path* path) {
        std::error_code ignored;
        fs::remove_all(*path, ignored);
      });
  try {
    fs::copy(s.root, root, fs::copy_options::recursive);
    const talus::ResumePoint point = talus::read_resume_point((root / kSettleCheckpoints).string());
    const talus::Scene scene = talus_bench::make_variant(s.scene, variant);
    settings.resume = std::make_shared<const talus::Checkpoint>(
        talus_bench::checkpoint_for_variant(*point.checkpoint, s.scene, scene));
    settings.output_root = point.output_root;
    settings.overwrite = true;
    if (scene.outputs.probes) {  // the header alone: rows continue it from the settled step
      const talus::ProbeWriter header(
          talus::joined_path(point.output_root, scene.outputs.probes->file),
          talus::probe_columns(*scene.outputs.probes, scene.walls));
    }
    talus::ProductionRunner runner(scene, settings);
    const long long warmup = steps_of(kEffectsCase.warmup_steps, 0);
    const long long timed = steps_of(cuda ? kEffectsCase.cuda_steps : kEffectsCase.host_steps, 1);
    if (runner.step() + warmup + timed > talus::scene_step_count(scene))
      throw std::runtime_error(scene.file + ": the scene ends before the benchmark's last step");
    for (long long k = 0; k < warmup; ++k) runner.advance();
    const talus::ProductionReport before = runner.report();
    // Each step timed alone (manual time), so that the Time column and ms_per_step are the same
    // seconds, with nothing of the loop's own in them.
    double seconds = 0;
    for (auto _ : state) {
      const auto start = std::chrono::steady_clock::now();
      runner.advance();
      const double step_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      state.SetIterationTime(step_seconds);
      seconds += step_seconds;
    }
    const talus::ProductionReport after = runner.report();
    const long long steps = after.steps - before.steps;
    if (steps <= 0 || seconds <= 0) throw std::runtime_error("no steps were timed");
    const double particles = 0.5 * double(before.particles + after.particles);
    const double ms = 1e3 * seconds / double(steps);
    state.counters["ms_per_step"] = ms;
    state.counters["steps_per_s"] = double(steps) / seconds;
    state.counters["particles"] = particles;
    state.counters["particle_steps_per_s"] = particles * double(steps) / seconds;
    const double contacts =
        after.mean_contacts * double(after.steps) - before.mean_contacts * double(before.steps);
    state.counters["contacts_per_particle"] = contacts / double(steps) / particles;
    std::map<std::string, double> spent(after.stage_seconds.begin(), after.stage_seconds.end());
    for (const auto& [stage, total] : before.stage_seconds) spent[stage] -= total;
    for (const auto& [stage, total] : spent)
      state.counters["stage_" + stage + "_ms"] = 1e3 * total / double(steps);
    state.counters["output_ms"] =
        1e3 * (after.output_seconds - before.output_seconds) / double(steps);
    state.counters["threads"] = after.host_threads;
    state.counters["timed_steps"] = double(steps);
    if (variant.name == "all")
      all_ms[cuda] = ms;
    else if (all_ms.count(cuda))
      state.counters["cost_ms_per_step"] = all_ms[cuda] - ms;
    state.SetLabel(after.backend + ", from step " + std::to_string(before.steps) + ", settled on " +
                   s.on);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

// The variants' names need the scene (one per output it writes); a scene that does not load
// still gets one benchmark a backend, which reports why.
void register_variants() {
  std::vector<std::string> names;
  try {
    for (const EffectVariant& v : talus_bench::effect_variants(talus::load_scene(
             (fs::path(talus_bench::source_root()) / kEffectsCase.file).string())))
      names.push_back(v.name);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_effects: %s\n", e.what());
    names = {"all"};
  }
  for (const bool cuda : {false, true}) {
#if !TALUS_HAVE_CUDA
    if (cuda) continue;
#endif
    for (std::size_t k = 0; k < names.size(); ++k) {
      const std::string name = "effects/" + std::string(cuda ? "cuda/" : "cpu/") + names[k];
      benchmark::RegisterBenchmark(
          name.c_str(), [k, cuda](benchmark::State& state) { run_variant(state, k, cuda); })
          ->Iterations(steps_of(cuda ? kEffectsCase.cuda_steps : kEffectsCase.host_steps, 1))
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    steps_factor();  // a bad TALUS_BENCH_EFFECTS_STEPS stops here, before any benchmark
    register_variants();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_effects: %s\n", e.what());
    return 2;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ignored;
  if (!output_folder.empty()) fs::remove_all(output_folder, ignored);
  return 0;
}
