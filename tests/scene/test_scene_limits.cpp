// Counts derived from real numbers are refused above their limits (solver/scene/scene_limits.hpp)
// with a message naming the key and the limit, never converted with an overflow: each case is
// kValidScene (scene_test_util.hpp) with one edit, and the boundary values on either side of
// each limit are checked, so an off-by-one in a limit fails here.
#include <cmath>

#include "solver/scene/scene_limits.hpp"
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

const std::string kOneParticle = "      - {template: grain, position: [0, 0, 0.05]}\n";

// kValidScene with `entry` added to its particle list (at line 17).
std::string with_entry(const std::string& entry) {
  return replaced(kValidScene, kOneParticle, kOneParticle + entry);
}

// The error of kValidScene with `entry` added.
SceneError entry_error(const std::string& entry) {
  return scene_error(with_entry(entry));
}

void expect_key_and_message(const SceneError& e, const std::string& key,
                            const std::string& message) {
  EXPECT_EQ(e.key(), key) << e.what();
  EXPECT_EQ(e.message(), message) << e.what();
}

Scene parse(const std::string& text) {
  return parse_scene(text, "errors.yaml", scene_data_dir());
}

TEST(SceneLimits, DescribesLimitsByTheirPowerOfTwo) {
  EXPECT_EQ(describe_limit(kMaxSteps), "2^53 = 9007199254740992");
  EXPECT_EQ(describe_limit(kMaxParticles), "2^31 - 1 = 2147483647");
  EXPECT_EQ(describe_limit(kMaxSeed), "2^63 - 1 = 9223372036854775807");
  EXPECT_EQ(describe_limit(1000), "1000");
}

TEST(SceneLimits, EndTimeOfMoreThan2To53StepsIsRefusedAtTimeEnd) {
  // Once: llround(1e300 / 1e-5) overflowed and the run did 0 steps with exit status 0.
  EXPECT_STREQ(error_with("end: 0.1", "end: 1e300").what(),
               "errors.yaml:1:27: time.end: an end time of 1e+300 s is 1e+305 steps of 1e-05 s, "
               "above the limit of 2^53 = 9007199254740992 steps (the step index and the time "
               "stay exact in a double up to it)");
  // With a step of 1 s the count is the end time: 2^53 steps pass, 2^53 + 2 do not (2^53 + 1 is
  // not a double).
  EXPECT_EQ(scene_step_count(parse(replaced(kValidScene, "{step: 1.0e-5, end: 0.1}",
                                            "{step: 1, end: 9007199254740992}"))),
            kMaxSteps);
  const SceneError above =
      error_with("{step: 1.0e-5, end: 0.1}", "{step: 1, end: 9007199254740994}");
  EXPECT_EQ(above.key(), "time.end");
  EXPECT_EQ(above.message().rfind("an end time of 9.0072e+15 s is 9.01e+15 steps of 1 s, above "
                                  "the limit of 2^53",
                                  0),
            0u)
      << above.what();
  // With step: auto the count is checked once the step is known, at time.step (a second
  // particle, so that contacts limit the step).
  const SceneError automatic =
      scene_error(replaced(with_entry("      - {template: grain, position: [0, 0, 0.2]}\n"),
                           "{step: 1.0e-5, end: 0.1}", "{step: auto, end: 1e300}"));
  EXPECT_EQ(automatic.key(), "time.step");
  EXPECT_EQ(automatic.message().rfind("with step: auto, an end time of 1e+300 s is ", 0), 0u)
      << automatic.what();
  // A tiny step under a long end: the ratio is inf, still refused (not a wrapped count).
  EXPECT_EQ(error_with("{step: 1.0e-5, end: 0.1}", "{step: 1e-300, end: 1e300}").key(), "time.end");
}

TEST(SceneLimits, CheckedStepCountThrowsNamingTheKey) {
  EXPECT_EQ(checked_step_count(0.1, 1e-5, "--end"), 10000);
  try {
    checked_step_count(1e300, 1e-5, "--end");
    ADD_FAILURE() << "no overflow_error";
  } catch (const std::overflow_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--end: an end time of 1e+300 s is 1e+305 steps", 0), 0u)
        << e.what();
  }
}

TEST(SceneLimits, OutputEveryAbove2To53StepsNamesTheLimit) {
  const std::string outputs = "  friction: true\noutputs:\n  trajectories: {every: ";
  const auto every = [&](const std::string& value) {
    return replaced(kValidScene, "  friction: true\n", outputs + value + "}\n");
  };
  EXPECT_EQ(parse(every("9007199254740992")).outputs.trajectories->every, kMaxSteps);
  // Just above, beyond a long long, and written as a double: the same message, never a wrapped
  // value.
  for (const std::string value : {"9007199254740993", "99999999999999999999", "1e300"})
    EXPECT_EQ(scene_error(every(value)).what(),
              "errors.yaml:22:25: outputs.trajectories.every: expected a positive integer number "
              "of steps, at most 2^53 = 9007199254740992, got '" +
                  value + "'");
}

TEST(SceneLimits, SeedsAbove2To63Minus1NameTheLimit) {
  EXPECT_EQ(parse(replaced(kValidScene, "seed: 3", "seed: 9223372036854775807")).seed,
            9223372036854775807ull);
  for (const std::string value : {"9223372036854775808", "1e19"})
    EXPECT_EQ(error_with("seed: 3", "seed: " + value).what(),
              "errors.yaml:2:7: seed: expected a non-negative integer, at most 2^63 - 1 = "
              "9223372036854775807, got '" +
                  value + "'");
  // An entry's seed: the same limit.
  const SceneError entry = entry_error(
      "  - random: {template: grain, region: {box: {min: [0, 0, 0], max: [1, 1, 1]}}, "
      "count: 5, seed: 18446744073709551616}\n");
  expect_key_and_message(entry, "particles[1].random.seed",
                         "expected a non-negative integer, at most 2^63 - 1 = "
                         "9223372036854775807, got '18446744073709551616'");
}

TEST(SceneLimits, LatticeOf8e9PointsIsRefusedBeforeItsCountOverflows) {
  // 20 m / 0.01 m = 2000 points an axis: 8e9 in all, which an int (the old per-axis product)
  // cannot hold.
  const SceneError e = entry_error(
      "  - lattice: {template: grain, region: {box: {min: [0, 0, 0], max: [20, 20, "
      "20]}}, spacing: 0.01}\n");
  EXPECT_EQ(e.line(), 17);
  expect_key_and_message(e, "particles[1].lattice.spacing",
                         "a lattice of 2000 x 2000 x 2000 = 8e+09 points, above the limit of "
                         "2^31 - 1 = 2147483647 particles in a scene; use a larger spacing or a "
                         "smaller box");
  // 1291^3 = 2151685171 points is just above the limit and 1290^3 = 2146689000 just below: the
  // check counts points as the lattice does. (Only loaded: no particle is made.)
  const auto lattice = [](const std::string& size) {
    return with_entry("  - lattice: {template: grain, region: {box: {min: [0, 0, 0], max: [" +
                      size + ", " + size + ", " + size + "]}}, spacing: 0.01}\n");
  };
  EXPECT_EQ(scene_error(lattice("12.91")).message().rfind("a lattice of 1291 x 1291 x 1291 = ", 0),
            0u);
  const Scene below = parse(lattice("12.9"));
  EXPECT_EQ(lattice_point_count(below.lattices[0].region, below.lattices[0].spacing),
            1290.0 * 1290 * 1290);
}

TEST(SceneLimits, RandomFillCountsAboveTheLimitNameIt) {
  const std::string region = "region: {box: {min: [0, 0, 0], max: [1000, 1000, 1000]}}";
  EXPECT_STREQ(
      entry_error("  - random: {template: grain, " + region + ", count: 2147483648}\n").what(),
      "errors.yaml:17:96: particles[1].random.count: expected a positive integer "
      "number of particles, at most 2^31 - 1 = 2147483647, got '2147483648'");
  // A volume fraction of a 1000 m box: about 1e15 particles, refused before llround could wrap.
  const SceneError fraction =
      entry_error("  - random: {template: grain, " + region + ", volume_fraction: 0.3}\n");
  // A dodecahedron of circumscribed radius 5 mm has edges of 4 R / (sqrt(3) (1 + sqrt(5))) =
  // 3.568 mm and a volume of (15 + 7 sqrt(5)) / 4 a^3 = 3.481e-7 m^3: 0.3 x 1e9 / 3.481e-7.
  expect_key_and_message(fraction, "particles[1].random.volume_fraction",
                         "a volume fraction of 0.3 of this region is 8.617e+14 particles of "
                         "template 'grain', above the limit of 2^31 - 1 = 2147483647 particles "
                         "in a scene");
}

TEST(SceneLimits, FeedOfMoreParticlesThanTheLimitIsRefusedAtItsRate) {
  // 1e20 per second over the 0.1 s run: 1e19 particles, above 2^63 too (the feed once inserted
  // nothing, its due count wrapped negative).
  const SceneError e = entry_error(
      "  - feed: {template: grain, region: {box: {min: [0, 0, 0], max: [1, 1, 1]}}, "
      "rate: 1e20}\n");
  EXPECT_STREQ(e.what(),
               "errors.yaml:17:84: particles[1].feed.rate: 1e+20 particles per second from 0 s "
               "to 0.1 s is 1e+19 particles, above the limit of 2^31 - 1 = 2147483647 particles "
               "in a scene");
  // 2.1e10 per second for 0.1 s: 2.1e9 particles, just below the limit, loads.
  const Scene below = parse(with_entry(
      "  - feed: {template: grain, region: {box: {min: [0, 0, 0], max: [1, 1, 1]}}, rate: "
      "2.1e10}\n"));
  // floor(2.1e10 x 0.1) may land 1 below 2.1e9 (0.1 is not a double): within 1.
  EXPECT_NEAR(scene_particle_count(below), 1 + 2.1e9, 1.0);
}

TEST(SceneLimits, EntriesTogetherAboveTheLimitAreRefusedAtTheEntryThatCrossesIt) {
  // Two fills of 1.5e9 (each allowed, and sparse enough in a 1000 m box to be placed).
  const std::string fill =
      "  - random: {template: grain, region: {box: {min: [0, 0, 0], max: [1000, 1000, 1000]}}, "
      "count: 1500000000}\n";
  const SceneError e = entry_error(fill + fill);
  EXPECT_STREQ(e.what(),
               "errors.yaml:18:13: particles[2].random: this entry brings the scene to 3e+09 "
               "particles (initial ones and all that feeds insert), above the limit of 2^31 - 1 = "
               "2147483647 particles in a scene");
}

}  // namespace
}  // namespace talus
