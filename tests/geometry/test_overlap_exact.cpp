// Exact cases, properties and the named hard cases of the dual-space overlap (paper §2.3).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::testing {
namespace {

// Double round-off: the overlap of shapes of size L is assembled from O(100) terms each with
// relative error ~1e-16, so 1e-12 relative is tight yet safe by two orders of magnitude.
constexpr double kExact = 1e-12;

void expect_finite(const OverlapResult<double>& r) {
  EXPECT_TRUE(std::isfinite(r.volume));
  EXPECT_TRUE(std::isfinite(r.vector_area.x) && std::isfinite(r.vector_area.y) &&
              std::isfinite(r.vector_area.z));
  EXPECT_TRUE(std::isfinite(r.centroid.x) && std::isfinite(r.centroid.y) &&
              std::isfinite(r.centroid.z));
  EXPECT_FALSE(r.workspace_overrun);
}

TEST(OverlapExact, AxisAlignedCuboidsOverlapInABox) {
  const TestShape a("cuboid:0.004,0.006,0.009"), b("cuboid:0.005,0.003,0.008");
  const Vec3d offset(0.0011, -0.0007, 0.0023);
  const auto r = overlap(a, input_frame_pose(a.shape, {}), b, input_frame_pose(b.shape, offset));
  // Intersection of [-2,2]x[-3,3]x[-4.5,4.5] mm with [-1.4,3.6]x[-2.2,0.8]x[-1.7,6.3] mm.
  const double lx = 2.0 - (-1.4), ly = 0.8 - (-2.2), lz = 4.5 - (-1.7);
  ASSERT_EQ(r.status, OverlapStatus::overlapping);
  EXPECT_NEAR(r.volume, lx * ly * lz * 1e-9, kExact * r.volume);
  EXPECT_NEAR(r.centroid.x, (2.0 - 1.4) / 2 * 1e-3, 1e-15);
  EXPECT_NEAR(r.centroid.y, (0.8 - 2.2) / 2 * 1e-3, 1e-15);
  EXPECT_NEAR(r.centroid.z, (4.5 - 1.7) / 2 * 1e-3, 1e-15);
  // A's faces on the boundary: +x (ly*lz), +y? no: B's top y=0.8 < 3 so it is B's; A's -y? B's
  // bottom -2.2 > -3, so B's too; A's +z face (4.5 < 6.3): lx*ly. Net S = (+x face) + (+z face).
  EXPECT_NEAR(r.vector_area.x, ly * lz * 1e-6, kExact * 1e-5);
  EXPECT_NEAR(r.vector_area.y, 0.0, kExact * 1e-5);
  EXPECT_NEAR(r.vector_area.z, lx * ly * 1e-6, kExact * 1e-5);
  expect_finite(r);
}

TEST(OverlapExact, EveryBuiltinAgainstACopyOfItselfIsItsVolume) {
  std::mt19937_64 rng(11);
  for (const auto& spec : builtin_specs()) {
    SCOPED_TRACE(spec);
    const TestShape s(spec);
    const Posed p{{0.3, -0.2, 0.1}, random_rotation(rng)};
    const auto r = overlap(s, p, s, p);
    ASSERT_EQ(r.status, OverlapStatus::overlapping);
    EXPECT_NEAR(r.volume, s.shape.volume, kExact * s.shape.volume);
    // All faces are twins: each counts half to A and half to B, and a closed surface sums to 0.
    EXPECT_LT(norm(r.vector_area), kExact * std::pow(s.shape.volume, 2.0 / 3.0));
    EXPECT_LT(norm(r.centroid - p.position), kExact * 1.0);  // |position| ~ 0.4 m
    expect_finite(r);
  }
}

TEST(OverlapExact, NestedShapeGivesTheInnerVolume) {
  const TestShape outer("dodecahedron:0.02"), inner("icosahedron:0.006");
  std::mt19937_64 rng(3);
  for (int i = 0; i < 50; ++i) {
    const Posed pa{{0, 0, 0}, random_rotation(rng)};
    const Posed pb{{0.001, -0.0015, 0.002}, random_rotation(rng)};
    const auto r = overlap(outer, pa, inner, pb);
    ASSERT_EQ(r.status, OverlapStatus::overlapping);
    EXPECT_NEAR(r.volume, inner.shape.volume, kExact * inner.shape.volume);
    // The whole boundary is B's: S on A's surface is zero.
    EXPECT_LT(norm(r.vector_area), 1e-18);
    const auto swapped = overlap(inner, pb, outer, pa);
    EXPECT_NEAR(swapped.volume, inner.shape.volume, kExact * inner.shape.volume);
  }
}

TEST(OverlapExact, TouchingShapesHaveZeroVolume) {
  const TestShape cube("cube:0.01");
  const double side = 0.01 / std::sqrt(3.0);
  const Posed pa = input_frame_pose(cube.shape, {});
  // Face to face, edge to edge (diagonal offset), corner to corner.
  for (const Vec3d offset : {Vec3d(side, 0, 0), Vec3d(side, side, 0), Vec3d(side, side, side),
                             Vec3d(side, 0.3 * side, -0.2 * side)}) {
    const auto r = overlap(cube, pa, cube, input_frame_pose(cube.shape, offset));
    EXPECT_EQ(r.status, OverlapStatus::touching);
    EXPECT_EQ(r.volume, 0.0);
    expect_finite(r);
  }
  const auto apart = overlap(cube, pa, cube, input_frame_pose(cube.shape, {side * 1.001, 0, 0}));
  EXPECT_EQ(apart.status, OverlapStatus::separate);
}

TEST(OverlapProperties, SymmetryAntisymmetryInvarianceAndBound) {
  std::mt19937_64 rng(5);
  const auto specs = builtin_specs();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const TestShape a(specs[i]), b(specs[(i + 4) % specs.size()]);
    for (int k = 0; k < 300; ++k) {
      const auto pair =
          random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius, 0.0, 0.8);
      const auto ab = overlap(a, pair.a, b, pair.b);
      const auto ba = overlap(b, pair.b, a, pair.a);
      const double scale_v = std::min(a.shape.volume, b.shape.volume);
      const double scale_s = std::pow(scale_v, 2.0 / 3.0);
      // Swapping the roles changes which planes are A's, not the polytope: round-off only.
      EXPECT_NEAR(ab.volume, ba.volume, kExact * scale_v);
      EXPECT_LT(norm(ab.vector_area + ba.vector_area), 1e-10 * scale_s);
      EXPECT_LE(ab.volume, scale_v * (1 + kExact));
      // A common rigid motion moves the polytope with the bodies.
      const Quatd q = random_rotation(rng);
      const Vec3d t(0.5, -1.0, 2.0);
      const Posed ma{t + rotate(q, pair.a.position), q * pair.a.orientation};
      const Posed mb{t + rotate(q, pair.b.position), q * pair.b.orientation};
      const auto moved = overlap(a, ma, b, mb);
      // Positions near 2 m carry 2e-16 m round-off against mm shapes: 1e-10 relative.
      EXPECT_NEAR(moved.volume, ab.volume, 1e-10 * scale_v);
      EXPECT_LT(norm(moved.vector_area - rotate(q, ab.vector_area)), 1e-9 * scale_s);
      if (ab.volume > 1e-6 * scale_v) {
        EXPECT_LT(norm(moved.centroid - (t + rotate(q, ab.centroid))), 1e-11);
      }
    }
  }
}

}  // namespace
}  // namespace talus::testing

namespace talus::testing {
namespace {

// The plane filters only drop planes that cannot bound the intersection: the naive hull of every
// plane, the plane filter and both filters build the same polytope, so the numbers agree to
// round-off (the hulls differ in their interior points only: 1e-12 relative).
TEST(OverlapProperties, CullingVariantsGiveTheSamePolytope) {
  std::mt19937_64 rng(31);
  const auto specs = builtin_specs();
  int overlapping = 0;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const TestShape a(specs[i]), b(specs[(i + 5) % specs.size()]);
    for (int k = 0; k < 400; ++k) {
      const auto pair =
          random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius, 0.0, 0.6);
      const auto faces = overlap(a, pair.a, b, pair.b, overlap_options_named("faces"));
      const double scale_v = std::min(a.shape.volume, b.shape.volume);
      const double scale_s = std::pow(scale_v, 2.0 / 3.0);
      overlapping += faces.status == OverlapStatus::overlapping;
      for (const char* variant : {"planes", "naive"}) {
        const auto other = overlap(a, pair.a, b, pair.b, overlap_options_named(variant));
        ASSERT_NEAR(other.volume, faces.volume, kExact * scale_v) << variant << " " << k;
        ASSERT_LT(norm(other.vector_area - faces.vector_area), 1e-10 * scale_s) << variant;
      }
    }
  }
  EXPECT_GT(overlapping, 1000);
  EXPECT_THROW(overlap_options_named("fast"), std::invalid_argument);
}

}  // namespace
}  // namespace talus::testing
