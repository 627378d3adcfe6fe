// `time.step`: where it was written (the advisor's errors point there), and `step: auto`, which
// the loader resolves to the time-step advisor's recommended step (contact/time_step_advisor.hpp)
// or refuses with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "solver/contact/time_step_advisor.hpp"
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

Scene parse(const std::string& text) {
  return parse_scene(text, "errors.yaml", scene_data_dir());
}

// kValidScene with a second particle, so that two dodecahedra can touch.
std::string two_particles(const std::string& text) {
  return replaced(text, "      - {template: grain, position: [0, 0, 0.05]}\n",
                  "      - {template: grain, position: [0, 0, 0.05]}\n"
                  "      - {template: grain, position: [0, 0, 0.08]}\n");
}

TEST(SceneTimeStep, NumericStepRecordsWhereItWasWritten) {
  const Scene scene = parse(kValidScene);
  EXPECT_FALSE(scene.time_step_auto);
  EXPECT_EQ(scene.time_step, 1.0e-5);
  EXPECT_EQ(scene.time_step_source.file, "errors.yaml");
  EXPECT_EQ(scene.time_step_source.line, 1);
  EXPECT_EQ(scene.time_step_source.column, 14);  // time: {step: 1.0e-5 ...: the value
  EXPECT_EQ(scene.time_step_source.key, "time.step");
}

// `step: auto` is the advisor's recommended step, a fifth of the critical one, the same double
// for every solver that loads the scene.
TEST(SceneTimeStep, AutoTakesTheAdvisorsRecommendedStep) {
  const Scene scene = parse(replaced(two_particles(kValidScene), "step: 1.0e-5", "step: auto"));
  EXPECT_TRUE(scene.time_step_auto);
  const TimeStepAdvice advice = advise_time_step(scene);
  ASSERT_TRUE(advice.limited()) << advice.limit;
  EXPECT_EQ(scene.time_step, advice.recommended_step);
  EXPECT_EQ(scene.time_step, kAutoStepFraction * advice.critical_step);
  EXPECT_EQ(kAutoStepFraction, 0.2);
  EXPECT_EQ(advice.limit, "grain-grain contacts");
  EXPECT_EQ(scene.time_step_source.line, 1);
  EXPECT_EQ(scene.time_step_source.column, 14);
  // Block style, and auto written with the end first: the same.
  const Scene block = parse(replaced(two_particles(kValidScene), "time: {step: 1.0e-5, end: 0.1}",
                                     "time:\n  end: 0.1\n  step: auto"));
  EXPECT_EQ(block.time_step, scene.time_step);
  EXPECT_EQ(block.time_step_source.line, 3);
  EXPECT_EQ(block.time_step_source.column, 9);
}

// auto where nothing limits the step (one particle, no walls; or no contact model): refused at
// time.step with the reason.
TEST(SceneTimeStep, AutoWithoutALimitIsRefused) {
  EXPECT_STREQ(error_with("step: 1.0e-5", "step: auto").what(),
               "errors.yaml:1:14: time.step: auto needs a critical time step, and nothing limits "
               "the step here: no contact can occur (one particle and no walls); write the time "
               "step in s");
  const SceneError no_contact =
      scene_error(replaced(replaced(two_particles(kValidScene), "step: 1.0e-5", "step: auto"),
                           "  contact: volume\n  friction: true\n", ""));
  EXPECT_EQ(no_contact.key(), "time.step");
  EXPECT_NE(no_contact.message().find("no contacts (effects.contact is absent)"), std::string::npos)
      << no_contact.what();
  // The paper's law without gravity or speed: nothing loads a contact.
  const SceneError no_load = scene_error(
      replaced(replaced(replaced(two_particles(kValidScene), "step: 1.0e-5", "step: auto"),
                        "contact: volume", "contact: volume_paper"),
               "  gravity: [0, 0, -9.81]\n", ""));
  EXPECT_NE(no_load.message().find("nothing limits the step here: no load"), std::string::npos)
      << no_load.what();
}

// An auto step longer than the run is an error too (a run of no step).
TEST(SceneTimeStep, AutoLongerThanTheEndIsRefused) {
  const SceneError error =
      scene_error(replaced(two_particles(kValidScene), "time: {step: 1.0e-5, end: 0.1}",
                           "time: {step: auto, end: 1.0e-9}"));
  EXPECT_EQ(error.key(), "time.step");
  EXPECT_EQ(error.line(), 1);
  EXPECT_NE(error.message().find("longer than time.end"), std::string::npos) << error.what();
}

}  // namespace
}  // namespace talus
