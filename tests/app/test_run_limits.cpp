// `talus run` and what a scene or --end asks for beyond the machine or the counters: a clear
// one-line error and a non-zero exit status, never a silent run of 0 steps or a crash; and the
// warnings on a scene's initial particles, on stderr.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <unistd.h>

#include "tests/app/run_talus.hpp"

namespace {

using talus_test::ProcessResult;
using talus_test::run_talus;
using talus_test::write_scene;

// Spheres (5 mm), linear contact, no gravity; PARTICLES is replaced by the particle list.
const std::string kScene = R"(time: {step: 1.0e-5, end: 3.0e-5}
materials:
  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3, friction: 0.3, restitution: 0.9}
templates:
  ball: {sphere: 0.005, material: steel}
particles:
PARTICLES
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 1.0}
)";

// A scene file in a fresh directory `name` with `particles` as its list, run quietly with `extra`
// options (and `address_space` bytes of virtual memory, 0: no cap).
struct SceneRun {
  std::string scene;
  ProcessResult run;
};
SceneRun run_scene(const std::string& name, const std::string& particles,
                   const std::vector<std::string>& extra = {}, rlim_t address_space = 0) {
  const std::string dir = talus_test::fresh_directory("test-run-limits", name);
  std::string text = kScene;
  const std::string key = "PARTICLES";
  const std::string scene = write_scene(dir, text.replace(text.find(key), key.size(), particles));
  std::vector<std::string> args = {"run", "--quiet", "--output", dir};
  args.insert(args.end(), extra.begin(), extra.end());
  args.push_back(scene);
  return {scene, run_talus(args, address_space)};
}

// Whether `text` starts with `prefix` (then the rest is checked apart, or varies by machine).
bool starts_with(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

TEST(TalusRunLimits, EndBeyond2To53StepsIsAnErrorNotAnEmptyRun) {
  const SceneRun r = run_scene(
      "end", "  - explicit:\n      - {template: ball, position: [0, 0, 0]}", {"--end", "1e300"});
  EXPECT_EQ(r.run.exit_code, 2);
  EXPECT_EQ(r.run.out, "");
  EXPECT_EQ(r.run.err,
            "talus: error: --end: an end time of 1e+300 s is 1e+305 steps of 1e-05 s, above the "
            "limit of 2^53 = 9007199254740992 steps (the step index and the time stay exact in a "
            "double up to it)\n");
}

TEST(TalusRunLimits, ASceneBeyondTheMachinesMemoryIsRefusedBeforeAllocating) {
  // 1250^3 = 1.95e9 lattice points (below the 2^31 - 1 particle limit): 4.0e12 bytes at 2048 a
  // particle, beyond any machine this runs on; refused at once, not after a bad_alloc.
  const SceneRun r = run_scene("memory",
                               "  - lattice: {template: ball, region: {box: {min: [0, 0, 0], "
                               "max: [12.5, 12.5, 12.5]}}, spacing: 0.01}");
  EXPECT_EQ(r.run.exit_code, 2);
  EXPECT_TRUE(starts_with(r.run.err, "talus: error: " + r.scene +
                                         ":7:14: particles[0].lattice: the scene would create "
                                         "1953125000 particles (1953125000 of them from this "
                                         "entry), an estimated 4000000000000 bytes (2048 a "
                                         "particle), more than the "))
      << r.run.err;
  EXPECT_NE(r.run.err.find(" bytes of memory this machine has; ask for fewer particles\n"),
            std::string::npos)
      << r.run.err;
}

TEST(TalusRunLimits, AnAllocationThatFailsAnywayIsOneLineAndExitStatus1) {
  // 2e6 lattice points (estimate 4.1 GB, below this machine's memory) under a 1 GiB address
  // space: making the initial particles (about 200 bytes each, twice) fails with bad_alloc.
  if (double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE)) < 8e9)
    GTEST_SKIP() << "the estimate check would refuse the scene first on this small machine";
  const SceneRun r = run_scene("bad_alloc",
                               "  - lattice: {template: ball, region: {box: {min: [0, 0, 0], "
                               "max: [1.26, 1.26, 1.26]}}, spacing: 0.01}",
                               {}, rlim_t(1) << 30);
  EXPECT_EQ(r.run.exit_code, 1);
  EXPECT_EQ(r.run.err,
            "talus: error: out of memory: an allocation failed; the run needs "
            "more memory than this process may use (the machine's, or a limit such as ulimit "
            "-v); run fewer particles\n");
}

TEST(TalusRunLimits, InitialOverlapsAreWarnedOnStderrAndDeepOnesRefused) {
  const std::string pair =
      "  - explicit:\n      - {template: ball, position: [0, 0, 0]}\n      - {template: ball, "
      "position: [X, 0, 0]}";
  const std::string x = "X";
  // 9 mm apart: the 5 mm spheres overlap by 1 mm, a warning; the run goes on.
  const SceneRun shallow =
      run_scene("shallow", std::string(pair).replace(pair.find(x), 1, "0.009"));
  EXPECT_EQ(shallow.run.exit_code, 0) << shallow.run.err;
  EXPECT_EQ(shallow.run.err, "talus run: " + shallow.scene +
                                 ":8:9: particles[0].explicit[0]: warning: 1 pair of particles "
                                 "overlaps at the start with particles of " +
                                 shallow.scene +
                                 ":9:9: particles[0].explicit[1]; the contact law pushes them "
                                 "apart at the first step, turning the overlap's elastic energy "
                                 "into speed (id pairs: 0-1)\n");
  // 1 nm apart: refused.
  const SceneRun deep = run_scene("deep", std::string(pair).replace(pair.find(x), 1, "1.0e-9"));
  EXPECT_EQ(deep.run.exit_code, 2);
  EXPECT_TRUE(starts_with(deep.run.err, "talus: error: " + deep.scene +
                                            ":8:9: particles[0].explicit[0]: particles 0 and 1 "
                                            "(the second of " +
                                            deep.scene +
                                            ":9:9: particles[0].explicit[1]) start with the "
                                            "centroid"))
      << deep.run.err;
}

}  // namespace
