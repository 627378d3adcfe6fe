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
#include "solver/scene/scene.hpp"
#include "solver/step/step_plan.hpp"

namespace talus {

struct ProductionProgress {
  long long step = 0, total_steps = 0;
  double time = 0, end_time = 0;  // s
  std::size_t particles = 0;
  std::size_t contacts = 0;  // particle-particle and particle-wall, at the last evaluation
  double wall_seconds = 0;   // since the run started
};

class AnyStep;  // any_step.hpp
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
};

struct ProductionReport {
  std::string backend = "cpu";  // the step's: "cpu" or "cuda"
  int host_threads = 0;         // the host step's threads (backend "cpu"); 0 for another backend
  long long steps = 0;
  double simulated_time = 0;  // s
  double wall_seconds = 0;
  std::size_t particles = 0;
  double mean_contacts = 0;  // particle-particle and particle-wall contacts per step
  std::vector<std::pair<std::string, double>> stage_seconds;  // the plan's stages, in order
  double output_seconds = 0;
  std::size_t particle_bytes = 0;   // the step's arrays at the end
  long long peak_memory_bytes = 0;  // the process's peak resident set (getrusage)
  std::vector<std::string> outputs;
  // At the end: the highest point of any particle along -g (the bed_height probe), m; NaN
  // without gravity.
  double bed_height = std::numeric_limits<double>::quiet_NaN();
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
  void advance();  // one step and its outputs
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
