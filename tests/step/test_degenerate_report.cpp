// A pair whose contact geometry cannot be computed stops the step with a message that lets the
// failure be replayed alone: the scene file, both particles' ids and templates, and their poses
// in full precision.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "solver/step/host_step.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

// Two balls with one centre: one sphere inside the other has no contact circle (degenerate).
const char* const kScene = R"(time: {step: 1.0e-5, end: 1.0e-4}
materials:
  stone: {density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.5,
          restitution: 0.5}
templates:
  ball: {sphere: 0.005, material: stone}
effects: {contact: volume}
particles:
  - explicit:
      - {template: ball, position: [0.1, -0.25, 0.0625]}
      - {template: ball, position: [0.1, -0.25, 0.0625]}
)";

TEST(DegenerateReport, NamesTheFileTheParticlesAndTheirPoses) {
  const Scene scene = talus_test::scene_from(kScene);
  HostStep<double> step(scene);
  try {
    step.step();
    FAIL() << "a sphere inside another was stepped";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.yaml: particles 0 and 1"), std::string::npos) << m;
    EXPECT_NE(m.find("degenerate"), std::string::npos) << m;
    // 0.1 is not a binary fraction: 17 significant digits give it back exactly.
    EXPECT_NE(m.find("particle 1 (template 'ball') at (0.10000000000000001, -0.25, 0.0625), "
                     "orientation (1, 0, 0, 0)"),
              std::string::npos)
        << m;
  }
}

}  // namespace
}  // namespace talus
