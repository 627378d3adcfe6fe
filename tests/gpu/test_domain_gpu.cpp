// The domain box and the renumbering by cell on the CUDA step (cuda_step.cu, cuda_particles.cu,
// cuda_pair_list.cu), against the host step (tests/step/test_domain_step.cpp): the same particles
// removed at the same steps with the same energy booked, the pour's motion within round-off of
// the host's, the contact histories carried through every renumbering of the device arrays, and a
// restart after removal that continues bit for bit. Skipped with the reason where no GPU is
// usable. TALUS_GPU_TEST_MAX_STEPS caps the long run (compute-sanitizer).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/support/domain_scenes.hpp"
#include "tests/support/gpu_skip.hpp"

namespace talus {
namespace {

using talus::testing::histories_by_key;
using talus::testing::pour_scene;

Scene scene_from(const std::string& yaml) {
  return parse_scene(yaml, "domain.yaml", ".");
}

long long capped(long long steps) {
  const char* cap = std::getenv("TALUS_GPU_TEST_MAX_STEPS");
  return cap && std::atoll(cap) > 0 ? std::min(steps, std::atoll(cap)) : steps;
}

// As tests/gpu/test_feed_gpu.cpp: the device runs the host's functions in the host's order and
// differs by nvcc's fused multiply-adds (1e-16 relative per operation), which the contacts of a
// short pour amplify by far less than 1e5: 1e-10 m keeps a margin of 1000.
constexpr double kPositionTolerance = 1e-10;

TEST(DomainGpu, RemovalMatchesTheHost) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(pour_scene(true, true, false));
  HostStep<double> host(scene, 1);
  CudaStep<double> gpu(scene);
  ASSERT_EQ(gpu.particle_count(), 32);
  long long steps = 0;
  while (host.time() < 0.018) {  // the rain is gone by 18 ms (test_domain_step.cpp)
    host.step();
    gpu.step();
    ++steps;
    ASSERT_EQ(gpu.particle_count(), host.particle_count()) << "step " << steps;
  }
  EXPECT_EQ(gpu.particle_count(), 24);
  EXPECT_EQ(gpu.removed_count(), 8);
  const std::vector<TrajectoryRow> h = host.trajectory_rows(), g = gpu.trajectory_rows();
  ASSERT_EQ(h.size(), g.size());
  for (std::size_t k = 0; k < h.size(); ++k) {
    EXPECT_EQ(h[k].id, g[k].id);
    EXPECT_LT(norm(h[k].position - g[k].position), kPositionTolerance) << h[k].id;
  }
  // The removed energy: the same 8 particles' free fall; the device sums it in another order
  // (a CUB reduction), 1e-15 relative, and their motion agrees to round-off.
  const double removed = host.energy().ledger.removed;
  EXPECT_GT(removed, 0);
  EXPECT_NEAR(gpu.energy().ledger.removed, removed, 1e-12 * std::abs(removed));
}

TEST(DomainGpu, RestartAfterRemovalContinuesBitForBit) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(pour_scene(true, true, false));
  CudaStep<double> a(scene);
  while (a.time() < 0.018) a.step();
  ASSERT_EQ(a.particle_count(), 24);
  const StepState<double> saved = a.export_state();
  EXPECT_EQ(saved.next_id, 32);
  CudaStep<double> b(scene);
  b.import_state(saved);
  EXPECT_EQ(b.particle_count(), 24);
  for (int k = 0; k < 50; ++k) a.step(), b.step();
  talus_test::expect_same_state(a.export_state(), b.export_state());
}

// The pour renumbered by cell at every build of the pair list (the CUDA step's default: its
// scene does not ask) against the host's pour renumbered at every step (`reorder: true`): the
// same contacts with the same springs, the same motion.
TEST(DomainGpu, RenumberingByCellMatchesTheHost) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(pour_scene(false, false, false, 0.15));
  ASSERT_FALSE(scene.reorder.has_value());
  const Scene host_scene = scene_from(pour_scene(false, false, true, 0.15));
  HostStep<double> host(host_scene, 1);
  CudaStep<double> gpu(scene);
  const long long steps = capped(std::llround(0.15 / scene.time_step) - 1);
  for (long long k = 0; k < steps; ++k) host.step(), gpu.step();
  const StepState<double> sh = host.export_state(), sg = gpu.export_state();
  if (steps > 1000) {  // the pour has landed: the list rebuilt, the particles renumbered
    EXPECT_GT(gpu.pair_list_builds(), 1);
    EXPECT_FALSE(std::is_sorted(sg.global_ids.begin(), sg.global_ids.end()));
  }
  const auto hh = histories_by_key(sh), hg = histories_by_key(sg);
  ASSERT_EQ(hh.size(), hg.size());
  double largest = 0;
  for (const auto& [key, h] : hh) largest = std::max(largest, norm(h.elastic_force));
  for (const auto& [key, h] : hh) {
    ASSERT_TRUE(hg.count(key)) << key.first << "-" << key.second;
    // A lost history would differ by the whole spring force; round-off as for the positions.
    EXPECT_LT(norm(h.elastic_force - hg.at(key).elastic_force), 1e-8 * largest + 1e-300);
  }
  const std::vector<TrajectoryRow> rh = host.trajectory_rows(), rg = gpu.trajectory_rows();
  ASSERT_EQ(rh.size(), rg.size());
  for (std::size_t k = 0; k < rh.size(); ++k) {
    EXPECT_EQ(rh[k].id, rg[k].id);
    EXPECT_LT(norm(rh[k].position - rg[k].position), kPositionTolerance) << rh[k].id;
  }
}

}  // namespace
}  // namespace talus
