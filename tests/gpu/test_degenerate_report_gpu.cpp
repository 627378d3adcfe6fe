// The CUDA step's message for a pair whose contact geometry cannot be computed: the host's
// (tests/step/test_degenerate_report.cpp), the poses downloaded from the device. Skipped with the
// reason where no GPU is usable.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "solver/geometry/overlap_batch.hpp"  // cuda_device_available
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda_step.hpp"

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

TEST(DegenerateReportGpu, NamesTheFileTheParticlesAndTheirPoses) {
  std::string why;
  if (!cuda_device_available(&why)) GTEST_SKIP() << why;
  const Scene scene = parse_scene(kScene, "test.yaml", ".");
  CudaStep<double> step(scene);
  try {
    step.step();
    FAIL() << "a sphere inside another was stepped";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.yaml: particles 0 and 1"), std::string::npos) << m;
    // 0.1 is not a binary fraction: 17 significant digits give it back exactly.
    EXPECT_NE(m.find("particle 1 (template 'ball') at (0.10000000000000001, -0.25, 0.0625), "
                     "orientation (1, 0, 0, 0)"),
              std::string::npos)
        << m;
  }
}

}  // namespace
}  // namespace talus
