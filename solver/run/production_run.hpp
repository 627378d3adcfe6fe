// A scene run by the production solver: the step of the chosen backend (host_step.hpp by
// default, cuda_step.hpp where the caller passes make_cuda_step) in the scene's precision,
// stepped to the end time, writing the outputs the reference solver writes (solver/io:
// trajectory frames, run.json, probes) at step 0, every `every` steps and at the last step.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "solver/io/trajectory.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/step_plan.hpp"

namespace talus {

struct ProductionProgress {
  long long step = 0, total_steps = 0;
  double time = 0, end_time = 0;  // s
  std::size_t particles = 0;
  std::size_t contacts = 0;      // particle-particle and particle-wall, at the last evaluation
  double wall_seconds = 0;       // since the run started
  std::vector<FeedCount> feeds;  // each feed's progress (AnyStep::feed_counts)
};

class AnyStep;     // any_step.hpp
class Checkpoint;  // solver/io/checkpoint.hpp
using StepFactory = std::function<std::unique_ptr<AnyStep>(const Scene&)>;

struct ProductionSettings {
  std::string output_root;
  // The backend: the step it makes for the scene (make_cuda_step of cuda_step.hpp in CUDA
  // builds); empty: the host step. The host library cannot name the CUDA one itself (talus_cuda
  // links talus_solver), so the caller that links both passes it.
  StepFactory make_step;  // relative output paths of the scene are taken inside it
  // The host step's threads (<= 0: OpenMP's default, all cores or OMP_NUM_THREADS).
  int host_threads = 0;
  std::function<void(const ProductionProgress&)> progress;
  double progress_interval = 1.0;  // s of wall time
  // Told each part of the runner's setup as it ends, with its wall-clock seconds: "step" (the
  // step built: the particles on the backend, the walls' grids), "restore" (a resumed run's
  // checkpoint read into it), "first_forces" (a new run's step-0 contacts and outputs).
  std::function<void(const char* part, double seconds)> setup_done;
  // Continue from this checkpoint (read_resume_point) instead of the scene's initial state: the
  // step's state set back, the outputs continued (probe rows after its step dropped, then
  // appended; frames numbered on; the ParaView collections as they were). Null: a new run.
  std::shared_ptr<const Checkpoint> resume;
  // A new run into an output root that holds an earlier run's outputs removes them first
  // (claim_output_root, solver/io/run_directory.hpp); false: such a run is refused.
  bool overwrite = false;
  // Asked after each step; true stops the run there (Ctrl-C, SIGTERM), with a checkpoint when
  // the scene asks for checkpoints (report().interrupted).
  std::function<bool()> stop_requested;
  // Appended to the watchdog's message when a run stops for energy it created or a state that is
  // no longer finite (talus run: the time-step advisor's numbers).
  std::string instability_hint =
      "the likely cause is a time step too large for the contact law's stiffness (time.step)";
};

// The runner checks the energy balance every this many steps (and at the last one).
constexpr long long kEnergyWatchEvery = 100;

// Where `talus run --resume PATH` goes on from: the newest checkpoint of the directory PATH (or
// the checkpoint file PATH), read and checked, and what it says of the run.
struct ResumePoint {
  std::string checkpoint_path;
  std::shared_ptr<const Checkpoint> checkpoint;
  std::string scene_file;   // absolute, as the run loaded it
  std::string output_root;  // the run's output root, found from the checkpoint directory
  std::string backend;      // "cpu" or "cuda": the step that wrote it
  std::string precision;    // "double" or "float"
  long long step = 0;
};
// Throws CheckpointError (solver/io/checkpoint.hpp) naming the file: no checkpoint in the
// directory, a corrupt or truncated one (checksum, size; naming an older checkpoint of the
// directory to resume from instead, when there is one), another format version, or a scene file
// or a mesh file it reads that is gone or has changed since the checkpoint was written (their
// hashes).
ResumePoint read_resume_point(const std::string& path);

// The files a scene reads: the scene file, then its templates' and walls' mesh files, each once,
// as absolute paths. A checkpoint keeps their hashes; resuming checks them.
std::vector<std::string> scene_input_files(const Scene& scene);

struct ProductionReport {
  std::string backend = "cpu";  // the step's: "cpu" or "cuda"
  int host_threads = 0;         // the host step's threads (backend "cpu"); 0 for another backend
  long long steps = 0;
  double simulated_time = 0;  // s
  double wall_seconds = 0;
  std::size_t particles = 0;
  long long removed_particles = 0;  // left the scene's domain box
  double mean_contacts = 0;         // particle-particle and particle-wall contacts per step
  // Builds of the pair list by this process (a resumed run counts from its resumption; a list
  // is kept until a particle has moved 0.45 skin or the particles changed).
  long long pair_list_builds = 0;
  std::vector<std::pair<std::string, double>> stage_seconds;  // the plan's stages, in order
  // A run on several ranks: the most wall-clock seconds a rank spent exchanging particles and
  // ghosts (and waiting for the others there); 0 in one process.
  double exchange_seconds = 0;
  // Of exchange_seconds: the rebuild vote's (the wait for the slowest rank included) and the
  // rebuild steps' (AnyStep); the rest is the ghosts' updates.
  double exchange_vote_seconds = 0, exchange_rebuild_seconds = 0;
  double exchange_bytes = 0;  // decomposed: bytes the ranks sent each other (AnyStep)
  long long rebalances = 0;   // the boxes cut again (docs/parallel.md)
  // The CUDA step's steps launched as one graph, graphs captured, graph steps finished stage by
  // stage (AnyStep::graph_steps); 0 for the host.
  long long graph_steps = 0, graph_captures = 0, graph_aborted = 0;
  // Stages that ran beside another, each with that stage (AnyStep::stages_beside): their seconds
  // in stage_seconds overlap that stage's. Empty for the host.
  std::vector<std::pair<std::string, std::string>> stages_beside;
  std::vector<FeedCount> feeds;  // each feed's progress at the end (AnyStep::feed_counts)
  double output_seconds = 0;
  std::size_t particle_bytes = 0;   // the step's arrays at the end
  long long peak_memory_bytes = 0;  // the process's peak resident set (getrusage)
  std::vector<std::string> outputs;
  // At the end: the highest point of any particle along -g (the bed_height probe), m; NaN
  // without gravity.
  double bed_height = std::numeric_limits<double>::quiet_NaN();
  long long resumed_from_step = -1;  // the checkpoint's step; -1: a new run
  // The run after its first step, for timing the steps alone: a run's setup (reading a
  // checkpoint, building the walls' grid) and its first step (the first list, the boxes cut and
  // the first ghosts on several ranks) take seconds at a million particles, which a short run's
  // wall_seconds spreads over its steps. steps 0: the run made at most one step.
  struct Steady {
    long long steps = 0;
    double seconds = 0;  // wall-clock, from the end of the first step to the end of the last
    std::vector<std::pair<std::string, double>> stage_seconds;
    // Decomposed: the change in exchange_seconds (the most any rank spent, at the end less at
    // the first step's end) and exchange_bytes.
    double exchange_seconds = 0, exchange_bytes = 0;
    double exchange_vote_seconds = 0, exchange_rebuild_seconds = 0;
  } steady;
  bool interrupted = false;     // stopped by stop_requested before the end
  std::string last_checkpoint;  // the newest checkpoint written (empty: none)
};

// Steps: round(end_time / time_step). Throws StepNotSupported naming the scene item for what
// the production step cannot simulate yet (StepPlan), and for output files that fail.
class ProductionRunner {
 public:
  ProductionRunner(const Scene& scene, ProductionSettings settings);
  ~ProductionRunner();
  ProductionRunner(const ProductionRunner&) = delete;
  ProductionRunner& operator=(const ProductionRunner&) = delete;

  bool done() const;
  void advance();  // one step and its outputs (and its checkpoint when one is due)
  // Stops the run at the present step: writes a checkpoint there when the scene asks for
  // checkpoints (and none is there yet); report().interrupted becomes true.
  void interrupt();
  bool interrupted() const;
  long long step() const;
  const StepPlan& plan() const;
  // The current particles as trajectory rows (world-frame angular velocity).
  std::vector<TrajectoryRow> rows() const;
  std::size_t pair_contacts() const;  // at the last evaluation
  std::size_t wall_contacts() const;
  ProductionReport report() const;
  void report_progress();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

ProductionReport run_production(const Scene& scene, const ProductionSettings& settings);

}  // namespace talus
