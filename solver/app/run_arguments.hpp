// `talus run`'s options, as the command line (command_line.hpp) gives them to run_json.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

enum class SolverKind { production, reference };

struct RunArguments {
  // The scene file; empty: the built-in scene (solver/scene/builtin_scene.hpp), written into
  // the output root and run from there.
  std::string scene_path;
  SolverKind solver = SolverKind::production;  // --solver production|reference
  std::optional<Backend> backend;              // --backend auto|cpu|cuda: overrides the scene's
  std::optional<Precision> precision;          // --precision double|float: overrides the scene's
  // --output DIR: relative output paths of the scene (trajectories, probes) are taken inside DIR
  // instead of the working directory. Empty: the working directory.
  std::string output_root;
  // --threads N: the host backend's threads (N >= 1). 0: OpenMP's default (all cores, or
  // OMP_NUM_THREADS).
  int threads = 0;
  bool quiet = false;  // --quiet: no progress lines on stderr
  // --allow-unstable-step: run a scene whose time step is above the critical step of the
  // time-step advisor (solver/contact/time_step_advisor.hpp) instead of refusing it.
  bool allow_unstable_step = false;
  // --overwrite: a new run into an output root that holds an earlier run's outputs removes them
  // first (solver/io/run_directory.hpp); without it such a run is refused.
  bool overwrite = false;
  // --end T: stop at T seconds instead of the scene's end time (s, > 0; shorter runs).
  std::optional<double> end_time;
  // --stop-after S: stop the run after S seconds of wall-clock time from the command's start, at
  // a step boundary, with a checkpoint, as a stop signal does (exit status 75, kExitStopped), so
  // that a run longer than a sitting goes on with --resume. Rank 0 decides for every rank.
  std::optional<double> stop_after_seconds;
  // --resume PATH: continue the run from the newest checkpoint in the directory PATH, or from the
  // checkpoint file PATH (no scene path; the checkpoint names the scene, the output root and the
  // precision). Empty: a new run.
  std::string resume_directory;
};

const char* to_string(SolverKind solver);

}  // namespace talus
