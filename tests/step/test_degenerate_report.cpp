// A pair whose contact geometry cannot be computed stops the step with a message that lets the
// failure be replayed alone: the scene file, both particles' ids and templates, and their poses
// in full precision.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "solver/step/host/host_step.hpp"
#include "tests/step/step_test_util.hpp"
#include "tests/support/degenerate_pair.hpp"

namespace talus {
namespace {

TEST(DegenerateReport, NamesTheFileTheParticlesAndTheirPoses) {
  const Scene scene = talus_test::scene_from(talus_test::degenerate_pair_scene());
  HostStep<double> step(scene);
  try {
    step.step();
    FAIL() << "a sphere inside another was stepped";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.yaml: particles 0 and 1"), std::string::npos) << m;
    EXPECT_NE(m.find("degenerate"), std::string::npos) << m;
    EXPECT_NE(m.find(talus_test::degenerate_pair_pose()), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace talus
