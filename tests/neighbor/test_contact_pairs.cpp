// The broad phase against its brute-force oracle: every pair of overlapping bounding spheres,
// nothing else, each once, sorted — on random clouds, mixed sizes, crowds at one point, far-off
// particles and tiny hash tables; and the same list on any number of threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "solver/neighbor/contact_pairs.hpp"

namespace talus {
namespace {

struct Cloud {
  std::vector<double> x, y, z, r;
  NeighborInput<double> input(double skin = 0) const {
    NeighborInput<double> in;
    in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = r.data();
    in.count = static_cast<int>(x.size());
    in.skin = skin;
    return in;
  }
  void add(double px, double py, double pz, double pr) {
    x.push_back(px), y.push_back(py), z.push_back(pz), r.push_back(pr);
  }
};

// O(n^2): every a < b with |x_a - x_b| <= r_a + r_b + skin, in (a, b) order.
std::vector<ContactPair> brute_force(const Cloud& c, double skin = 0) {
  std::vector<ContactPair> pairs;
  const int n = static_cast<int>(c.x.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const double dx = c.x[a] - c.x[b], dy = c.y[a] - c.y[b], dz = c.z[a] - c.z[b];
      const double reach = c.r[a] + c.r[b] + skin;
      if (dx * dx + dy * dy + dz * dz <= reach * reach) pairs.push_back({a, b});
    }
  }
  return pairs;
}

// n particles uniform in a cube of side `box`, radii uniform in [r_min, r_max].
Cloud random_cloud(int n, double box, double r_min, double r_max, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Cloud c;
  for (int i = 0; i < n; ++i) {
    c.add(box * (u(rng) - 0.5), box * (u(rng) - 0.5), box * (u(rng) - 0.5),
          r_min + (r_max - r_min) * u(rng));
  }
  return c;
}

void expect_same_pairs(const std::vector<ContactPair>& got, const std::vector<ContactPair>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_TRUE(got[k] == want[k]) << "pair " << k << ": got (" << got[k].a << ", " << got[k].b
                                   << "), want (" << want[k].a << ", " << want[k].b << ")";
  }
}

TEST(ContactPairs, RandomCloudsMatchBruteForce) {
  // Densities from sparse to about 6 neighbours per particle, equal and mixed radii.
  const struct {
    int n;
    double box, r_min, r_max;
  } cases[] = {{2000, 1.0, 0.01, 0.01},
               {2000, 0.3, 0.01, 0.01},
               {3000, 0.4, 0.002, 0.02},
               {500, 0.05, 0.001, 0.01}};
  std::uint64_t seed = 11;
  for (const auto& c : cases) {
    const Cloud cloud = random_cloud(c.n, c.box, c.r_min, c.r_max, seed++);
    NeighborStats stats;
    const std::vector<ContactPair> pairs = build_candidate_pairs(cloud.input(), &stats);
    const std::vector<ContactPair> want = brute_force(cloud);
    expect_same_pairs(pairs, want);
    EXPECT_GT(want.size(), 0u);  // the case tests something
    EXPECT_EQ(stats.pairs, static_cast<long long>(want.size()));
    EXPECT_GE(stats.candidates, stats.pairs);
  }
}

// A packed cloud's cells are numbered densely (at most 4 cells a particle: 17^3 = 4913 for 2000
// particles of 0.02 m cells in a 0.3 m box, with the margin), a sparse one's hashed (52^3 cells in
// a 1 m box); both lists are the brute force's, and a dense particle's 27 buckets are distinct.
TEST(ContactPairs, DenseAndHashedNumberingsGiveTheBruteForceList) {
  const Cloud packed = random_cloud(2000, 0.3, 0.01, 0.01, 21);
  const Cloud sparse = random_cloud(2000, 1.0, 0.01, 0.01, 22);
  const NeighborGrid<double> dense = make_neighbor_grid(packed.input(), 0.0, true);
  EXPECT_GT(dense.dims[0], 0);
  EXPECT_EQ(make_neighbor_grid(sparse.input(), 0.0, true).dims[0], 0);
  EXPECT_EQ(make_neighbor_grid(packed.input()).dims[0], 0);  // hashed unless asked (the GPU's)
  for (int i = 0; i < 2000; i += 97) {
    std::uint32_t buckets[27];
    ASSERT_EQ(neighbour_buckets(packed.input(), dense, i, buckets), 27);
    for (int k = 1; k < 27; ++k) EXPECT_LT(buckets[k - 1], buckets[k]);
  }
  for (const Cloud* cloud : {&packed, &sparse}) {
    const std::vector<ContactPair> want = brute_force(*cloud, 0.002);
    EXPECT_GT(want.size(), 0u);
    expect_same_pairs(build_candidate_pairs(cloud->input(0.002)), want);
    expect_same_pairs(build_candidate_pairs(cloud->input(0.002), nullptr, 0.0, 2), want);
  }
}

// A size ratio of 1:100: the cells follow the largest sphere, and small ones all share a cell.
TEST(ContactPairs, SizeRatioOneToHundred) {
  Cloud cloud = random_cloud(1500, 0.2, 0.0005, 0.0005, 5);
  cloud.add(0, 0, 0, 0.05);
  cloud.add(0.07, 0.02, 0, 0.05);
  expect_same_pairs(build_candidate_pairs(cloud.input()), brute_force(cloud));
}

// The skin keeps pairs up to r_a + r_b + skin apart.
TEST(ContactPairs, SkinWidensTheTest) {
  const Cloud cloud = random_cloud(1500, 0.5, 0.005, 0.01, 9);
  const std::vector<ContactPair> plain = build_candidate_pairs(cloud.input());
  const std::vector<ContactPair> skinned = build_candidate_pairs(cloud.input(0.004));
  expect_same_pairs(skinned, brute_force(cloud, 0.004));
  EXPECT_GT(skinned.size(), plain.size());
}

// Exactly touching spheres count (the reference's broad phase skips only when farther apart);
// spheres a hair apart do not.
TEST(ContactPairs, TouchingCountsAndAHairApartDoesNot) {
  Cloud cloud;
  cloud.add(0, 0, 0, 0.5);
  cloud.add(1, 0, 0, 0.5);             // distance 1 = 0.5 + 0.5, exact in binary
  cloud.add(0, 2.0000000001, 0, 0.5);  // 1e-10 beyond the reach of the third
  cloud.add(0, 1, 0, 0.5);             // touches the first and the third
  const std::vector<ContactPair> pairs = build_candidate_pairs(cloud.input());
  expect_same_pairs(pairs, {{0, 1}, {0, 3}});  // (1, 3) are sqrt 2 apart, (2, 3) 1 + 1e-10
  expect_same_pairs(pairs, brute_force(cloud));
}

// Many particles at one point (every pair overlaps), negative and far-off coordinates (clamped
// cells), and the empty and single-particle inputs.
TEST(ContactPairs, CrowdsFarOffParticlesAndTinyInputs) {
  Cloud crowd;
  for (int i = 0; i < 40; ++i) crowd.add(-3.5, -3.5, -3.5, 0.01);
  crowd.add(1e15, -1e15, 1e15, 0.01);
  crowd.add(1e15, -1e15, 1e15 + 0.015, 0.01);
  const std::vector<ContactPair> pairs = build_candidate_pairs(crowd.input());
  EXPECT_EQ(pairs.size(), 40u * 39u / 2u + 1u);
  expect_same_pairs(pairs, brute_force(crowd));

  Cloud none;
  EXPECT_TRUE(build_candidate_pairs(none.input()).empty());
  Cloud one;
  one.add(1, 2, 3, 0.1);
  EXPECT_TRUE(build_candidate_pairs(one.input()).empty());
}

// A coarse grid (a large min_cell: everything in a few cells) gives the same pairs: the grid
// changes the work, never the answer.
TEST(ContactPairs, CellSizeChangesWorkNotAnswer) {
  const Cloud cloud = random_cloud(1000, 0.3, 0.005, 0.01, 21);
  NeighborStats fine, coarse;
  const std::vector<ContactPair> a = build_candidate_pairs(cloud.input(), &fine);
  const std::vector<ContactPair> b = build_candidate_pairs(cloud.input(), &coarse, 0.1);
  expect_same_pairs(a, b);
  EXPECT_GT(coarse.candidates, fine.candidates);
}

// On several threads (the host step's) the list is the same, pair for pair: each particle's
// count and segment are its own, and the binning and the scan stay serial. 5000 particles: more
// than kParallelMinIndices, so the per-particle loops do run on several threads.
TEST(ContactPairs, ThreadCountChangesNothing) {
  const Cloud cloud = random_cloud(5000, 0.4, 0.002, 0.02, 31);
  NeighborStats one;
  const std::vector<ContactPair> serial = build_candidate_pairs(cloud.input(), &one, 0.0, 1);
  EXPECT_GT(serial.size(), 5000u);
  for (const int threads : {2, 3, 8}) {
    NeighborStats many;
    expect_same_pairs(build_candidate_pairs(cloud.input(), &many, 0.0, threads), serial);
    EXPECT_EQ(many.candidates, one.candidates);
  }
  expect_same_pairs(serial, brute_force(cloud));
}

TEST(ContactPairs, NonFiniteInputIsRefusedNamingTheParticle) {
  Cloud cloud = random_cloud(10, 1, 0.01, 0.01, 3);
  cloud.y[7] = std::nan("");
  try {
    build_candidate_pairs(cloud.input());
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("particle 7"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace talus

namespace talus {
namespace {

// Morton keys: each coordinate's bits three apart, x lowest.
TEST(CellOrder, MortonKeysInterleaveTheCellCoordinates) {
  EXPECT_EQ(spread_bits_by_three(0), 0u);
  EXPECT_EQ(spread_bits_by_three(1), 1u);
  EXPECT_EQ(spread_bits_by_three(0b101), 0b1000001u);
  EXPECT_EQ(spread_bits_by_three(0x1fffff), 0x1249249249249249ull);
  EXPECT_EQ(spread_bits_by_three(0x200000), 0u);  // beyond 21 bits: dropped (coordinates clamp)
  std::vector<double> x = {0.5, 1.5, 0.5}, y = {0.5, 0.5, 1.5}, z = {1.5, 0.5, 0.5},
                      r = {0.25, 0.25, 0.25};
  NeighborInput<double> in;
  in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = r.data(), in.count = 3;
  NeighborGrid<double> grid;                      // origin 0, cells of 1
  EXPECT_EQ(particle_cell_key(in, grid, 0), 4u);  // cell (0, 0, 1): z's bit at 2
  EXPECT_EQ(particle_cell_key(in, grid, 1), 1u);  // (1, 0, 0)
  EXPECT_EQ(particle_cell_key(in, grid, 2), 2u);  // (0, 1, 0)
}

// cell_order is a permutation that sorts the particles by key, stable within a cell, and the
// pair list does not depend on where the grid's origin is put (a fixed origin from the domain).
TEST(CellOrder, SortsByCellAndTheListIgnoresTheOrigin) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(0, 0.2);
  const int n = 3000;
  std::vector<double> x(n), y(n), z(n), r(n, 0.004);
  for (int i = 0; i < n; ++i) x[i] = u(rng), y[i] = u(rng), z[i] = u(rng);
  NeighborInput<double> in;
  in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = r.data(), in.count = n;
  const std::vector<int> order = cell_order(in, 2);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i);
  const NeighborGrid<double> grid = make_neighbor_grid(in);
  for (int k = 1; k < n; ++k) {
    const auto previous = particle_cell_key(in, grid, order[k - 1]);
    const auto key = particle_cell_key(in, grid, order[k]);
    ASSERT_LE(previous, key);
    if (previous == key) {
      ASSERT_LT(order[k - 1], order[k]);  // stable
    }
  }
  const std::vector<ContactPair> free_origin = build_candidate_pairs(in);
  in.fixed_origin = true;
  in.origin[0] = -1.3, in.origin[1] = -0.01, in.origin[2] = 0.05;  // even above some particles
  EXPECT_EQ(build_candidate_pairs(in), free_origin);
  EXPECT_GT(free_origin.size(), 100u);
}

}  // namespace
}  // namespace talus
