// The broad phase on the GPU against the host driver (itself tested against brute force in
// tests/neighbor): the same list, pair for pair, in double and float, dense and sparse, and the
// same refusal of a non-finite particle. Skipped with the reason where no GPU is usable.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/neighbor/contact_pairs_gpu.hpp"
#include "tests/support/gpu_skip.hpp"

namespace talus {
namespace {

template <class Real>
struct Cloud {
  std::vector<Real> x, y, z, r;
  NeighborInput<Real> input(Real skin = 0) const {
    NeighborInput<Real> in;
    in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = r.data();
    in.count = static_cast<int>(x.size());
    in.skin = skin;
    return in;
  }
};

template <class Real>
Cloud<Real> random_cloud(int n, double box, double r_min, double r_max, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Cloud<Real> c;
  for (int i = 0; i < n; ++i) {
    c.x.push_back(Real(box * (u(rng) - 0.5)));
    c.y.push_back(Real(box * (u(rng) - 0.5)));
    c.z.push_back(Real(box * (u(rng) - 0.5)));
    c.r.push_back(Real(r_min + (r_max - r_min) * u(rng)));
  }
  return c;
}

// The device list equals the host list exactly: both compute the same grid (min/max
// reductions are exact), the same buckets and the same sphere tests in the same precision, and
// both sort each particle's segment.
template <class Real>
void expect_gpu_matches_host(const Cloud<Real>& cloud, Real skin) {
  const std::vector<ContactPair> host = build_candidate_pairs(cloud.input(skin));
  ContactPairsGpu<Real> gpu;
  gpu.set_particles(cloud.input(skin));
  gpu.build();
  const std::vector<ContactPair> device = gpu.pairs();
  ASSERT_EQ(device.size(), host.size());
  EXPECT_EQ(gpu.pair_count(), static_cast<long long>(host.size()));
  for (std::size_t k = 0; k < host.size(); ++k) {
    ASSERT_TRUE(device[k] == host[k])
        << "pair " << k << ": device (" << device[k].a << ", " << device[k].b << "), host ("
        << host[k].a << ", " << host[k].b << ")";
  }
}

TEST(GpuContactPairs, AgreesWithTheHostInDoubleAndFloat) {
  SKIP_WITHOUT_GPU();
  // About 6 neighbours per particle (dense) and a sparse mixed-size cloud.
  const Cloud<double> dense = random_cloud<double>(200000, 1.0, 0.008, 0.012, 1);
  expect_gpu_matches_host(dense, 0.0);
  expect_gpu_matches_host(dense, 0.002);
  const Cloud<double> mixed = random_cloud<double>(50000, 2.0, 0.001, 0.03, 2);
  expect_gpu_matches_host(mixed, 0.0);
  const Cloud<float> dense_f = random_cloud<float>(200000, 1.0, 0.008, 0.012, 3);
  expect_gpu_matches_host(dense_f, 0.0f);
}

TEST(GpuContactPairs, EmptySingleAndNonFiniteInput) {
  SKIP_WITHOUT_GPU();
  ContactPairsGpu<double> gpu;
  Cloud<double> cloud;
  gpu.set_particles(cloud.input());
  gpu.build();
  EXPECT_EQ(gpu.pair_count(), 0);
  cloud = random_cloud<double>(1, 1.0, 0.1, 0.1, 4);
  gpu.set_particles(cloud.input());
  gpu.build();
  EXPECT_EQ(gpu.pair_count(), 0);
  cloud = random_cloud<double>(1000, 1.0, 0.01, 0.01, 5);
  cloud.z[123] = std::nan("");
  gpu.set_particles(cloud.input());
  try {
    gpu.build();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("particle 123"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace talus
