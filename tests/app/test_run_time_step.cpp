// `talus run` and the time-step advisor (solver/contact/time_step_advisor.hpp), through the built
// binary: the line with dt / dt_crit, the refusal of a step above dt_crit naming the scene's
// time.step (for every solver), --allow-unstable-step, `step: auto`, and the summary's numbers.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "solver/contact/time_step_advisor.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/app/run_talus.hpp"
#include "tests/support/json_test_util.hpp"

namespace {

using talus_test::Json;
using talus_test::parse_or_fail;
using talus_test::ProcessResult;
using talus_test::run_talus;
using talus_test::write_scene;

std::string directory(const std::string& name) {
  return talus_test::fresh_directory("test-run-time-step", name);
}

// Two 5.77 mm cubes (E = 5 MPa, density 1200) above a floor under gravity, 3 steps of 10 us;
// CONTACT is replaced by the law. They start apart and do not touch within the run.
const std::string kCubes = R"(time: {step: 1.0e-5, end: 3.0e-5}
materials:
  rubber: {density: 1200, youngs_modulus: 5.0e6, poisson_ratio: 0.3, friction: 0.5,
           restitution: 0.5}
templates:
  cube: {shape: cube:0.01, material: rubber}
particles:
  - explicit:
      - {template: cube, position: [0, 0, 0.01]}
      - {template: cube, position: [0, 0, 0.03]}
walls:
  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: rubber}
effects:
  gravity: [0, 0, -9.81]
  contact: CONTACT
  friction: true
  rotation: true
)";

std::string with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

// The advisor's verdict on a scene file, computed here in-process, as the binary must print it.
talus::TimeStepAdvice advice_for(const std::string& path) {
  return talus::advise_time_step(talus::load_scene(path));
}

// The paper's law as printed at 10 us: refused, exit 2, one line naming the file, line and column
// of time.step, the largest stable step (dt_crit rounded down to two digits), what limits it and
// how to proceed; nothing on stdout, no usage. The reference solver is refused the same way.
TEST(TalusRunTimeStep, StepAboveTheCriticalStepIsRefusedAtTimeStep) {
  const std::string dir = directory("refused");
  const std::string scene = write_scene(dir, with(kCubes, "CONTACT", "volume_paper"));
  const talus::TimeStepAdvice advice = advice_for(scene);
  ASSERT_LT(advice.critical_step, 1e-8);  // the issue's case: nanoseconds
  const std::string stable = format("%.1e", talus::round_down_two_digits(advice.critical_step));
  const std::string expected =
      "talus: error: " + scene + ":1:14: time.step: 1e-05 s is above the largest stable step " +
      stable +
      " s for cube-cube contacts (contact: volume_paper); write "
      "time.step <= " +
      stable + " or step: auto, or pass --allow-unstable-step to run anyway\n";
  for (const char* solver : {"production", "reference"}) {
    const ProcessResult run =
        run_talus({"run", "--solver", solver, "--backend", "cpu", "--output", dir, scene});
    EXPECT_EQ(run.exit_code, 2) << solver << "\n" << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
    // The line before the error is the advisor's report; the error is the last line.
    const std::size_t error = run.err.find("talus: error: ");
    ASSERT_NE(error, std::string::npos) << run.err;
    EXPECT_EQ(run.err.substr(error), expected) << solver;
    EXPECT_EQ(run.err.find("usage:"), std::string::npos) << run.err;
  }
  std::printf("refused: %s", expected.c_str());
}

// --allow-unstable-step runs it after a warning line; the summary says how far above it is.
TEST(TalusRunTimeStep, AllowUnstableStepRunsWithAWarning) {
  const std::string dir = directory("allowed");
  const std::string scene = write_scene(dir, with(kCubes, "CONTACT", "volume_paper"));
  const talus::TimeStepAdvice advice = advice_for(scene);
  const ProcessResult run = run_talus(
      {"run", "--allow-unstable-step", "--backend", "cpu", "--quiet", "--output", dir, scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string stable = format("%.1e", talus::round_down_two_digits(advice.critical_step));
  EXPECT_NE(run.err.find("talus run: warning: time step 1e-05 s is above the largest stable step " +
                         stable +
                         " s for cube-cube contacts (contact: volume_paper); running anyway "
                         "(--allow-unstable-step)\n"),
            std::string::npos)
      << run.err;
  Json summary = parse_or_fail(run.out);
  EXPECT_EQ(summary["steps"].get<double>(), 3);
  // 17 digits carry the doubles exactly.
  EXPECT_EQ(summary["critical_time_step"].get<double>(), advice.critical_step);
  EXPECT_EQ(summary["time_step_ratio"].get<double>(), 1.0e-5 / advice.critical_step);
  EXPECT_GT(summary["time_step_ratio"].get<double>(), 1e3);
}

// The default law accepts 10 us for these cubes (dt_crit 1.4e-5 s) and says so in one line.
TEST(TalusRunTimeStep, AcceptedStepIsReportedAgainstTheCriticalStep) {
  const std::string dir = directory("accepted");
  const std::string scene = write_scene(dir, with(kCubes, "CONTACT", "volume"));
  const talus::TimeStepAdvice advice = advice_for(scene);
  ASSERT_GT(advice.critical_step, 1e-5);
  const ProcessResult run = run_talus({"run", "--backend", "cpu", "--output", dir, scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string line =
      format("talus run: time step 1e-05 s = %.2g of the critical step %.1e s (",
             1e-5 / advice.critical_step, advice.critical_step) +
      "cube-cube contacts, contact: volume; Rayleigh time " + format("%.1e", advice.rayleigh_time) +
      " s)\n";
  EXPECT_NE(run.err.find(line), std::string::npos) << line << "\n" << run.err;
  Json summary = parse_or_fail(run.out);
  EXPECT_EQ(summary["time_step"].get<double>(), 1.0e-5);
  EXPECT_EQ(summary["critical_time_step"].get<double>(), advice.critical_step);
  EXPECT_EQ(summary["time_step_ratio"].get<double>(), 1.0e-5 / advice.critical_step);
  // --quiet drops the line.
  const ProcessResult quiet =
      run_talus({"run", "--backend", "cpu", "--quiet", "--output", dir, scene});
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("time step"), std::string::npos) << quiet.err;
}

// `step: auto` runs at 0.2 dt_crit, the number both the line and the summary give.
TEST(TalusRunTimeStep, AutoStepRunsAtAFifthOfTheCriticalStep) {
  const std::string dir = directory("auto");
  const std::string scene =
      write_scene(dir, with(with(kCubes, "CONTACT", "volume"), "step: 1.0e-5", "step: auto"));
  const talus::TimeStepAdvice advice = advice_for(scene);
  const ProcessResult run = run_talus({"run", "--backend", "cpu", "--output", dir, scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find(format("talus run: time step %.3g s (step: auto) = 0.2 of the critical "
                                "step %.1e s (cube-cube contacts",
                                advice.recommended_step, advice.critical_step)),
            std::string::npos)
      << run.err;
  Json summary = parse_or_fail(run.out);
  EXPECT_EQ(summary["time_step"].get<double>(), advice.recommended_step);
  EXPECT_EQ(summary["time_step"].get<double>(), 0.2 * advice.critical_step);
  EXPECT_EQ(summary["critical_time_step"].get<double>(), advice.critical_step);
}

// Without contacts nothing limits the step: the line says why, the summary has null.
TEST(TalusRunTimeStep, NoContactsNoCriticalStep) {
  const std::string dir = directory("free");
  std::string text = with(kCubes, "  contact: CONTACT\n  friction: true\n", "");
  text = with(text,
              "walls:\n  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, "
              "material: rubber}\n",
              "");
  const std::string scene = write_scene(dir, text);
  const ProcessResult run = run_talus({"run", "--backend", "cpu", "--output", dir, scene});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("talus run: time step 1e-05 s; no critical step: no contacts "
                         "(effects.contact is absent); Rayleigh time "),
            std::string::npos)
      << run.err;
  Json summary = parse_or_fail(run.out);
  EXPECT_TRUE(summary["critical_time_step"].is_null());
  EXPECT_EQ(summary["time_step_ratio"].get<double>(), 0.0);
}

}  // namespace
