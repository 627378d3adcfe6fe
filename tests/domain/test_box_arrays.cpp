// The boxes as plain numbers (solver/domain/box_arrays.hpp), which the CUDA decomposition's kernels
// classify particles with: the same owner and the same squared distance to every box, to the bit,
// as RcbDomain::owner and squared_distance, for points inside, outside, on the cuts and on the
// region's faces, so that a GPU rank migrates and chooses ghosts as a host rank does.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "solver/domain/box_arrays.hpp"
#include "solver/domain/domain.hpp"

namespace talus {
namespace {

// Points to ask about: random ones in and around the region, every cut's coordinate exactly
// (the half-open faces), the region's faces, and one ulp either side of each.
std::vector<Vec3d> probe_points(const std::vector<double>& numbers, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  std::vector<Vec3d> points;
  for (int i = 0; i < 4000; ++i) points.push_back({u(random), 0.5 * u(random), 2.0 * u(random)});
  std::vector<double> planes[3];
  for (std::size_t k = 0; k < numbers.size(); ++k) {
    const double v = numbers[k];
    if (!std::isfinite(v)) continue;
    const int axis = static_cast<int>(k % kBoxNumbers) % 3;
    for (const double w : {v, std::nextafter(v, -HUGE_VAL), std::nextafter(v, HUGE_VAL)})
      planes[axis].push_back(w);
  }
  // Each plane's coordinate with random others, so that the faces and cuts are hit exactly.
  for (int axis = 0; axis < 3; ++axis) {
    for (const double w : planes[axis]) {
      for (int j = 0; j < 20; ++j) {
        double c[3] = {u(random), 0.5 * u(random), 2.0 * u(random)};
        c[axis] = w;
        points.push_back({c[0], c[1], c[2]});
      }
    }
  }
  return points;
}

void expect_same_answers(const RcbDomain& d, unsigned seed) {
  const bool bounded = d.region().bounded();
  const std::vector<double> numbers = box_numbers(d);
  ASSERT_EQ(numbers.size(), static_cast<std::size_t>(kBoxNumbers) * (d.ranks() + 1));
  int inside = 0, outside = 0;
  for (const Vec3d& x : probe_points(numbers, seed)) {
    const int owner = box_owner(numbers.data(), d.ranks(), x.x, x.y, x.z);
    ASSERT_EQ(owner, d.owner(x)) << x.x << " " << x.y << " " << x.z;
    (owner < 0 ? outside : inside) += 1;
    for (int r = 0; r < d.ranks(); ++r) {
      const double* b = numbers.data() + kBoxNumbers * (r + 1);
      // Bitwise: a ghost is chosen by `<= h^2`, and the host and the device must agree.
      ASSERT_EQ(box_squared_distance(b, x.x, x.y, x.z), squared_distance(d.box_of(r), x))
          << "rank " << r << " at " << x.x << " " << x.y << " " << x.z;
      ASSERT_EQ(box_holds(b, x.x, x.y, x.z), d.box_of(r).contains(x));
    }
  }
  // Both kinds were asked about (the points reach beyond a bounded region on every side).
  EXPECT_GT(inside, 1000);
  if (bounded) {
    EXPECT_GT(outside, 100);
  } else {
    EXPECT_EQ(outside, 0);
  }
}

TEST(BoxArrays, OwnerAndDistancesMatchTheBisection) {
  Box region;
  region.min = {0, 0, 0};
  region.max = {1, 0.5, 2};
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3d> bed;  // a bed in the lower part of the region
  for (int i = 0; i < 3000; ++i) bed.push_back({u(random), 0.5 * u(random), 0.4 * u(random)});
  for (const int ranks : {1, 2, 3, 4, 7, 16}) {
    SCOPED_TRACE(ranks);
    expect_same_answers(RcbDomain(bed, region, ranks, 0, 0.01), 100 + ranks);
  }
}

TEST(BoxArrays, OwnerWithPointsOutsideTheRegionAndAnOpenRegion) {
  // Particles beyond the region take part in the cuts (one outside stays with rank 0 until the
  // step removes it): a cut may then lie outside the region, which the owner must not follow.
  Box region;
  region.min = {0, 0, 0};
  region.max = {1, 0.5, 2};
  std::vector<Vec3d> points = {{0.1, 0.1, 0.1}, {0.2, 0.2, 0.2}, {5, 0.3, 0.3}, {6, 0.4, 3}};
  for (const int ranks : {2, 3, 4})
    expect_same_answers(RcbDomain(points, region, ranks, 0, 0.01), 7);
  // All of space as the region: the outer faces are infinite.
  expect_same_answers(RcbDomain(points, Box(), 3, 1, 0.01), 9);
  const std::vector<double> open = box_numbers(RcbDomain(points, Box(), 3, 1, 0.01));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(box_owner(open.data(), 3, nan, 0, 0), -1);  // NaN is in no box, as Box::contains
  // A NaN position is near no box (NaN <= h^2 is false), as on the host.
  Box unit;
  unit.min = {0, 0, 0};
  unit.max = {1, 1, 1};
  const double numbers[kBoxNumbers] = {0, 0, 0, 1, 1, 1};
  for (const Vec3d& x : {Vec3d{nan, 0.5, 0.5}, Vec3d{2, nan, 0.5}, Vec3d{-1, 0.5, nan}}) {
    EXPECT_TRUE(std::isnan(squared_distance(unit, x)));
    EXPECT_TRUE(std::isnan(box_squared_distance(numbers, x.x, x.y, x.z)));
  }
}

}  // namespace
}  // namespace talus
