// The vertex enumeration (vertex_enumeration.hpp), the overlap's fast path for a few kept planes:
// it must agree with the dual hull and the oracle wherever it answers, answer for most shallow
// contacts (else it is no fast path), and decline every degenerate contact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::testing {
namespace {

// The enumeration and the dual hull compute the same polytope with different arithmetic (Cramer
// vertices and fans from the face means against the polar hull's): both carry the input's
// round-off ~1e-16 L / d relative for an overlap of depth d (test_overlap_oracle.cpp). Compared
// above 1e-6 of the smaller volume, that is 1e-10; 1e-9 is the oracle tests' tolerance.
constexpr double kRel = 1e-9;
constexpr double kSmallFraction = 1e-6;

std::string format_g(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

struct Sweep {
  int overlapping = 0;  // overlaps above kSmallFraction of the smaller volume
  int enumerated = 0;   // of those, answered by the enumeration
  double worst = 0;     // worst relative difference (volume, S, centroid) against the hull
};

// Shallow random poses of a and b (bounding-sphere overlap up to `depth` of the radius sum): the
// default options (enumeration first) against the dual hull alone ("faces") and, every fourth
// pose, the oracle.
Sweep sweep(const TestShape& a, const TestShape& b, int poses, double depth, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Sweep s;
  const double scale_v = std::min(a.shape.volume, b.shape.volume);
  const double scale_l = std::cbrt(scale_v);
  for (int k = 0; k < poses; ++k) {
    const auto pair =
        random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius, 0.0, depth);
    const auto fast = overlap(a, pair.a, b, pair.b);
    const auto hull = overlap(a, pair.a, b, pair.b, overlap_options_named("faces"));
    EXPECT_FALSE(hull.enumerated);
    if (!fast.enumerated) {
      // Declined: the same path as without the enumeration, bit for bit.
      EXPECT_EQ(fast.volume, hull.volume) << k;
      EXPECT_EQ(fast.status, hull.status) << k;
      if (hull.volume > kSmallFraction * scale_v) ++s.overlapping;
      continue;
    }
    // It only ever answers "overlapping", and then the hull must agree.
    EXPECT_EQ(fast.status, OverlapStatus::overlapping) << k;
    EXPECT_EQ(hull.status, OverlapStatus::overlapping) << k;
    EXPECT_GT(fast.depth_hint, 0.0) << k;
    EXPECT_LE(fast.depth_hint, hull.depth_hint * (1 + 1e-9)) << "depth_hint must be <= inradius";
    EXPECT_EQ(fast.hull_points, hull.hull_points) << k;
    if (hull.volume <= kSmallFraction * scale_v) continue;
    ++s.overlapping;
    ++s.enumerated;
    const double dv = std::abs(fast.volume - hull.volume) / hull.volume;
    const double area = std::pow(hull.volume, 2.0 / 3.0);  // the overlap's own area scale
    const double ds =
        norm(fast.vector_area - hull.vector_area) / std::max(area, norm(hull.vector_area));
    const double dc = norm(fast.centroid - hull.centroid) / scale_l;
    s.worst = std::max({s.worst, dv, ds, dc});
    EXPECT_LE(dv, kRel) << "volume " << fast.volume << " hull " << hull.volume << " pose " << k;
    EXPECT_LE(ds, kRel) << "vector area, pose " << k;
    EXPECT_LE(dc, kRel) << "centroid, pose " << k;
    if (k % 4 == 0) {
      const OracleResult ref = oracle(a, pair.a, b, pair.b);
      const double ref_v = double(ref.volume);
      EXPECT_LE(std::abs(fast.volume - ref_v), kRel * ref_v) << "against the oracle, pose " << k;
      EXPECT_LE(norm(fast.vector_area - to_d(ref.vector_area_a)), kRel * double(ref.boundary_area));
      EXPECT_LE(norm(fast.centroid - to_d(ref.centroid)), kRel * scale_l);
    }
    if (::testing::Test::HasFailure()) break;
  }
  return s;
}

// Every built-in against a few others, shallow: agreement wherever the enumeration answers.
TEST(VertexEnumeration, AgreesWithTheDualHullAndTheOracle) {
  const auto specs = builtin_specs();
  int overlapping = 0, enumerated = 0;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    for (std::size_t shift : {0u, 2u, 5u}) {
      const TestShape a(specs[i]), b(specs[(i + shift) % specs.size()]);
      const Sweep s = sweep(a, b, 1000, 0.3, 77 + 13 * i + shift);
      overlapping += s.overlapping;
      enumerated += s.enumerated;
      RecordProperty(specs[i] + "_" + std::to_string(shift) + "_worst", format_g(s.worst));
      if (HasFailure()) {
        ADD_FAILURE() << specs[i] << " vs " << specs[(i + shift) % specs.size()];
        return;
      }
    }
  }
  // The sweep must exercise the fast path on real overlaps.
  EXPECT_GT(overlapping, 5000);
  EXPECT_GT(enumerated, overlapping / 2);
  RecordProperty("enumerated", enumerated);
  RecordProperty("overlapping", overlapping);
}

// The fast path's purpose: shallow dodecahedron contacts (the dense bed's) almost all take it.
TEST(VertexEnumeration, AnswersMostShallowDodecahedronContacts) {
  const TestShape a("dodecahedron:0.01"), b("dodecahedron:0.01");
  const Sweep s = sweep(a, b, 4000, 0.25, 5);
  ASSERT_FALSE(HasFailure());
  ASSERT_GT(s.overlapping, 1000);
  EXPECT_GT(s.enumerated, 0.9 * s.overlapping)
      << s.enumerated << " of " << s.overlapping << " enumerated";
  RecordProperty("enumerated_fraction", format_g(double(s.enumerated) / s.overlapping));
}

// Float: the enumeration in float against the oracle on the float-rounded poses, above 1e-3 of
// the body's volume, where the templates' float round-off (6e-8 L) stays under 1e-4 relative
// (test_overlap_oracle.cpp gives the argument).
TEST(VertexEnumeration, FloatAgreesWithTheOracle) {
  const TestShape a("dodecahedron:0.01"), b("icosahedron:0.009");
  std::mt19937_64 rng(19);
  const double scale_v = std::min(a.shape.volume, b.shape.volume);
  int compared = 0, enumerated = 0;
  for (int k = 0; k < 6000; ++k) {
    const auto pair =
        random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius, 0.0, 0.3);
    const Pose<float> fa = to_float(pair.a), fb = to_float(pair.b);
    const Posed ra{Vec3d(fa.position), Quatd(fa.orientation).normalized()};
    const Posed rb{Vec3d(fb.position), Quatd(fb.orientation).normalized()};
    const auto f = overlap(a.view_f(), fa, b.view_f(), fb);
    if (!f.enumerated) continue;
    ++enumerated;
    const OracleResult ref = oracle(a, ra, b, rb);
    const double ref_v = double(ref.volume);
    if (ref_v <= 1e-3 * scale_v) continue;
    ++compared;
    ASSERT_LE(std::abs(double(f.volume) - ref_v), 1e-4 * ref_v) << k;
    ASSERT_LE(norm(Vec3d(f.vector_area) - to_d(ref.vector_area_a)),
              1e-4 * double(ref.boundary_area))
        << k;
  }
  EXPECT_GT(compared, 300);
  EXPECT_GT(enumerated, compared);
  RecordProperty("compared", compared);
}

// Degenerate contacts are declined and left to the dual hull.
TEST(VertexEnumeration, DeclinesWhereFourPlanesMeet) {
  const TestShape cube("cube:0.01");
  const double side = 0.01 / std::sqrt(3.0);
  // Face on face, aligned, overlapping by 1% of the side: the overlap is a box whose corners are
  // each on 3 planes of one cube and a twin-free plane of the other... its side faces are twins
  // (coincident planes of both cubes), so every corner has four planes through it.
  const Posed a{Vec3d(0, 0, 0), Quatd()};
  const Posed b{Vec3d(0, 0, side * 0.99), Quatd()};
  const auto r = overlap(cube, a, cube, b);
  EXPECT_EQ(r.status, OverlapStatus::overlapping);
  EXPECT_FALSE(r.enumerated);
  EXPECT_NEAR(r.volume, side * side * side * 0.01, 1e-9 * side * side * side * 0.01);
  // Coincident copies: every plane has a twin.
  const TestShape dodeca("dodecahedron:0.01");
  const Posed p{Vec3d(0.1, -0.2, 0.3), Quatd(0.9, 0.1, -0.3, 0.2).normalized()};
  const auto same = overlap(dodeca, p, dodeca, p);
  EXPECT_FALSE(same.enumerated);
  EXPECT_NEAR(same.volume, dodeca.shape.volume, 1e-12 * dodeca.shape.volume);
}

// A body strictly inside another keeps only its own planes: the enumeration gives its volume and
// centroid; the outer body's planes are all culled. (A cube: three faces at each corner. An
// octahedron's corners have four and are declined.)
TEST(VertexEnumeration, NestedBodyIsEnumerated) {
  const TestShape outer("cube:0.05"), inner("cube:0.01");
  const Posed a{Vec3d(1, 2, 3), Quatd(0.8, 0.2, 0.1, -0.3).normalized()};
  const Posed b{Vec3d(1.002, 2.001, 2.999), Quatd(0.3, -0.5, 0.7, 0.1).normalized()};
  const auto r = overlap(outer, a, inner, b);
  EXPECT_TRUE(r.enumerated);
  EXPECT_EQ(r.hull_points, 6);
  EXPECT_NEAR(r.volume, inner.shape.volume, 1e-12 * inner.shape.volume);
  EXPECT_LT(norm(r.centroid - b.position), 1e-12 * 0.01);
  // All of the boundary lies on B: S (on A's surface) is zero.
  EXPECT_LT(norm(r.vector_area), 1e-12 * 0.01 * 0.01);
}

}  // namespace
}  // namespace talus::testing
