// The CUDA step's message for a pair whose contact geometry cannot be computed: the host's
// (tests/step/test_degenerate_report.cpp), the poses downloaded from the device. Skipped with the
// reason where no GPU is usable.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "solver/core/cuda_device.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "tests/support/degenerate_pair.hpp"

namespace talus {
namespace {

TEST(DegenerateReportGpu, NamesTheFileTheParticlesAndTheirPoses) {
  std::string why;
  if (!cuda_device_available(&why)) GTEST_SKIP() << why;
  const Scene scene = parse_scene(talus_test::degenerate_pair_scene(), "test.yaml", ".");
  CudaStep<double> step(scene);
  try {
    step.step();
    FAIL() << "a sphere inside another was stepped";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.yaml: particles 0 and 1"), std::string::npos) << m;
    EXPECT_NE(m.find(talus_test::degenerate_pair_pose()), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace talus
