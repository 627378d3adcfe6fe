// What the CUDA step computes of its particles on the device (cuda_step_outputs.cu): the energy
// probe's terms and the bed height, each against the host step's loop over the same state,
// exported from the device and imported by the host; and which of its stages it says ran beside
// another (the run summary's `stages_beside`). Skipped with the reason where no GPU is usable.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/support/gpu_skip.hpp"

namespace talus {
namespace {

Scene scene_from(const std::string& yaml) {
  return parse_scene(yaml, "test.yaml", ".");
}

// The energy terms of the particles (CudaStep::energy, summed on the device in fixed trees)
// equal the host's sum over the same state: 70,000 dodecahedra (274 blocks of 256, more than the
// 256 threads of the total's block, so its strided loop is exercised) falling with a random
// velocity field, and three spinning about other axes; the state exported from the device and
// imported by the host step, which sums particle by particle. The parts are the same per-particle
// doubles summed in another order: agreement to 1e-12 of the largest part (70,000 terms of one
// sign, each summation's rounding below 1e-16 relative a term times log2 of the count for the
// tree, the count for the host's running sum: ~1e-11 at worst, 1e-12 in practice for terms of
// one sign; a wrong inertia, mass or block total is off by whole particles' shares, 1e-5 or
// more).
TEST(GpuStep, DeviceEnergyEqualsTheHostSumOfTheSameState) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(R"(
time: {step: 1.0e-5, end: 1.0}
seed: 11
materials:
  resin: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.5,
          restitution: 0.3}
templates:
  grain: {shape: dodecahedron:0.01, material: resin}
particles:
  - random:
      template: grain
      region: {box: {min: [-1, -1, 0.1], max: [1, 1, 0.6]}}
      count: 70000
      velocity: [0.3, -0.2, -1.0]
      random_orientation: true
  - explicit:
      - {template: grain, position: [0, 0, 0.8], angular_velocity: [3, 0, 1]}
      - {template: grain, position: [0.1, 0, 0.8], angular_velocity: [0, -7, 2]}
      - {template: grain, position: [0.2, 0, 0.8], angular_velocity: [1, 1, 1]}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)");
  CudaStep<double> gpu(scene);
  for (int k = 0; k < 5; ++k) gpu.step();
  HostStep<double> host(scene, 1);
  host.import_state(gpu.export_state());
  const EnergyTerms d = gpu.energy(), h = host.energy();
  ASSERT_EQ(host.particle_count(), 70003);
  ASSERT_GT(h.kinetic_rotational, 0);
  const double scale = std::max({std::abs(h.kinetic_translational), std::abs(h.kinetic_rotational),
                                 std::abs(h.gravitational)});
  EXPECT_NEAR(d.kinetic_translational, h.kinetic_translational, 1e-12 * scale);
  EXPECT_NEAR(d.kinetic_rotational, h.kinetic_rotational, 1e-12 * scale);
  EXPECT_NEAR(d.gravitational, h.gravitational, 1e-12 * scale);
  EXPECT_NEAR(gpu.kinetic_energy(), host.kinetic_energy(), 1e-12 * scale);
}

// The bed_height probe computed on the device (a maximum over blocks) against the host loop over
// the same state: spheres and dodecahedra, gravity tilted so that every coordinate counts.
TEST(GpuStep, DeviceBedHeightEqualsTheHostLoopOverTheSameState) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(R"(
time: {step: 1.0e-5, end: 1.0}
seed: 12
materials:
  resin: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.5,
          restitution: 0.3}
templates:
  grain: {shape: dodecahedron:0.01, material: resin}
  ball: {sphere: 0.004, material: resin}
particles:
  - random:
      template: grain
      region: {box: {min: [-1, -1, 0.1], max: [1, 1, 0.6]}}
      count: 30000
      random_orientation: true
  - random:
      template: ball
      region: {box: {min: [-1, -1, 0.1], max: [1, 1, 0.6]}}
      count: 30000
effects:
  gravity: [0.5, -3.0, -9.0]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
  CudaStep<double> gpu(scene);
  for (int k = 0; k < 3; ++k) gpu.step();
  HostStep<double> host(scene, 1);
  host.import_state(gpu.export_state());
  ASSERT_EQ(host.particle_count(), 60000);
  const Vec3d g(0.5, -3.0, -9.0);
  const double h = host.bed_height(g);
  // The same per-particle function on both sides (particle_top); only the device's fused
  // multiply-adds may round differently, a few ulps of a height below 1 m.
  EXPECT_NEAR(gpu.bed_height(g), h, 1e-12);
  EXPECT_NEAR(gpu.bed_height(g * -1.0), host.bed_height(g * -1.0), 1e-12);
  EXPECT_GT(h, 0.1);  // the particles' tops, not an empty maximum
}

// The wall stage runs beside the pair stage in a scene with walls (unless the environment says
// TALUS_WALLS_BESIDE_PAIRS=0), and nothing runs beside anything in a scene without: what the
// summary's `stages_beside` and the scaling driver's stage sums read.
TEST(GpuStep, SaysWhichStagesRunBesideOthers) {
  SKIP_WITHOUT_GPU();
  const std::string head = R"(
time: {step: 1.0e-5, end: 1.0}
materials:
  resin: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.5,
          restitution: 0.3}
templates:
  grain: {shape: dodecahedron:0.01, material: resin}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.02]}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
)";
  const std::string floor = R"(walls:
  - plane: {name: floor, point: [0, 0, 0], normal: [0, 0, 1], size: 0.1, material: resin}
)";
  const char* beside = std::getenv("TALUS_WALLS_BESIDE_PAIRS");
  const bool allowed = beside == nullptr || std::string(beside) != "0";
  using Pairs = std::vector<std::pair<std::string, std::string>>;
  const Pairs walls_beside_pairs = allowed ? Pairs{{"wall_contacts", "pair_contacts"}} : Pairs{};
  EXPECT_EQ(CudaStep<double>(scene_from(head + floor)).stages_beside(), walls_beside_pairs);
  EXPECT_EQ(CudaStep<double>(scene_from(head)).stages_beside(), Pairs{});
}

}  // namespace
}  // namespace talus
