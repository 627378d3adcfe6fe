// expected.yaml: each quantity a case checks, its tolerance and the reason for it
// (validation/README.md, "expected.yaml").
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "solver/contact/time_step_advisor.hpp"
#include "solver/io/input_files.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "solver/scene/scene_loader.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

[[noreturn]] void fail(const std::string& file, const YAML::Node& node, const std::string& key,
                       const std::string& what) {
  const YAML::Mark mark = node.Mark();
  std::ostringstream text;
  text << file;
  if (mark.line >= 0) text << ":" << mark.line + 1 << ":" << mark.column + 1;
  text << ": " << key << ": " << what;
  throw ValidationError(text.str());
}

double number(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) fail(file, node, key, "expected a number");
  double value = 0;
  std::istringstream in(node.Scalar());
  in >> value;
  if (!in || !in.eof() || !std::isfinite(value))
    fail(file, node, key, "expected a finite number, got '" + node.Scalar() + "'");
  return value;
}

std::string text(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar() || node.Scalar().empty()) fail(file, node, key, "expected some text");
  return node.Scalar();
}

void only_keys(const std::string& file, const YAML::Node& map, const std::string& where,
               const std::set<std::string>& allowed) {
  for (const auto& entry : map) {
    const std::string key = entry.first.Scalar();
    if (allowed.count(key) == 0) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(file, entry.first, where.empty() ? key : where + "." + key,
           "unknown key; expected one of " + list);
    }
  }
}

ExpectedQuantity quantity(const std::string& file, const std::string& name, const YAML::Node& node,
                          bool has_parameter) {
  const std::string where = "quantities." + name;
  if (!node.IsMap()) fail(file, node, where, "expected a map of unit, description, tolerance...");
  only_keys(file, node, where,
            {"unit", "description", "relative", "absolute", "range", "checked", "reason"});
  ExpectedQuantity q;
  q.name = name;
  for (const char* key : {"unit", "description", "reason"}) {
    if (!node[key]) fail(file, node, where + "." + key, "missing required key");
  }
  q.unit = text(file, node["unit"], where + ".unit");
  q.description = text(file, node["description"], where + ".description");
  q.reason = text(file, node["reason"], where + ".reason");
  if (node["checked"]) {
    const YAML::Node checked = node["checked"];
    if (!checked.IsScalar() || (checked.Scalar() != "true" && checked.Scalar() != "false"))
      fail(file, checked, where + ".checked", "expected true or false");
    q.checked = checked.Scalar() == "true";
  }
  if (node["relative"]) q.tolerance.relative = number(file, node["relative"], where + ".relative");
  if (node["absolute"]) q.tolerance.absolute = number(file, node["absolute"], where + ".absolute");
  if (q.tolerance.relative < 0)
    fail(file, node["relative"], where + ".relative", "expected a number >= 0");
  if (q.tolerance.absolute < 0)
    fail(file, node["absolute"], where + ".absolute", "expected a number >= 0");
  if (q.checked && !(q.tolerance.relative > 0 || q.tolerance.absolute > 0))
    fail(file, node, where,
         "expected a tolerance: relative (a fraction of the expected value) or absolute (in the "
         "quantity's unit), or both, above 0");
  if (node["range"]) {
    const YAML::Node range = node["range"];
    if (!has_parameter)
      fail(file, range, where + ".range", "a range needs the case's swept `parameter` named");
    if (!range.IsSequence() || range.size() != 2)
      fail(file, range, where + ".range", "expected [from, to], the checked parameter values");
    q.ranged = true;
    q.from = number(file, range[0], where + ".range[0]");
    q.to = number(file, range[1], where + ".range[1]");
    if (!(q.from <= q.to)) fail(file, range, where + ".range", "expected from <= to");
  }
  return q;
}

}  // namespace

double Tolerance::bound(double expected) const {
  return std::max(relative * std::abs(expected), absolute);
}

const ExpectedQuantity& Expected::quantity(const std::string& name) const {
  for (const ExpectedQuantity& q : quantities) {
    if (q.name == name) return q;
  }
  throw ValidationError(file + ": quantities." + name +
                        ": missing; the case's checker measures it and needs its tolerance");
}

Expected read_expected(const std::string& path) {
  std::string contents;
  try {
    contents = read_input_file(path);
  } catch (const InputFileError& error) {
    throw ValidationError(std::string(error.what()) + "; every case folder holds expected.yaml");
  }
  YAML::Node root;
  try {
    root = YAML::Load(contents);
  } catch (const YAML::Exception& error) {
    std::ostringstream text;
    text << path << ":" << error.mark.line + 1 << ":" << error.mark.column + 1
         << ": invalid YAML: " << error.msg;
    throw ValidationError(text.str());
  }
  if (!root.IsMap()) fail(path, root, "(top level)", "expected a map with `quantities`");
  only_keys(path, root, "", {"parameter", "quantities"});
  Expected expected;
  expected.file = path;
  if (root["parameter"]) expected.parameter = text(path, root["parameter"], "parameter");
  const YAML::Node list = root["quantities"];
  if (!list) fail(path, root, "quantities", "missing required key");
  if (!list.IsMap() || list.size() == 0)
    fail(path, list, "quantities", "expected a map of quantity name to its tolerance");
  for (const auto& entry : list) {
    expected.quantities.push_back(
        quantity(path, entry.first.Scalar(), entry.second, !expected.parameter.empty()));
  }
  return expected;
}

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::pass:
      return "pass";
    case Verdict::fail:
      return "fail";
    case Verdict::reported:
      return "reported";
  }
  return "reported";
}

const Check& add_check(CaseResult& result, const ExpectedQuantity& quantity, double parameter,
                       double measured, double expected, const std::string& variant,
                       bool report_only) {
  Check check;
  check.quantity = quantity.name;
  check.variant = variant;
  check.unit = quantity.unit;
  check.parameter = parameter;
  check.measured = measured;
  check.expected = expected;
  check.tolerance = quantity.tolerance.bound(expected);
  if (report_only || !quantity.checks(parameter)) {
    check.verdict = Verdict::reported;
  } else {
    // A NaN measured value fails (the comparison is false).
    check.verdict =
        std::abs(measured - expected) <= check.tolerance ? Verdict::pass : Verdict::fail;
  }
  result.checks.push_back(check);
  return result.checks.back();
}

Scene load_case_scene(const std::string& path, CaseResult& result, double time_step) {
  Scene scene = load_scene(path);
  if (time_step > 0) scene.time_step = time_step;
  const std::string name = std::filesystem::path(path).filename().string();
  const TimeStepAdvice advice = advise_time_step(scene);
  refuse_unstable_step(scene, advice);  // a SceneError, as `talus run` gives
  if (advice.limited()) {
    result.notes.push_back(
        fmt::format("{}: time step {:.3g} s, {:.2g} of the critical step "
                    "{:.2g} s ({})",
                    name, scene.time_step, scene.time_step / advice.critical_step,
                    advice.critical_step, advice.describe()));
  } else {
    result.notes.push_back(fmt::format("{}: time step {:.3g} s; no critical step: {}", name,
                                       scene.time_step, advice.describe()));
  }
  for (const std::string& warning : check_initial_state(scene, initial_particles(scene)))
    result.notes.push_back(name + ": " + warning);
  return scene;
}

bool CaseResult::passed() const {
  if (!failure.empty()) return false;
  bool any = false;
  for (const Check& c : checks) {
    if (c.verdict == Verdict::fail) return false;
    any = any || c.verdict == Verdict::pass;
  }
  return any;  // a case that checked nothing has not passed
}

}  // namespace talus::validation
