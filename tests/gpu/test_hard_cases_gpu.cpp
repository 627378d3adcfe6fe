// The dynamic hard cases (tests/support/hard_cases.hpp) on the GPU: scenes of the host's at
// dt = 1e-5 s on the CUDA step, each coming to rest as on the host
// (tests/step/test_hard_cases.cpp). A step of a few particles costs the CUDA step about as much as
// one of thousands (a few launches and synchronisations per stage), so the GPU runs the cases that
// take a second, one of each kind of contact (pair, wall, friction holding on an incline); the
// column (21 s) and the 80-facet cylinders stay on the host. Skipped with the reason where no GPU
// is usable.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "tests/support/hard_cases.hpp"

namespace talus {
namespace {

using talus_test::HardCase;

class HardCasesGpu : public ::testing::TestWithParam<HardCase> {};

// The host test's bounds (kinetic energy 1e-12 J, drift 1e-9 m over 1 s, the walls carrying the
// weight to 1e-6; tests/step/test_hard_cases.cpp says why). The GPU step's sums are the host's
// in the same order, so its rest is the host's to round-off.
TEST_P(HardCasesGpu, ComesToRestAtTenMicroseconds) {
  std::string why;
  if (!cuda_device_available(&why)) GTEST_SKIP() << why;
  const HardCase& c = GetParam();
  const Scene scene = parse_scene(c.yaml, "hard.yaml", ".");
  CudaStep<double> step(scene);
  const talus_test::RestMeasure r = talus_test::rest_of(step, scene, c.settle, c.check);
  EXPECT_LT(r.kinetic_settled, 1e-12) << c.name;
  EXPECT_LT(r.kinetic_end, 1e-12) << c.name;
  EXPECT_LT(r.drift, 1e-9) << c.name;
  EXPECT_GT(r.lowest, 0.0) << c.name;
  EXPECT_NEAR(r.floor_force, 1.0, 1e-6) << c.name;
}

std::vector<HardCase> gpu_cases() {
  std::vector<HardCase> kept;
  for (const HardCase& c : talus_test::hard_cases())
    if (c.name == "CubeFaceDownOnACube" || c.name == "TetrahedronDroppedVertexFirst" ||
        c.name == "CubeOnAnInclineBelowTheFrictionAngle")
      kept.push_back(c);
  return kept;
}

INSTANTIATE_TEST_SUITE_P(, HardCasesGpu, ::testing::ValuesIn(gpu_cases()),
                         [](const ::testing::TestParamInfo<HardCase>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace talus
