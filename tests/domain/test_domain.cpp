// The domain seam (solver/domain/domain.hpp): boxes, the single-process domain the steps use, and
// the slab decomposition: every point of the region owned by exactly one rank, the one whose
// local box holds it, and a feed split over the ranks without a particle lost or doubled.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "solver/domain/domain.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/feeding.hpp"

namespace talus {
namespace {

Box box(Vec3d lo, Vec3d hi) {
  Box b;
  b.min = lo, b.max = hi;
  return b;
}

TEST(Domain, BoxesAreHalfOpenAndTheDefaultHoldsAllSpace) {
  const Box unit = box({0, 0, 0}, {1, 1, 1});
  EXPECT_TRUE(unit.bounded());
  EXPECT_TRUE(unit.contains({0, 0, 0}));
  EXPECT_FALSE(unit.contains({1, 0.5, 0.5}));  // the upper faces belong to the next box
  EXPECT_FALSE(unit.contains({0.5, -1e-300, 0.5}));
  EXPECT_FALSE(unit.contains({std::nan(""), 0.5, 0.5}));
  const Box all;
  EXPECT_FALSE(all.bounded());
  EXPECT_TRUE(all.contains({1e300, -1e300, 0}));
  const Box grown = unit.expanded(0.5);
  EXPECT_EQ(grown.min.x, -0.5);
  EXPECT_EQ(grown.max.z, 1.5);
}

TEST(Domain, SingleDomainOwnsItsRegionAsRankZero) {
  const SingleDomain d(box({0, 0, 0}, {2, 1, 1}), 0.1);
  EXPECT_EQ(d.rank(), 0);
  EXPECT_EQ(d.ranks(), 1);
  EXPECT_EQ(d.owner({1.5, 0.5, 0.5}), 0);
  EXPECT_EQ(d.owner({2.5, 0.5, 0.5}), -1);
  EXPECT_TRUE(d.owns({0, 0, 0}));
  EXPECT_EQ(d.reach_box().min.x, -0.1);
  EXPECT_EQ(d.reach_box().max.x, 2.1);
  EXPECT_EQ(d.sum(3.5), 3.5);
  const SingleDomain everywhere;
  EXPECT_EQ(everywhere.owner({-1e200, 0, 1e200}), 0);
  EXPECT_FALSE(everywhere.reach_box().bounded());
}

TEST(Domain, SlabsOwnEveryPointOnceAndAgreeWithTheirBoxes) {
  const Box region = box({-0.3, 0, 0}, {0.4, 0.2, 0.1});
  const int ranks = 7;
  std::vector<SlabDomain> slabs;
  for (int r = 0; r < ranks; ++r) slabs.emplace_back(region, 0, ranks, r, 0.01);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.35, 0.45), v(-0.05, 0.25);
  std::vector<Vec3d> points;
  for (int k = 0; k < 20000; ++k) points.push_back({u(rng), v(rng), v(rng) * 0.5});
  // The slab faces themselves, where rounding decides.
  for (int r = 0; r <= ranks; ++r)
    for (const double nudge : {-1e-17, 0.0, 1e-17})
      points.push_back({-0.3 + 0.7 * r / ranks + nudge, 0.1, 0.05});
  for (const Vec3d& x : points) {
    int holders = 0;
    for (int r = 0; r < ranks; ++r) {
      const bool in_box = slabs[r].local_box().contains(x);
      EXPECT_EQ(slabs[r].owns(x), in_box) << x.x << " rank " << r;
      holders += in_box;
      EXPECT_EQ(slabs[r].owner(x), slabs[0].owner(x));  // every rank agrees on the owner
    }
    EXPECT_EQ(holders, region.contains(x) ? 1 : 0) << x.x << " " << x.y << " " << x.z;
  }
  EXPECT_THROW(SlabDomain(Box(), 0, 2, 0, 0), std::invalid_argument);
  EXPECT_THROW(SlabDomain(region, 3, 2, 0, 0), std::invalid_argument);
  EXPECT_THROW(SlabDomain(region, 0, 2, 2, 0), std::invalid_argument);
}

TEST(Domain, SceneDomainTakesTheBoxAndTheReach) {
  const Scene scene = parse_scene(R"(time: {step: 1.0e-5, end: 0.01}
skin: 0.002
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  small: {sphere: 0.003, material: glass}
  large: {sphere: 0.005, material: glass}
particles:
  - explicit:
      - {template: small, position: [0, 0, 0]}
domain: {min: [-1, -1, -1], max: [1, 2, 3]}
)",
                                  "domain.yaml", ".");
  // 2 r_max + skin.
  EXPECT_DOUBLE_EQ(scene_halo_width(scene), 2 * 0.005 + 0.002);
  const std::unique_ptr<Domain> d = make_scene_domain(scene);
  EXPECT_EQ(d->local_box().max.y, 2);
  EXPECT_EQ(d->owner({0, 0, 3.5}), -1);
  EXPECT_DOUBLE_EQ(d->halo_width(), 0.012);
}

// A feed asked through two slab domains gives each rank its share: together exactly the
// particles one process inserts, none twice.
TEST(Domain, FeedsSplitOverSlabsWithoutLossOrDoubles) {
  const Scene scene = parse_scene(R"(time: {step: 1.0e-4, end: 0.1}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  ball: {sphere: 0.003, material: glass}
particles:
  - feed:
      template: ball
      region: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.05]}}
      rate: 20000
      seed: 4
domain: {min: [-0.01, -0.01, -0.01], max: [0.11, 0.11, 0.11]}
)",
                                  "feed.yaml", ".");
  const Box region = *scene.domain;
  Feeding one(scene), left(scene), right(scene);
  const SingleDomain single(region);
  const SlabDomain rank0(region, 0, 2, 0, 0), rank1(region, 0, 2, 1, 0);
  const double t = 0.005;  // 100 particles due
  const std::vector<ParticleState> all = one.insert(t, {}, {}, single);
  const std::vector<ParticleState> a = left.insert(t, {}, {}, rank0);
  const std::vector<ParticleState> b = right.insert(t, {}, {}, rank1);
  ASSERT_GE(all.size(), 90u);
  EXPECT_GT(a.size(), 10u);
  EXPECT_GT(b.size(), 10u);
  EXPECT_EQ(a.size() + b.size(), all.size());
  std::set<std::tuple<double, double, double>> seen;
  for (const auto* part : {&a, &b})
    for (const ParticleState& p : *part) {
      EXPECT_TRUE(seen.insert({p.position.x, p.position.y, p.position.z}).second);
    }
  for (const ParticleState& p : all)
    EXPECT_EQ(seen.count({p.position.x, p.position.y, p.position.z}), 1u);
}

}  // namespace
}  // namespace talus

namespace talus {
namespace {

// Points clustered in a corner of a tall box (a bed at the bottom of a silo): the bisection must
// follow the particles, not the box.
std::vector<Vec3d> bed_points(int n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3d> points;
  for (int i = 0; i < n; ++i) points.push_back({0.3 * u(random), 0.5 * u(random), 0.1 * u(random)});
  return points;
}

TEST(Domain, BisectionSplitsThePointsEvenlyAndOwnsEachOnce) {
  const std::vector<Vec3d> points = bed_points(1000, 7);
  for (const int ranks : {1, 2, 3, 4, 7}) {
    std::vector<int> count(ranks, 0);
    const RcbDomain d(points, Box(), ranks, 0, 0.01);
    ASSERT_EQ(d.ranks(), ranks);
    for (const Vec3d& x : points) {
      const int r = d.owner(x);
      ASSERT_GE(r, 0);
      ASSERT_LT(r, ranks);
      ++count[r];
      // The owner's box holds the point, and no other box does.
      for (int s = 0; s < ranks; ++s) EXPECT_EQ(d.box_of(s).contains(x), s == r);
    }
    // Each cut gives each half its share rounded down, so a rank holds 1000 / ranks give or take
    // one per level of cuts (3 levels for 7 ranks).
    for (int r = 0; r < ranks; ++r) EXPECT_NEAR(count[r], 1000.0 / ranks, 3.0) << ranks << " ranks";
  }
}

TEST(Domain, BisectionIsTheSameOnEveryRankAndCutsTheWidestExtent) {
  const std::vector<Vec3d> points = bed_points(500, 3);
  const RcbDomain a(points, Box(), 2, 0, 0.01), b(points, Box(), 2, 1, 0.01);
  EXPECT_EQ(a.local_box().max.y, b.local_box().min.y);  // y: the widest extent (0.5 m)
  EXPECT_EQ(a.box_of(1).min.y, b.local_box().min.y);
  EXPECT_TRUE(std::isinf(a.local_box().min.y));  // all space is owned: the outer faces open
  EXPECT_TRUE(std::isinf(b.local_box().max.x));
  for (const Vec3d& x : points) EXPECT_EQ(a.owner(x), b.owner(x));
}

TEST(Domain, BisectionKeepsTheRegionAndItsOutsideToNone) {
  const Box region = box({0, 0, 0}, {1, 1, 2});
  const RcbDomain d({{0.5, 0.5, 0.1}, {0.5, 0.5, 1.9}}, region, 2, 0, 0.01);
  EXPECT_EQ(d.owner({0.5, 0.5, 2.5}), -1);
  EXPECT_EQ(d.owner({0.5, 0.5, 0.1}), 0);
  EXPECT_EQ(d.owner({0.5, 0.5, 1.9}), 1);
  EXPECT_EQ(d.local_box().min.z, 0);  // the region's faces bound the boxes
  EXPECT_EQ(d.box_of(1).max.z, 2);
  // Without points the cut halves the region.
  const RcbDomain empty({}, region, 2, 1, 0.01);
  EXPECT_EQ(empty.local_box().min.z, 1);
  EXPECT_THROW(RcbDomain({}, region, 2, 2, 0.01), std::invalid_argument);
}

TEST(Domain, SquaredDistanceToABox) {
  const Box b = box({0, 0, 0}, {1, 1, 1});
  EXPECT_EQ(squared_distance(b, {0.5, 0.5, 0.5}), 0);
  EXPECT_DOUBLE_EQ(squared_distance(b, {2, 0.5, 0.5}), 1);
  EXPECT_DOUBLE_EQ(squared_distance(b, {-1, -1, 0.5}), 2);
  EXPECT_EQ(squared_distance(Box(), {1e300, 0, 0}), 0);  // all space
}

}  // namespace
}  // namespace talus
