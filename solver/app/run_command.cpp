// `talus run [options] scene.yaml`: loads the scene and runs it with the chosen solver. The
// reference solver is linked in where CMake found CGAL and Eigen (TALUS_HAVE_REFERENCE); the
// production solver runs on the host backend (solver/step/host/host_step.hpp) or, in CUDA builds
// (TALUS_HAVE_CUDA), on the CUDA backend (solver/step/cuda/cuda_step.hpp): `--backend cuda` asks
// for it, `auto` takes it where a device is usable. `--threads N` sets the host backend's threads
// (default: OpenMP's, all cores or OMP_NUM_THREADS); the summary and the notice of `auto` name
// the count when the host runs the scene. `--resume DIR` continues a production run from the
// newest checkpoint in DIR (solver/io/checkpoint.hpp); SIGINT and SIGTERM stop a production run
// at a step boundary, with a checkpoint when the scene asks for them. Before either solver runs,
// the time-step advisor (solver/contact/time_step_advisor.hpp) prints dt / dt_crit and refuses a
// step above dt_crit unless --allow-unstable-step.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/app/commands.hpp"
#include "solver/app/run_arguments.hpp"
#include "solver/app/run_messages.hpp"
#include "solver/contact/time_step_advisor.hpp"
#include "solver/core/host_parallel.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/io/json.hpp"
#include "solver/io/output_files.hpp"
#include "solver/io/run_directory.hpp"
#include "solver/parallel/decomposed_step.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/builtin_scene.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/scene/scene_memory.hpp"

#if TALUS_HAVE_REFERENCE
#include "reference/run/scene_run.hpp"
#endif
#if TALUS_HAVE_OPENCV
#include "solver/render/render_run.hpp"
#endif
#if TALUS_HAVE_CUDA
#include "solver/core/cuda_device.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#endif

namespace talus {

namespace {

// Members a caller adds to the summary after the run (the built-in scene's bed height).
using ExtraMembers = std::function<void(const ProductionReport&, Json&)>;

// The signal that asked the run to stop (0: none). The handler only records it and puts the
// default action back, so that a second Ctrl-C ends the process at once.
volatile std::sig_atomic_t stop_signal = 0;

// When talus started (static initialisation), from which --stop-after counts.
const std::chrono::steady_clock::time_point process_start = std::chrono::steady_clock::now();

void request_stop(int signal) {
  stop_signal = signal;
  std::signal(signal, SIG_DFL);
}

// Ctrl-C and SIGTERM stop the run at the next step boundary while it runs.
class StopSignals {
 public:
  StopSignals() {
    stop_signal = 0;
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
  }
  ~StopSignals() {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

// The time-step advisor's verdict on the scene's step, before any solver runs: one line on
// stderr (dt, dt / dt_crit, what limits dt_crit, the Rayleigh time) unless --quiet; a step above
// dt_crit is a SceneError at time.step naming the largest stable step, or with
// --allow-unstable-step a warning line and the run.
TimeStepAdvice check_time_step(const RunArguments& args, const Scene& scene) {
  const TimeStepAdvice advice = advise_time_step(scene);
  const double dt = scene.time_step;
  const std::string rayleigh = std::isfinite(advice.rayleigh_time)
                                   ? fmt::format("; Rayleigh time {:.1e} s", advice.rayleigh_time)
                                   : "";
  const char* automatic = scene.time_step_auto ? " (step: auto)" : "";
  if (!args.quiet) {
    if (advice.limited()) {
      fmt::print(stderr,
                 "talus run: time step {:.3g} s{} = {:.2g} of the critical step {:.1e} s ({}{})\n",
                 dt, automatic, dt / advice.critical_step, advice.critical_step, advice.describe(),
                 rayleigh);
    } else {
      fmt::print(stderr, "talus run: time step {:.3g} s{}; no critical step: {}{}\n", dt, automatic,
                 advice.describe(), rayleigh);
    }
  }
  if (!(dt > advice.critical_step)) return advice;
  // The largest stable step, rounded down so that the value we suggest is stable.
  const double stable = round_down_two_digits(advice.critical_step);
  if (args.allow_unstable_step) {
    fmt::print(stderr,
               "talus run: warning: time step {:.6g} s is above the largest stable step {:.1e} s "
               "for {} (contact: {}); running anyway (--allow-unstable-step)\n",
               dt, stable, advice.limit, advice.model);
    return advice;
  }
  refuse_unstable_step(scene, advice);
  return advice;
}

// The initial particles, made once here and checked (scene/initial_state_checks.hpp): what cannot
// run right is a SceneError, the rest a warning line each on stderr (also with --quiet). Then they
// are handed on to the solver that the run builds next (keep_initial_particles), which takes the
// list instead of placing a random fill again: the peak memory is that of the list and the
// solver's arrays, as when the solver made its own.
void check_initial_particles(const Scene& scene) {
  std::vector<ParticleState> particles = initial_particles(scene);
  for (const std::string& warning : check_initial_state(scene, particles))
    std::fprintf(stderr, "talus run: %s\n", warning.c_str());
  keep_initial_particles(scene, std::move(particles));
}

// The advisor's numbers in a run's summary: dt_crit (null when nothing limits it) and dt / dt_crit.
void time_step_members(const Scene& scene, const TimeStepAdvice& advice, Json& json) {
  json["time_step"] = scene.time_step;
  json["critical_time_step"] = advice.critical_step;
  json["time_step_ratio"] = scene.time_step / advice.critical_step;
}

// A rank's host threads in a decomposed run: --threads, else the cores shared among the ranks.
int decomposed_threads(const RunArguments& args) {
  if (args.threads > 0) return args.threads;
  return std::max(1, host_thread_count(0) / world()->size());
}

// `--backend auto` takes the GPU for scenes of at least this many particles (all a scene
// creates, feeds included: scene_particle_count) and the host below. Measured (benchmarks/
// README.md, session 19): the built-in scene with 8, 16, 32 and 63 of its dodecahedra, 12,500
// steps by `talus run` on an H200 and its 16-core host: GPU 3,997 / 3,536 / 3,132 / 2,892 steps
// a second, host 23,219 / 12,008 / 3,729 / 1,615. The GPU step has a floor of about 0.25 ms
// (some thirty dependent kernels, each a thread's serial geometry at the least) whatever the
// count, the host's grows with it; they cross between 32 and 63 particles.
constexpr double kAutoGpuParticles = 50;

// A decomposed run's backend (the same answer on every rank): the CUDA step for --backend cuda
// (refused where this talus has no CUDA or no GPU is usable), and for auto where a GPU is usable
// and the scene is large enough; else the host step.
bool decomposed_on_cuda(const Scene& scene) {
#if TALUS_HAVE_CUDA
  if (scene.backend == Backend::cpu) return false;
  std::string why;
  if (cuda_device_available(&why))
    return scene.backend == Backend::cuda || scene_particle_count(scene) >= kAutoGpuParticles;
  if (scene.backend == Backend::cuda)
    throw RunError("--backend cuda: " + why + "; run this scene with --backend cpu (or auto)");
  return false;
#else
  if (scene.backend == Backend::cuda)
    throw RunError(
        "this talus was built without CUDA (no nvcc at configure time); run this scene with "
        "--backend cpu (or --backend auto)");
  return false;
#endif
}

// The production solver on the chosen backend (make_step: empty for the host), from the scene's
// start or from `resume`; the summary adds wall time per stage, contacts per step and peak
// memory (and what `extra` adds). A stop signal ends it with RunInterrupted.
std::string run_production_json(const RunArguments& args, const Scene& scene,
                                const TimeStepAdvice& advice, StepFactory make_step,
                                const ResumePoint* resume, SetupTimes& setup,
                                const ExtraMembers& extra = {}) {
  if (world()->rank() != 0) {
    // Rank 0 runs the runner; this rank serves its step's commands (parallel/decomposed_step.hpp).
    // Resumed, its step starts empty as rank 0's does (production_run.cpp): the checkpoint's
    // particles arrive with the restore.
    const Scene start = resume ? without_initial_particles(scene) : scene;
#if TALUS_HAVE_CUDA
    if (decomposed_on_cuda(start)) {
      serve_decomposed_cuda_step(start, world());
      return "";
    }
#endif
    serve_decomposed_step(start, decomposed_threads(args), world());
    return "";
  }
  ProductionSettings settings;
  settings.make_step = std::move(make_step);
  settings.host_threads = args.threads;
  settings.output_root = resume ? resume->output_root : args.output_root;
  if (resume) settings.resume = resume->checkpoint;
  settings.overwrite = args.overwrite;
  // Rank 0 alone asks (the serving ranks follow its commands), so every rank stops at one step.
  std::optional<std::chrono::steady_clock::time_point> deadline;
  if (args.stop_after_seconds && *args.stop_after_seconds < 1e9)  // beyond 30 years: none
    deadline = process_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(*args.stop_after_seconds));
  settings.stop_requested = [deadline] {
    return stop_signal != 0 || (deadline && std::chrono::steady_clock::now() >= *deadline);
  };
  if (!args.quiet) settings.progress = print_production_progress;
  settings.setup_done = [&setup](const char* part, double seconds) {
    setup.runner_part(part, seconds);
  };
  if (advice.limited()) {
    settings.instability_hint = fmt::format(
        "The likely cause is a time step too large for the contact law: time.step = {:.3g} s is "
        "{:.2g} of the critical step {:.1e} s ({}); try time.step: auto ({:.1e} s).",
        scene.time_step, scene.time_step / advice.critical_step, advice.critical_step,
        advice.describe(), advice.recommended_step);
  }
  ProductionReport report;
  try {
    const StopSignals signals;
    report = run_production(scene, settings);
  } catch (const StepNotSupported& e) {
    // What the production step cannot simulate yet is the run's setting, not an internal fault.
    throw RunError(e.what());
  } catch (const CheckpointError& e) {
    throw RunError(e.what());  // a checkpoint that does not fit the scene
  } catch (const OutputConflict& e) {
    throw RunError(e.what());  // an output directory in use or holding another run's outputs
  }
  Json json;
  json["solver"] = "talus";
  json["backend"] = report.backend;
  json["ranks"] = world()->size();  // MPI ranks the run was decomposed over (docs/parallel.md)
  if (report.host_threads > 0) json["host_threads"] = report.host_threads;
  json["precision"] = to_string(scene.precision);
  json["scene"] = resume ? resume->scene_file : args.scene_path;
  if (resume) json["resumed_from_step"] = report.resumed_from_step;
  json["steps"] = report.steps;
  json["simulated_time"] = report.simulated_time;
  time_step_members(scene, advice, json);
  json["wall_seconds"] = report.wall_seconds;
  // Before the first step: the scene's reading and its particles' making, then the runner's
  // parts (these within wall_seconds).
  Json& setup_json = json["setup_seconds"] = Json::object();
  for (const auto& [part, seconds] : setup.parts()) setup_json[part] = seconds;
  json["particles"] = report.particles;
  if (scene.domain) json["removed_particles"] = report.removed_particles;
  json["mean_contacts_per_step"] = report.mean_contacts;
  json["pair_list_builds"] = report.pair_list_builds;
  // Each feed's progress, and a line on stderr (also with --quiet) for one that fell behind: a
  // feed whose region stays full inserts nothing and would otherwise say so nowhere.
  if (!report.feeds.empty()) {
    Json& feeds = json["feeds"] = Json::array();
    for (std::size_t f = 0; f < report.feeds.size(); ++f) {
      const FeedCount& c = report.feeds[f];
      feeds.push_back({{"inserted", c.inserted}, {"due", c.due}, {"total", c.total}});
      if (c.inserted < c.due && f < scene.feeds.size()) {
        fmt::print(
            stderr,
            "talus run: {}: the feed fell behind: {} of the {} particles due by t = {:.6g} s "
            "inserted (of {} in all); its region had no room for the rest\n",
            scene.feeds[f].source.where(), c.inserted, c.due, report.simulated_time, c.total);
      }
    }
  }
  if (report.backend == "cuda") {  // how many steps ran as one graph launch
    Json& graphs = json["cuda_graphs"] = Json::object();
    graphs["steps"] = report.graph_steps;
    graphs["captures"] = report.graph_captures;
    graphs["aborted"] = report.graph_aborted;
  }
  if (!report.stages_beside.empty()) {  // their seconds overlap the other stage's
    Json& beside = json["stages_beside"] = Json::object();
    for (const auto& [stage, other] : report.stages_beside) beside[stage] = other;
  }
  Json& stages = json["stage_seconds"] = Json::object();
  for (const auto& [stage, seconds] : report.stage_seconds) stages[stage] = seconds;
  stages["output"] = report.output_seconds;
  if (world()->size() > 1) {
    json["exchange_seconds"] = report.exchange_seconds;
    json["exchange_vote_seconds"] = report.exchange_vote_seconds;
    json["exchange_rebuild_seconds"] = report.exchange_rebuild_seconds;
    json["exchange_bytes"] = report.exchange_bytes;
    json["rebalances"] = report.rebalances;
  }
  if (report.steady.steps > 0) {  // the steps after the first (ProductionReport::steady)
    Json& steady = json["steady"] = Json::object();
    steady["steps"] = report.steady.steps;
    steady["seconds"] = report.steady.seconds;
    Json& s = steady["stage_seconds"] = Json::object();
    for (const auto& [stage, seconds] : report.steady.stage_seconds) s[stage] = seconds;
    if (world()->size() > 1) {
      steady["exchange_seconds"] = report.steady.exchange_seconds;
      steady["exchange_vote_seconds"] = report.steady.exchange_vote_seconds;
      steady["exchange_rebuild_seconds"] = report.steady.exchange_rebuild_seconds;
      steady["exchange_bytes"] = report.steady.exchange_bytes;
    }
  }
  json["particle_array_bytes"] = report.particle_bytes;
  json["peak_memory_bytes"] = report.peak_memory_bytes;
  json["outputs"] = report.outputs;
  if (report.interrupted) {
    const int signal = stop_signal;
    const std::string cause =
        signal == 0 ? fmt::format("stopped after --stop-after {} s", *args.stop_after_seconds)
                    : std::string("interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM");
    std::string message = "run " + cause + " at step " + std::to_string(report.steps) +
                          " (t = " + std::to_string(report.simulated_time) + " s); ";
    if (report.last_checkpoint.empty()) {
      message +=
          "no checkpoint (the scene has no outputs.checkpoint); the outputs up to this "
          "step are complete";
    } else {
      message += "checkpoint " + report.last_checkpoint + "; continue with 'talus run --resume " +
                 std::filesystem::path(report.last_checkpoint).parent_path().string() + "'";
    }
    // The summary of the steps made so far (this sitting's, when resumed) goes to stdout as an
    // ended run's does, marked "stopped", so that a driver of many sittings keeps each one's
    // stage times.
    json["stopped"] = message;
    throw RunInterrupted(message, signal == 0 ? kExitStopped : 128 + signal, json_text(json));
  }
  if (extra) extra(report, json);
  return json_text(json);
}

// The built-in scene's closing: its last frame drawn where OpenCV is built in, the final bed
// height beside the paper's (solver/scene/builtin_scene.hpp), on stderr and in the summary.
void finish_builtin_run(const RunArguments& args, const ProductionReport& report, Json& json) {
  std::string picture;
#if TALUS_HAVE_OPENCV
  RenderSettings render;
  render.run_directory = args.output_root + "/frames";
  render.last_only = true;
  render.fit_walls = false;  // the bed fills the picture; the 0.5 m tube would dwarf it
  render.width = 640;
  render.height = 800;
  const RenderReport drawn = render_run(render);
  picture = drawn.images.back();
#endif
  json["bed_height"] = report.bed_height;
  json["paper_bed_height"] = kPaperBedHeight;
  json["picture"] = picture.empty() ? "none: this talus was built without OpenCV" : picture;
  std::fprintf(stderr,
               "talus run: final bed height %.1f cm after %.3g s; the paper (section 3.3) reports "
               "about %.0f cm%s%s\n",
               100 * report.bed_height, report.simulated_time, 100 * kPaperBedHeight,
               picture.empty() ? "" : "; picture: ", picture.c_str());
}

// The production step's backend for the scene: the CUDA step where the scene (or --backend) asks
// for it, or for auto where a device is usable and the scene is large enough to gain from it;
// else the host (empty). `auto` says which it took and why in one line.
StepFactory production_backend(const RunArguments& args, const Scene& scene) {
  if (world()->size() > 1) {
    // Several ranks (mpirun): the step decomposed over them (docs/parallel.md).
#if TALUS_HAVE_CUDA
    if (decomposed_on_cuda(scene))
      return [](const Scene& s) { return make_decomposed_cuda_step(s, world()); };
#else
    decomposed_on_cuda(scene);  // refuses --backend cuda
#endif
    return [&args](const Scene& s) {
      return make_decomposed_step(s, decomposed_threads(args), world());
    };
  }
  StepFactory make_step;  // empty: the host
  const int host_threads = host_thread_count(args.threads);
#if TALUS_HAVE_CUDA
  std::string why;
  if (scene.backend != Backend::cpu) {
    const double particles = scene_particle_count(scene);
    if (cuda_device_available(&why)) {
      if (scene.backend == Backend::cuda || particles >= kAutoGpuParticles) {
        make_step = make_cuda_step;
        if (scene.backend == Backend::automatic && !args.quiet) {
          fmt::print(stderr,
                     "talus run: {:.0f} particles: running on the GPU (cuda), faster than the "
                     "host from about {:.0f} particles\n",
                     particles, kAutoGpuParticles);
        }
      } else {
        if (!args.quiet) {
          fmt::print(stderr,
                     "talus run: {:.0f} particles: running on the host (cpu, {} thread{}), as "
                     "fast as the GPU below about {:.0f} particles; --backend cuda takes the "
                     "GPU\n",
                     particles, host_threads, host_threads == 1 ? "" : "s", kAutoGpuParticles);
        }
        return make_step;
      }
    } else if (scene.backend == Backend::cuda) {
      throw RunError("--backend cuda: " + why +
                     "; run this scene with --backend cpu (or "
                     "--backend auto, which falls back to the host)");
    }
  }
  if (scene.backend == Backend::automatic && !make_step && !args.quiet) {
    std::fprintf(stderr,
                 "talus run: no usable GPU backend (%s); running on the host (cpu, %d "
                 "thread%s)\n",
                 why.c_str(), host_threads, host_threads == 1 ? "" : "s");
  }
#else
  if (scene.backend == Backend::cuda) {
    throw RunError(
        "this talus was built without CUDA (no nvcc at configure time); run this scene with "
        "--backend cpu (or --backend auto)");
  }
  if (scene.backend == Backend::automatic && !args.quiet) {
    std::fprintf(stderr,
                 "talus run: no usable GPU backend (this talus was built without CUDA); running "
                 "on the host (cpu, %d thread%s)\n",
                 host_threads, host_threads == 1 ? "" : "s");
  }
#endif
  return make_step;
}

// --end T: the scene's end time becomes T (a whole number of steps, at least one), after
// `after_step` (a resumed run's checkpoint step) when given.
void apply_end_time(const RunArguments& args, Scene& scene, long long after_step = -1) {
  if (!args.end_time) return;
  if (*args.end_time < scene.time_step)
    throw RunError(fmt::format(
        "--end {}: shorter than one time step of the scene (time.step = {} s in {}); expected "
        "an end time of at least {} s",
        *args.end_time, scene.time_step, scene.file, scene.time_step));
  const std::string problem = step_count_problem(*args.end_time, scene.time_step);
  if (!problem.empty()) throw RunError("--end: " + problem);
  const auto end_step = static_cast<long long>(std::round(*args.end_time / scene.time_step));
  if (after_step >= 0 && end_step <= after_step)
    throw RunError(fmt::format(
        "--end {}: step {} of {:.6g} s, not after the checkpoint's step {}; expected an end "
        "time after {:.6g} s",
        *args.end_time, end_step, scene.time_step, after_step,
        double(after_step) * scene.time_step));
  scene.end_time = *args.end_time;
}

// `talus run --resume DIR`: the newest checkpoint of DIR, the scene it names (unchanged since:
// its hash), in the checkpoint's precision, on its backend unless --backend says otherwise, to
// the scene's end time or --end.
std::string resume_json(const RunArguments& args) {
  ResumePoint point;
  try {
    point = read_resume_point(args.resume_directory);
  } catch (const CheckpointError& e) {
    throw RunError(e.what());
  }
  warn_oversubscribed_threads(args);
  SetupTimes setup(args.quiet);
  Scene scene = load_scene(point.scene_file);
  setup.done("scene", "the scene and its walls read");
  check_scene_memory(scene, physical_memory_bytes());
  scene.precision = point.precision == "float" ? Precision::float32 : Precision::float64;
  scene.backend =
      args.backend ? *args.backend : (point.backend == "cuda" ? Backend::cuda : Backend::cpu);
  apply_end_time(args, scene, point.step);
  if (!args.quiet) {
    std::fprintf(stderr, "talus run: resuming %s from step %lld (%s)\n", point.scene_file.c_str(),
                 point.step, point.checkpoint_path.c_str());
  }
  const TimeStepAdvice advice = check_time_step(args, scene);
  return run_production_json(args, scene, advice, production_backend(args, scene), &point, setup);
}

#if TALUS_HAVE_REFERENCE
void print_progress(const reference::SceneRunProgress& p) {
  print_progress_line(p.step, p.total_steps, p.time, p.end_time, p.particles, p.contacts,
                      p.wall_seconds);
}
#endif

}  // namespace

std::string run_json(const RunArguments& given) {
  if (!given.resume_directory.empty()) return resume_json(given);
  RunArguments args = given;
  // Each rank of a decomposed run makes and checks the initial particles (a random fill on every
  // thread) on its share of the cores, as its step will run, not on all of them at once.
  if (world()->size() > 1) set_default_host_threads(decomposed_threads(args));
  warn_oversubscribed_threads(args);
  const bool builtin = args.scene_path.empty();
  // Before the built-in scene is written out: a refused run leaves no file behind.
  if (builtin && args.solver == SolverKind::reference)
    throw RunError("the built-in scene runs on the production solver; drop --solver reference");
  if (builtin) {
    // The built-in scene, written out so that the run directory holds what produced it (and
    // `talus render` finds it through run.json).
    if (args.output_root.empty()) {
      // talus's own directory for it: a new run of the built-in scene replaces the last one's.
      args.output_root = kBuiltinSceneOutput;
      args.overwrite = true;
    }
    args.scene_path = args.output_root + "/" + kBuiltinSceneFileName;
    if (world()->rank() == 0) {
      create_output_directory(args.output_root);
      write_file_atomically(args.scene_path, builtin_scene_text());
    }
    world()->broadcast(0, 0);  // the other ranks read it once it is written
    if (!args.quiet)
      std::fprintf(stderr,
                   "talus run: no scene given; running the built-in scene (63 dodecahedra poured "
                   "into a 10 cm cylinder, paper section 3.3), written to %s, outputs in %s/\n",
                   args.scene_path.c_str(), args.output_root.c_str());
  }
  SetupTimes setup(args.quiet);
  Scene scene = load_scene(args.scene_path);  // SceneError: file:line:column: key: message
  setup.done("scene", "the scene and its walls read");
  if (args.backend) scene.backend = *args.backend;
  if (args.precision) scene.precision = *args.precision;
  apply_end_time(args, scene);
  // Before any particle is made: a scene too large for this machine is refused with its numbers.
  check_scene_memory(scene, physical_memory_bytes());
  check_initial_particles(scene);
  setup.done("initial_particles",
             std::to_string(initial_particle_count(scene)) + " initial particles made and checked");
  const TimeStepAdvice advice = check_time_step(args, scene);

  if (args.solver == SolverKind::production) {
    ExtraMembers extra;
    if (builtin)
      extra = [&args](const ProductionReport& report, Json& json) {
        finish_builtin_run(args, report, json);
      };
    return run_production_json(args, scene, advice, production_backend(args, scene), nullptr, setup,
                               extra);
  }
  if (world()->size() > 1)
    throw RunError("the reference solver runs in one process; drop mpirun or --solver reference");
  if (args.threads > 0) {
    throw RunError(
        "--threads sets the production solver's host threads; the reference solver "
        "runs on one thread (drop --threads)");
  }
#if TALUS_HAVE_REFERENCE
  if (scene.outputs.checkpoint && !args.quiet)
    std::fprintf(stderr,
                 "talus run: the reference solver writes no checkpoints (%s: "
                 "outputs.checkpoint is ignored)\n",
                 args.scene_path.c_str());
  if (scene.precision != Precision::float64) {
    throw RunError(
        "--solver reference computes in double only; drop --precision float or set "
        "precision: double in " +
        args.scene_path);
  }
  reference::SceneRunSettings settings;
  settings.output_root = args.output_root;
  settings.overwrite = args.overwrite;
  if (!args.quiet) settings.progress = print_progress;
  reference::SceneRunReport report;
  try {
    report = reference::run_scene(scene, settings);
  } catch (const OutputConflict& e) {
    throw RunError(e.what());
  }
  Json json;
  json["solver"] = "reference";
  json["scene"] = args.scene_path;
  json["steps"] = report.steps;
  json["simulated_time"] = report.simulated_time;
  time_step_members(scene, advice, json);
  json["wall_seconds"] = report.wall_seconds;
  json["particles"] = report.particles;
  json["mean_contacts_per_step"] = report.mean_contacts;
  json["outputs"] = report.outputs;
  return json_text(json);
#else
  throw RunError(
      "this talus was built without the reference solver (CMake did not find CGAL and "
      "Eigen; scripts/setup installs them)");
#endif
}

}  // namespace talus
