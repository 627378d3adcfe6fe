// The validation framework (validation/framework/): tolerances and verdicts, expected.yaml, the
// results files, and a real case run through run_validation on the host step.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "solver/io/json.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

std::string temp_dir(const std::string& name) {
  const std::string dir = std::string(TALUS_BINARY_DIR) + "/test-validation/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string write(const std::string& dir, const std::string& text) {
  const std::string path = dir + "/expected.yaml";
  std::ofstream(path) << text;
  return path;
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

ExpectedQuantity ranged_quantity() {
  ExpectedQuantity q;
  q.name = "omega";
  q.unit = "rad/s";
  q.tolerance = {0.05, 2.0};
  q.ranged = true;
  q.from = 10;
  q.to = 60;
  return q;
}

TEST(ValidationTolerance, IsTheLargerOfRelativeAndAbsolute) {
  const Tolerance t{0.05, 2.0};
  EXPECT_DOUBLE_EQ(t.bound(100), 5.0);  // 5 % of 100 beats 2
  EXPECT_DOUBLE_EQ(t.bound(-10), 2.0);  // near zero the absolute bound holds
  EXPECT_DOUBLE_EQ(t.bound(0), 2.0);
}

TEST(ValidationCheck, PassesFailsOrReportsByToleranceAndRange) {
  CaseResult r;
  const ExpectedQuantity q = ranged_quantity();
  EXPECT_EQ(add_check(r, q, 30, 104.9, 100).verdict, Verdict::pass);    // 4.9 <= 5
  EXPECT_EQ(add_check(r, q, 30, 105.1, 100).verdict, Verdict::fail);    // 5.1 > 5
  EXPECT_EQ(add_check(r, q, 30, 1.9, 0).verdict, Verdict::pass);        // within 2 of 0
  EXPECT_EQ(add_check(r, q, 70, 500, 100).verdict, Verdict::reported);  // outside 10-60
  EXPECT_EQ(add_check(r, q, 10, 200, 100).verdict, Verdict::fail);      // the range is inclusive
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(add_check(r, q, 30, nan, 100).verdict, Verdict::fail);  // NaN never passes
  EXPECT_DOUBLE_EQ(r.checks[0].tolerance, 5.0);
  EXPECT_EQ(r.checks[0].unit, "rad/s");
}

TEST(ValidationCase, PassesOnlyWithAPassingCheckAndNoFailure) {
  const ExpectedQuantity q = ranged_quantity();
  CaseResult empty;
  EXPECT_FALSE(empty.passed());  // a case that checked nothing has not passed
  CaseResult reported_only;
  add_check(reported_only, q, 80, 1, 1);
  EXPECT_FALSE(reported_only.passed());
  CaseResult good;
  add_check(good, q, 20, 100, 100);
  add_check(good, q, 80, 1e9, 1);  // reported: does not fail the case
  EXPECT_TRUE(good.passed());
  good.failure = "the run failed";
  EXPECT_FALSE(good.passed());
  CaseResult bad;
  add_check(bad, q, 20, 100, 100);
  add_check(bad, q, 20, 200, 100);
  EXPECT_FALSE(bad.passed());
}

TEST(ValidationExpected, ReadsQuantitiesTolerancesAndRanges) {
  const std::string dir = temp_dir("read");
  const Expected e =
      read_expected(write(dir,
                          "parameter: theta_deg\n"
                          "quantities:\n"
                          "  omega:\n"
                          "    unit: rad/s\n"
                          "    description: the spin\n"
                          "    relative: 0.05\n"
                          "    absolute: 7.4\n"
                          "    range: [10, 60]\n"
                          "    reason: because\n"
                          "  v: {unit: m/s, description: d, reason: r, absolute: 0.02}\n"));
  EXPECT_EQ(e.parameter, "theta_deg");
  ASSERT_EQ(e.quantities.size(), 2u);
  const ExpectedQuantity& omega = e.quantity("omega");
  EXPECT_DOUBLE_EQ(omega.tolerance.relative, 0.05);
  EXPECT_DOUBLE_EQ(omega.tolerance.absolute, 7.4);
  EXPECT_TRUE(omega.ranged);
  EXPECT_DOUBLE_EQ(omega.from, 10);
  EXPECT_DOUBLE_EQ(omega.to, 60);
  EXPECT_EQ(omega.reason, "because");
  EXPECT_FALSE(e.quantity("v").ranged);
  EXPECT_DOUBLE_EQ(e.quantity("v").tolerance.relative, 0);
  EXPECT_THROW(e.quantity("nothing"), ValidationError);
}

// Each bad file: the message names the file, the line and column, the key and what was expected.
TEST(ValidationExpected, RefusesBadFilesNamingLineAndKey) {
  const std::string dir = temp_dir("bad");
  const auto message = [&](const std::string& text) {
    try {
      read_expected(write(dir, text));
    } catch (const ValidationError& error) {
      return std::string(error.what());
    }
    return std::string("(no error)");
  };
  const std::string file = dir + "/expected.yaml";
  EXPECT_EQ(message("quantities:\n  v: {unit: m/s, description: d, reason: r, relative: -1}\n"),
            file + ":2:55: quantities.v.relative: expected a number >= 0");
  EXPECT_EQ(message("quantities:\n  v: {unit: m/s, description: d, relative: 0.1}\n"),
            file + ":2:6: quantities.v.reason: missing required key");
  EXPECT_EQ(message("quantites:\n  v: {}\n"),
            file + ":1:1: quantites: unknown key; expected one of parameter, quantities");
  EXPECT_EQ(message("parameter: t\nquantities:\n  v: {unit: m/s, description: d, reason: r, "
                    "relative: 0.1, range: [2, 1]}\n"),
            file + ":3:67: quantities.v.range: expected from <= to");
  // yaml-cpp's own words after the prefix differ between its versions.
  EXPECT_EQ(message("quantities: [\n").rfind(file + ":2:1: invalid YAML: ", 0), 0u);
  EXPECT_EQ(message("quantities: {}\n"),
            file + ":1:13: quantities: expected a map of quantity name to its tolerance");
}

TEST(ValidationResults, CsvAndJsonCarryEveryCheck) {
  CaseResult r;
  r.name = "demo";
  r.title = "Demo";
  r.backend = "cpu";
  const ExpectedQuantity q = ranged_quantity();
  add_check(r, q, 20, 101, 100);
  add_check(r, q, 70, 1, 2);
  const std::string csv = checks_csv(r);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "quantity,variant,unit,parameter,measured,expected,tolerance,verdict");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  ValidationRun run;
  run.cases.push_back(r);
  ValidationOptions options;
  options.backend = "cpu";
  options.commit = "abc";
  const Json json = parse_json(results_json(run, options), "results");
  EXPECT_EQ(json["passed"], true);
  ASSERT_EQ(json["results"].size(), 2u);
  EXPECT_EQ(json["results"][0]["pass"], true);
  EXPECT_TRUE(json["results"][1]["pass"].is_null());  // reported, not checked
  EXPECT_EQ(json["results"][1]["verdict"], "reported");
  EXPECT_EQ(json["results"][0]["commit"], "abc");
  EXPECT_EQ(json["cases"][0]["checks_passed"], 1);
  const std::string md = summary_markdown(run, options);
  EXPECT_NE(md.find("| demo | pass | 1 | 0 | 1 |"), std::string::npos) << md;
}

// The free fall case, run through the framework on the host step: its files are written and every
// one of its 40 checks (speed and drop every 0.1 s to 2 s) passes.
TEST(ValidationRun, FreeFallCaseRunsOnTheHostAndPasses) {
  ValidationOptions options;
  options.cases = {"free_fall_drag"};
  options.cases_directory = std::string(TALUS_SOURCE_DIR) + "/validation";
  options.output_directory = temp_dir("run");
  options.backend = "cpu";
  options.make_step = [](const Scene& scene) { return make_host_step(scene, 1); };
  options.quiet = true;
  const ValidationRun run = run_validation(options);
  ASSERT_EQ(run.cases.size(), 1u);
  EXPECT_TRUE(run.cases[0].passed()) << run.cases[0].failure;
  EXPECT_EQ(run.cases[0].checks.size(), 40u);
  EXPECT_TRUE(std::filesystem::exists(run.results_file));
  EXPECT_NE(read(run.summary_file).find("all cases pass"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(options.output_directory + "/free_fall_drag/checks.csv"));
  options.cases = {"no_such_case"};
  EXPECT_THROW(run_validation(options), ValidationError);
}

}  // namespace
}  // namespace talus::validation
