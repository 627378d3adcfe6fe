// The validation cases (validation/README.md): each published case runs the production solver
// on its scene, measures the paper's quantities and checks each against its expected value under
// the tolerance that the case's expected.yaml states and justifies. `talus validate` runs them
// (solver/app/validate_command.cpp); run_validation writes validation-results.json, a Markdown
// summary, each case's checks as CSV and, where Python with matplotlib is found, its figure.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/run/any_step.hpp"
#include "solver/scene/scene.hpp"

namespace talus::validation {

// A case that cannot be run as asked (an unknown case, a missing or bad expected.yaml): the
// message names the file, line and key where there is one. `talus validate` exits with 2.
class ValidationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// |measured - expected| <= max(relative |expected|, absolute).
struct Tolerance {
  double relative = 0;
  double absolute = 0;
  double bound(double expected) const;
};

// One quantity of expected.yaml: what it is, its tolerance and why, and the range of the case's
// swept parameter where it is checked (outside it, its error is reported, not checked).
struct ExpectedQuantity {
  std::string name;
  std::string unit;
  std::string description;
  std::string reason;  // why this tolerance
  Tolerance tolerance;
  bool checked = true;  // false: reported only (`checked: false`)
  bool ranged = false;
  double from = 0, to = 0;  // the parameter's checked range, inclusive
  bool checks(double parameter) const {
    return checked && (!ranged || (parameter >= from && parameter <= to));
  }
};

struct Expected {
  std::string file;       // its path, for messages
  std::string parameter;  // the swept parameter's name ("theta_deg"), or empty
  std::vector<ExpectedQuantity> quantities;
  // The quantity of that name; a ValidationError naming the file when it has none.
  const ExpectedQuantity& quantity(const std::string& name) const;
};

// Reads a case's expected.yaml (format: validation/README.md). Throws ValidationError
// "<file>:<line>:<column>: <key>: <what was expected>".
Expected read_expected(const std::string& path);

enum class Verdict { pass, fail, reported };
const char* to_string(Verdict verdict);

struct Check {
  std::string quantity;
  std::string variant;  // which setting of the case it was measured at ("lambda 2"), or empty
  std::string unit;
  double parameter = 0;  // the swept parameter's value (0 for a case without one)
  double measured = 0;
  double expected = 0;
  double tolerance = 0;  // the absolute bound applied (Tolerance::bound)
  Verdict verdict = Verdict::reported;
};

struct CaseResult {
  std::string name;
  std::string title;
  std::string backend;  // "cpu" or "cuda"
  bool full = false;
  double wall_seconds = 0;
  std::vector<Check> checks;
  std::vector<std::string> notes;  // lines for the summary: what was run, what was seen
  std::string failure;             // a case that could not finish (the run failed): why
  std::string figure;              // the PNG, relative to the output directory; empty if none
  bool passed() const;
};

// Adds a check of `measured` against `expected` under the quantity's tolerance: pass or fail
// where the quantity checks `parameter`, reported elsewhere (or always, with `report_only`).
// Returns it.
const Check& add_check(CaseResult& result, const ExpectedQuantity& quantity, double parameter,
                       double measured, double expected, const std::string& variant = "",
                       bool report_only = false);

// The serial reference solver's run of a scene, where talus is built with it: `steps` steps,
// calling `sample` with the step number and the particles after every `every`-th. Empty without
// the reference solver (validate_command.cpp sets it).
using ReferenceRun = std::function<void(
    const Scene& scene, long long steps, long long every,
    const std::function<void(long long step, const std::vector<TrajectoryRow>&)>& sample)>;

// What a case is given: where its folder and its outputs are, which version, and the backend's
// step for a scene.
struct CaseContext {
  std::string case_directory;    // validation/<case>/
  std::string output_directory;  // <output>/<case>/, created
  bool full = false;
  bool quiet = false;
  std::string backend;  // "cpu" or "cuda"
  std::function<std::unique_ptr<AnyStep>(const Scene&)> make_step;
  ReferenceRun run_reference;  // empty: no reference solver in this talus
  Expected expected;
};

// The scene at `path` as `talus run` takes it: loaded (SceneError), its time step (`time_step`
// where given, > 0, else the file's) checked by the advisor (above it, the SceneError of `talus
// run`, refuse_unstable_step; a note of dt / dt_crit otherwise) and its initial particles
// checked (warnings become notes). Notes name the file by its name alone.
Scene load_case_scene(const std::string& path, CaseResult& result, double time_step = 0);

// A picture of `rows` as talus render draws them (`normal` colouring: shaded as a camera sees
// them), looking along `view` (projection.hpp's names), fit to the particles with 16 px to spare,
// the scene's walls at `time` outlined; written to `path` as PNG. False, with nothing written,
// where talus is built without OpenCV.
bool write_particle_picture(const Scene& scene, const std::vector<TrajectoryRow>& rows, double time,
                            const std::string& view, int width, int height,
                            const std::string& path);

struct ValidationCase {
  const char* name;  // its folder under validation/
  const char* title;
  // What its checker measures: expected.yaml gives each one's tolerance, and no other.
  std::vector<std::string> quantities;
  // Fills `result`'s checks and notes (name, backend and time are the runner's); throws what a
  // run throws (SceneError, std::runtime_error) when it cannot finish.
  void (*run)(const CaseContext& context, CaseResult& result);
};

// Every case, in the order `talus validate` runs them.
const std::vector<ValidationCase>& validation_cases();

struct ValidationOptions {
  std::vector<std::string> cases;  // names; empty: all
  bool full = false;
  bool quiet = false;
  std::string cases_directory;  // the folder that holds the case folders (validation/)
  std::string output_directory;
  std::string backend;  // "cpu" or "cuda", as chosen by the caller
  std::function<std::unique_ptr<AnyStep>(const Scene&)> make_step;
  ReferenceRun run_reference;  // for the cases that also check the reference solver
  std::string commit;          // recorded in the results
  std::string python;          // the interpreter for the figures; empty: none drawn
};

struct ValidationRun {
  std::vector<CaseResult> cases;
  std::string results_file;  // validation-results.json
  std::string summary_file;  // validation-summary.md
  bool passed() const;
};

// Runs the cases and writes the results (validation/README.md, "Running"). Throws
// ValidationError for an unknown case or a bad expected.yaml, before any case runs.
ValidationRun run_validation(const ValidationOptions& options);

// The results as JSON text (validation-results.json) and as Markdown.
std::string results_json(const ValidationRun& run, const ValidationOptions& options);
std::string summary_markdown(const ValidationRun& run, const ValidationOptions& options);

// The checks as CSV (case's checks.csv; the figure scripts read it): quantity, variant, unit,
// parameter, measured, expected, tolerance, verdict; 17 digits.
std::string checks_csv(const CaseResult& result);

}  // namespace talus::validation
