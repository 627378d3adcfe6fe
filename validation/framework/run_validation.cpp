// Running the validation cases and writing their results (validation/README.md, "Running").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <sys/wait.h>

#include "solver/io/json.hpp"
#include "solver/io/output_files.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

// `text` as one word for sh: in single quotes, each ' written '\''.
std::string shell_word(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string fixed(double value) {
  return fmt::format("{:.6g}", value);
}

const ValidationCase& find_case(const std::string& name) {
  std::string known;
  for (const ValidationCase& c : validation_cases()) {
    if (name == c.name) return c;
    known += (known.empty() ? "" : ", ") + std::string(c.name);
  }
  throw ValidationError("unknown validation case '" + name + "'; expected one of " + known);
}

// The case's figure: figure.py in its folder reads checks.csv and writes figure.png. A figure
// that cannot be drawn is a note, not a failure of the case.
void draw_figure(const ValidationOptions& options, const CaseContext& context, CaseResult& result) {
  const std::string script = joined_path(context.case_directory, "figure.py");
  if (options.python.empty() || !std::filesystem::exists(script)) return;
  const std::string csv = joined_path(context.output_directory, "checks.csv");
  const std::string png = joined_path(context.output_directory, "figure.png");
  std::remove(png.c_str());  // an earlier run's figure must not stand for this one
  const std::string command =
      shell_word(options.python) + " " + shell_word(script) + " " + shell_word(csv) + " " +
      shell_word(png) + " " + shell_word(result.title) + " > " +
      shell_word(joined_path(context.output_directory, "figure.log")) + " 2>&1";
  const int status = std::system(command.c_str());
  if (status == 0 && std::filesystem::exists(png)) {
    result.figure = result.name + "/figure.png";
  } else {
    const int code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : status;
    result.notes.push_back(
        fmt::format("figure not drawn: {} {} exited with {} (its output: {}/figure.log)",
                    options.python, script, code, result.name));
  }
}

std::size_t count(const CaseResult& r, Verdict v) {
  std::size_t n = 0;
  for (const Check& c : r.checks) n += c.verdict == v ? 1 : 0;
  return n;
}

}  // namespace

bool ValidationRun::passed() const {
  for (const CaseResult& c : cases) {
    if (!c.passed()) return false;
  }
  return !cases.empty();
}

std::string checks_csv(const CaseResult& result) {
  std::string text = "quantity,variant,unit,parameter,measured,expected,tolerance,verdict\n";
  for (const Check& c : result.checks) {
    text += c.quantity + "," + c.variant + "," + c.unit + "," + exact_decimal(c.parameter) + "," +
            exact_decimal(c.measured) + "," + exact_decimal(c.expected) + "," +
            exact_decimal(c.tolerance) + "," + to_string(c.verdict) + "\n";
  }
  return text;
}

std::string results_json(const ValidationRun& run, const ValidationOptions& options) {
  Json json;
  json["commit"] = options.commit;
  json["backend"] = options.backend;
  json["version"] = options.full ? "full" : "small";
  json["passed"] = run.passed();
  Json cases = Json::array();
  Json rows = Json::array();
  for (const CaseResult& r : run.cases) {
    Json c;
    c["case"] = r.name;
    c["title"] = r.title;
    c["passed"] = r.passed();
    c["backend"] = r.backend;
    c["wall_seconds"] = r.wall_seconds;
    c["checks_passed"] = count(r, Verdict::pass);
    c["checks_failed"] = count(r, Verdict::fail);
    c["reported"] = count(r, Verdict::reported);
    if (!r.failure.empty()) c["failure"] = r.failure;
    c["figure"] = r.figure.empty() ? Json(nullptr) : Json(r.figure);
    c["notes"] = r.notes;
    cases.push_back(c);
    for (const Check& k : r.checks) {
      Json row;
      row["case"] = r.name;
      row["quantity"] = k.quantity;
      if (!k.variant.empty()) row["variant"] = k.variant;
      row["unit"] = k.unit;
      row["parameter"] = k.parameter;
      row["measured"] = k.measured;
      row["expected"] = k.expected;
      row["tolerance"] = k.tolerance;
      row["pass"] =
          k.verdict == Verdict::reported ? Json(nullptr) : Json(k.verdict == Verdict::pass);
      row["verdict"] = to_string(k.verdict);
      row["backend"] = r.backend;
      row["wall_seconds"] = r.wall_seconds;
      row["commit"] = options.commit;
      rows.push_back(row);
    }
  }
  json["cases"] = cases;
  json["results"] = rows;
  return json_text(json);
}

std::string summary_markdown(const ValidationRun& run, const ValidationOptions& options) {
  std::ostringstream md;
  md << "# Validation: " << (run.passed() ? "all cases pass" : "FAILED") << "\n\n";
  md << "Commit `" << options.commit << "`, backend `" << options.backend << "`, "
     << (options.full ? "full" : "small") << " versions. `validation-results.json` holds every "
     << "number below; each case's `checks.csv` its rows.\n\n";
  md << "| case | result | checks passed | failed | reported only | wall time |\n";
  md << "|---|---|---|---|---|---|\n";
  for (const CaseResult& r : run.cases) {
    md << "| " << r.name << " | " << (r.passed() ? "pass" : "**FAIL**") << " | "
       << count(r, Verdict::pass) << " | " << count(r, Verdict::fail) << " | "
       << count(r, Verdict::reported) << " | " << fmt::format("{:.1f} s", r.wall_seconds) << " |\n";
  }
  for (const CaseResult& r : run.cases) {
    md << "\n## " << r.title << "\n\n";
    if (!r.failure.empty()) md << "**The case did not finish:** " << r.failure << "\n\n";
    for (const std::string& note : r.notes) md << "- " << note << "\n";
    if (!r.notes.empty()) md << "\n";
    if (!r.figure.empty()) md << "![" << r.name << "](" << r.figure << ")\n\n";
    if (r.checks.empty()) continue;
    // Each quantity (and setting): its verdicts and its largest error against its tolerance.
    struct Worst {
      std::string unit;
      std::size_t pass = 0, fail = 0, reported = 0;
      const Check* worst = nullptr;  // of the checked ones, the largest |error| / tolerance
    };
    std::vector<std::pair<std::string, Worst>> by;
    for (const Check& k : r.checks) {
      const std::string key = k.quantity + (k.variant.empty() ? "" : ", " + k.variant);
      auto at = std::find_if(by.begin(), by.end(), [&](const auto& b) { return b.first == key; });
      if (at == by.end()) at = by.insert(by.end(), {key, Worst{}});
      Worst& w = at->second;
      w.unit = k.unit;
      (k.verdict == Verdict::pass ? w.pass : k.verdict == Verdict::fail ? w.fail : w.reported)++;
      const auto ratio = [](const Check& c) {
        return std::abs(c.measured - c.expected) / c.tolerance;
      };
      if (k.verdict != Verdict::reported && (!w.worst || !(ratio(k) <= ratio(*w.worst))))
        w.worst = &k;
    }
    md << "| quantity | passed | failed | reported | largest checked error | its tolerance | at "
          "parameter |\n";
    md << "|---|---|---|---|---|---|---|\n";
    for (const auto& [key, w] : by) {
      md << "| " << key << " (" << w.unit << ") | " << w.pass << " | " << w.fail << " | "
         << w.reported << " | ";
      if (w.worst) {
        md << fixed(w.worst->measured - w.worst->expected) << " | " << fixed(w.worst->tolerance)
           << " | " << fixed(w.worst->parameter) << " |\n";
      } else {
        md << "— | — | — |\n";
      }
    }
    // Every check where there are few, else the failed ones (checks.csv holds them all).
    const bool all = r.checks.size() <= 40;
    bool header = false;
    for (const Check& k : r.checks) {
      if (!all && k.verdict != Verdict::fail) continue;
      if (!header) {
        md << "\n" << (all ? "Every check:" : "The failed checks:") << "\n\n";
        md << "| quantity | parameter | measured | expected | error | tolerance | verdict |\n";
        md << "|---|---|---|---|---|---|---|\n";
        header = true;
      }
      md << "| " << k.quantity << (k.variant.empty() ? "" : ", " + k.variant) << " (" << k.unit
         << ") | " << fixed(k.parameter) << " | " << fixed(k.measured) << " | " << fixed(k.expected)
         << " | " << fixed(k.measured - k.expected) << " | " << fixed(k.tolerance) << " | "
         << (k.verdict == Verdict::fail ? "**fail**" : to_string(k.verdict)) << " |\n";
    }
  }
  return md.str();
}

ValidationRun run_validation(const ValidationOptions& options) {
  // Every case and its expected values first, so that a typo stops the run before any case.
  std::vector<const ValidationCase*> chosen;
  if (options.cases.empty()) {
    for (const ValidationCase& c : validation_cases()) chosen.push_back(&c);
  } else {
    for (const std::string& name : options.cases) chosen.push_back(&find_case(name));
  }
  std::vector<CaseContext> contexts;
  for (const ValidationCase* c : chosen) {
    CaseContext context;
    context.case_directory = joined_path(options.cases_directory, c->name);
    if (!std::filesystem::exists(context.case_directory))
      throw ValidationError("case '" + std::string(c->name) + "': its folder " +
                            context.case_directory +
                            " does not exist; --cases names the folder that holds the cases");
    context.expected = read_expected(joined_path(context.case_directory, "expected.yaml"));
    std::string measured;
    for (const std::string& q : c->quantities) {
      context.expected.quantity(q);  // throws when expected.yaml lacks it
      measured += (measured.empty() ? "" : ", ") + q;
    }
    for (const ExpectedQuantity& q : context.expected.quantities) {
      if (std::find(c->quantities.begin(), c->quantities.end(), q.name) == c->quantities.end())
        throw ValidationError(context.expected.file + ": quantities." + q.name +
                              ": the case's checker does not measure it; it measures " + measured);
    }
    context.output_directory = joined_path(options.output_directory, c->name);
    context.full = options.full;
    context.quiet = options.quiet;
    context.backend = options.backend;
    context.make_step = options.make_step;
    context.run_reference = options.run_reference;
    contexts.push_back(std::move(context));
  }
  create_output_directory(options.output_directory, "validation output directory (--output)");
  ValidationRun run;
  run.results_file = joined_path(options.output_directory, "validation-results.json");
  run.summary_file = joined_path(options.output_directory, "validation-summary.md");
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const ValidationCase& c = *chosen[i];
    const CaseContext& context = contexts[i];
    create_output_directory(context.output_directory, "case output directory");
    CaseResult result;
    result.name = c.name;
    result.title = c.title;
    result.backend = options.backend;
    result.full = options.full;
    const auto start = std::chrono::steady_clock::now();
    try {
      c.run(context, result);
    } catch (const std::exception& error) {
      result.failure = error.what();
    }
    result.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_file_atomically(joined_path(context.output_directory, "checks.csv"), checks_csv(result));
    draw_figure(options, context, result);
    if (!options.quiet) {
      std::fprintf(stderr,
                   "talus validate: %s: %s (%zu passed, %zu failed, %zu reported; %.1f s)%s%s\n",
                   c.name, result.passed() ? "pass" : "FAIL", count(result, Verdict::pass),
                   count(result, Verdict::fail), count(result, Verdict::reported),
                   result.wall_seconds, result.failure.empty() ? "" : ": ", result.failure.c_str());
    }
    run.cases.push_back(std::move(result));
    // After each case, so that an interrupted run keeps the cases it finished.
    write_file_atomically(run.results_file, results_json(run, options));
    write_file_atomically(run.summary_file, summary_markdown(run, options));
  }
  return run;
}

}  // namespace talus::validation
