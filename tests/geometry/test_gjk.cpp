// GJK (Algorithm I) against the exact overlap: it is the narrow-phase filter, so it must never
// call an overlapping pair separate, should call clearly separate pairs separate, and must stop
// within its iteration bound.
#include <gtest/gtest.h>

#include <random>

#include "solver/geometry/gjk.hpp"
#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::testing {
namespace {

TEST(Gjk, AgreesWithTheExactOverlapOnEveryBuiltinPair) {
  const auto specs = builtin_specs();
  std::mt19937_64 rng(8);
  int overlapping = 0, separate = 0;
  for (std::size_t i = 0; i < specs.size(); ++i)
    for (std::size_t j = i; j < specs.size(); ++j) {
      const TestShape a(specs[i]), b(specs[j]);
      const double scale = a.shape.bounding_radius + b.shape.bounding_radius;
      for (int k = 0; k < 1000; ++k) {
        const auto pair = random_overlapping_pair(rng, a.shape.bounding_radius,
                                                  b.shape.bounding_radius, 0.0, 0.5);
        const auto gjk = gjk_intersect(a.view(), pair.a, b.view(), pair.b);
        ASSERT_FALSE(gjk.iteration_limit_hit) << specs[i] << " " << specs[j] << " " << k;
        // Without culling the LP runs on every pair: its depth is the signed Chebyshev depth of
        // the planes' intersection, negative with a margin when the bodies are apart.
        OverlapOptions all_planes;
        all_planes.cull_planes = false;
        const auto exact = overlap(a, pair.a, b, pair.b, all_planes);
        if (exact.volume > 0) {
          ++overlapping;
          ASSERT_TRUE(gjk.intersecting) << specs[i] << " " << specs[j] << " pose " << k;
        } else if (exact.depth_hint < -1e-9 * scale) {
          // Clearly apart (more than round-off, 1e-9 of the size): GJK finds the separating
          // direction.
          ++separate;
          ASSERT_FALSE(gjk.intersecting) << specs[i] << " " << specs[j] << " pose " << k;
        }
      }
    }
  EXPECT_GT(overlapping, 10000);
  EXPECT_GT(separate, 5000);
}

TEST(Gjk, TouchingCountsAsIntersecting) {
  const TestShape c("cube:0.017320508075688773");  // side 0.01
  const Posed pa = input_frame_pose(c.shape, {});
  for (const Vec3d offset : {Vec3d(0.01, 0, 0), Vec3d(0.01, 0.01, 0), Vec3d(0.01, 0.01, 0.01)}) {
    const auto r = gjk_intersect(c.view(), pa, c.view(), input_frame_pose(c.shape, offset));
    EXPECT_TRUE(r.intersecting);
    EXPECT_LE(r.iterations, 64);
  }
  const auto apart =
      gjk_intersect(c.view(), pa, c.view(), input_frame_pose(c.shape, {0.0101, 0, 0}));
  EXPECT_FALSE(apart.intersecting);
}

}  // namespace
}  // namespace talus::testing
