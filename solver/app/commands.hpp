// The `talus` commands that inspect shapes and contacts. Each returns its whole JSON document as a
// string (nothing is printed until it is complete) and throws UsageError for bad arguments.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "solver/app/render_arguments.hpp"
#include "solver/app/run_arguments.hpp"
#include "solver/app/validate_arguments.hpp"
#include "solver/run/production_run.hpp"

namespace talus {

// `talus overlap A POSE_A B POSE_B`: the exact overlap of two posed polyhedra (paper §2.3), the
// simple contact of BLAZE-DEM (§2.3) and the GJK verdict (paper Algorithm I), side by side.
std::string overlap_json(const std::string& spec_a, const std::string& pose_a,
                         const std::string& spec_b, const std::string& pose_b);

// `talus shape A`: the template built from a spec (paper §2.1) in its body frame.
std::string shape_json(const std::string& spec);

// A run that cannot go ahead as asked (a solver not built in, a setting it does not support).
// main prints the message without the usage and exits with status 2, as for a bad scene file.
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The exit status of a run that --stop-after stopped: EX_TEMPFAIL of sysexits.h, "try again",
// which a driver reads as "resume it".
constexpr int kExitStopped = 75;

// A run stopped at a step boundary by a signal (Ctrl-C: SIGINT, or SIGTERM) or by --stop-after,
// after writing its checkpoint when the scene asks for checkpoints. main writes `summary` (the
// run's JSON summary of the steps made, with "stopped": the message; empty: none) to stdout,
// prints the message (where the run stopped, the checkpoint, how to resume) and exits with
// `exit_status`: 128 + the signal's number, or kExitStopped.
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(const std::string& message, int exit_status, std::string summary = {})
      : std::runtime_error(message), exit_status_(exit_status), summary_(std::move(summary)) {}
  int exit_status() const { return exit_status_; }
  const std::string& summary() const { return summary_; }

 private:
  int exit_status_;
  std::string summary_;
};

// `talus run [options] scene.yaml`: runs the scene, writing its outputs as it goes and progress
// lines on stderr; returns the run's summary as JSON. Throws SceneError for a bad scene file,
// RunError as above (also for a checkpoint that --resume cannot use), RunInterrupted, and
// std::runtime_error for a failure while running (e.g. an unwritable output).
// With no scene path (and no --resume): the built-in scene (solver/scene/builtin_scene.hpp) is
// written to <output root>/scene.yaml (the root defaults to kBuiltinSceneOutput) and run from
// there; then, where OpenCV is built in, its last frame is drawn; the summary adds the final bed
// height beside the paper's and the picture, and a line on stderr says both.
std::string run_json(const RunArguments& args);

// `talus validate [options] [CASE...]`: runs the validation cases (validation/README.md) on the
// production solver's chosen backend, writing their results into the output directory; returns
// the results as JSON and sets `passed` (every case passed). Throws validation::ValidationError
// for an unknown case or a bad expected.yaml, RunError for a backend that cannot run.
std::string validate_json(const ValidateArguments& args, bool& passed);

// `talus accuracy [options]`: the accuracy-against-time study (experiments/accuracy/README.md)
// on the chosen backend, into the output directory's accuracy.csv; returns a summary as JSON.
// Throws UsageError for an unknown scene or knob, RunError for a backend that cannot run.
std::string accuracy_json(const AccuracyArguments& args);

// The production step's maker for `--backend`: the CUDA step where asked (`cuda`, or `auto` with a
// usable device), else the host's; `name` gets "cuda" or "cpu". RunError for `cuda` where no
// device is usable or talus was built without CUDA.
StepFactory step_factory(Backend backend, std::string& name);

// The first line a shell command prints, or "" when it fails.
std::string first_line_of(const std::string& command);

// TALUS_COMMIT where set (a copy of the tree without .git), else the source tree's commit with
// "-dirty" when it has uncommitted changes, else "unknown".
std::string commit_of(const std::string& source);

// `talus render [options] DIR`: pictures of a run (solver/render/render_run.hpp); returns a
// summary as JSON. Throws RunError when talus was built without OpenCV, or for a run directory
// it cannot draw; UsageError for bad options.
std::string render_json(const RenderArguments& args);

}  // namespace talus
