// A scene run by the reference solver: the scene (solver/scene, the loader both solvers share)
// turned into a RefWorld, stepped to the end time, with the scene's outputs written in the format
// the production solver writes too (solver/io: trajectory frames, run.json, probes, ParaView
// files).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "reference/world/world.hpp"
#include "solver/io/output_schedule.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/run_directory.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/scene.hpp"

namespace talus::reference {

// The RefWorld of a scene at t = 0: its templates, materials and pair rule, the initial
// particles (explicit, lattices, random fills: solver/scene/initial_particles.hpp) with ids in
// that order, its walls (solver/scene/wall_meshes.hpp) with their motion, and its effects.
// `template_of_body` receives, per body, the scene template index (for the trajectory's
// `template` column). Throws SceneError-like std::runtime_error naming the scene item when the
// reference cannot simulate what the scene asks for (the energy probe among them).
RefWorldSetup world_setup(const Scene& scene, std::vector<int>& template_of_body);

// Per-probe-row numbers of a world, in the columns of solver/io/probes.hpp (probe_columns).
std::vector<double> probe_values(const Scene& scene, const RefWorld& world);

// The highest point of any particle along -g (m, measured from the origin): for a polyhedron its
// highest vertex, for a sphere its centre plus radius. 0 without particles. Needs gravity.
double bed_height(const RefWorld& world, const Eigen::Vector3d& gravity);

struct SceneRunProgress {
  long long step = 0, total_steps = 0;
  double time = 0, end_time = 0;  // s
  std::size_t particles = 0;
  std::size_t contacts = 0;  // particle-particle and particle-wall, at the last evaluation
  double wall_seconds = 0;   // since the run started
};

struct SceneRunSettings {
  // Relative output paths of the scene are taken inside this directory; "" = as written.
  std::string output_root;
  // Called about every `progress_interval` seconds of wall time and at the end; may be empty.
  std::function<void(const SceneRunProgress&)> progress;
  double progress_interval = 1.0;
  // An output root with an earlier run's outputs: removed first (true) or refused (false), as
  // for the production runner (solver/io/run_directory.hpp).
  bool overwrite = false;
};

struct SceneRunReport {
  long long steps = 0;
  double simulated_time = 0;  // s
  double wall_seconds = 0;
  std::size_t particles = 0;         // at the end
  double mean_contacts = 0;          // per step
  std::vector<std::string> outputs;  // the files and directories written
};

// A run of a scene, step by step (run_scene drives it; tests step it and look at the world).
// Outputs at step 0, every `every` steps after, and at the last step. Steps: round(end_time /
// time_step). Before each step: closed outlet plates that are due to open go, and feeds insert
// the particles due (ids continue after the initial ones). Throws std::runtime_error naming the
// file or scene item.
class SceneRunner {
 public:
  // The scene must outlive the runner. Creates the output directory and files, writes run.json
  // and step 0's outputs.
  SceneRunner(const Scene& scene, SceneRunSettings settings);
  ~SceneRunner();
  SceneRunner(const SceneRunner&) = delete;
  SceneRunner& operator=(const SceneRunner&) = delete;

  bool done() const { return step_ >= total_steps_; }
  void advance();  // one step and its outputs
  const RefWorld& world() const { return world_; }
  long long step() const { return step_; }
  long long total_steps() const { return total_steps_; }
  // The report so far (run_scene calls it at the end).
  SceneRunReport report() const;
  // Calls settings.progress (when set) with where the run is; advance() calls it about every
  // progress_interval seconds.
  void report_progress();

 private:
  void write_outputs(bool last);

  const Scene& scene_;
  SceneRunSettings settings_;
  std::vector<int> template_of_body_;
  RefWorld world_;
  std::vector<int> polyhedron_slot_;
  std::vector<Feeder> feeders_;
  long long next_id_ = 0;
  std::vector<int> plate_triangles_;  // per wall: the closed plate still present, else 0
  long long step_ = 0, total_steps_ = 0;
  OutputLock lock_;  // the output root, this run's while it lasts; released after the outputs
  std::unique_ptr<OutputSchedule> outputs_;  // trajectories, probes, ParaView
  double contacts_sum_ = 0;
  double started_ = 0, last_progress_ = 0;  // steady-clock seconds
};

// Runs the scene to its end (SceneRunner) and returns the report.
SceneRunReport run_scene(const Scene& scene, const SceneRunSettings& settings);

}  // namespace talus::reference
