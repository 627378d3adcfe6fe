// The accuracy-against-time study (experiments/accuracy/README.md): each fidelity knob of talus
// (contact law, shape resolution, wall-mesh resolution, precision, time step, neighbour-list
// skin) set in turn on the same scenes (the method paper's §3.1 impact, §3.3 packing and a
// quasi-2D drum), each setting's error against a stated reference beside the wall time it took
// per simulated second. `talus accuracy` runs it (solver/app/accuracy_command.cpp) on either
// backend and writes accuracy.csv, which reports/generate.py draws.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solver/run/any_step.hpp"
#include "solver/scene/scene.hpp"

namespace talus::accuracy {

// The knobs and scenes, in the order the study runs them.
const std::vector<std::string>& knob_names();   // contact_law, shape_resolution, ...
const std::vector<std::string>& scene_names();  // impact, packing, drum

struct StudyOptions {
  std::vector<std::string> scenes;  // empty: every scene
  std::vector<std::string> knobs;   // empty: every knob
  bool quick = false;               // CI's size: fewer particles, shorter runs, fewer settings
  bool quiet = false;               // no line per run on stderr
  std::string output_directory;     // created; accuracy.csv and the scenes run go there
  std::string backend;              // "cpu" or "cuda"
  std::function<std::unique_ptr<AnyStep>(const Scene&)> make_step;
  // Provenance, written as the CSV's leading comment lines.
  std::string commit, machine, command, date;
};

// One setting of one knob on one scene.
struct Row {
  std::string knob, setting;
  double value = 0;  // orders the settings: sides, dt, segments, skin (0 where none)
  std::string scene, metric, reference;
  double error = 0;  // dimensionless, >= 0; NaN where not measured (the reference itself)
  double wall_seconds = 0, simulated_seconds = 0;
  long long steps = 0;
  std::size_t particles = 0;
  std::string precision;  // "double" or "float"
};

struct StudyResult {
  std::vector<Row> rows;
  // Per scene, the error between two runs of its reference setting that differ only in the
  // random placement's seed: what the other errors stand out from (NaN for the impact, which
  // has no randomness).
  std::vector<std::pair<std::string, double>> noise;
  std::vector<std::string> notes;  // per scene, what its reference run cost
  std::string csv_file;
};

// Runs the study, rewriting accuracy.csv after every run (an interrupted study keeps the rows it
// finished). Throws std::invalid_argument for an unknown scene or knob, before anything runs;
// what a run throws (SceneError) otherwise.
StudyResult run_study(const StudyOptions& options);

// The CSV: `# key: value` provenance lines, then knob,setting,value,scene,metric,reference,
// error,wall_seconds,simulated_seconds,steps,particles,precision.
std::string study_csv(const StudyResult& result, const StudyOptions& options);

}  // namespace talus::accuracy
