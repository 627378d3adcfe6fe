// The dual-space overlap against the independent primal-clipping oracle (long double) on random
// poses of every built-in pair and of random convex hulls; the vector area against a
// finite-difference gradient of the volume.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "solver/shape/template_builder.hpp"
#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::testing {
namespace {

// Tolerances. The inputs (poses, template planes) are doubles: a surface of size L is placed
// with an absolute error of ~1e-16 L, so the volume of an overlap of depth d carries a relative
// error ~1e-16 L/d from the input alone, whatever the algorithm. Relative 1e-9 therefore holds
// down to d ~ 1e-6 L; below a volume of 1e-6 of the smaller body we compare absolutely against
// 1e-15 of that body's volume (the same input round-off, integrated over the contact area).
constexpr double kRelDouble = 1e-9;
constexpr double kRelFloat = 1e-4;
constexpr double kSmallFraction = 1e-6;

struct Stats {
  int compared = 0, overlapping = 0;
  double worst_volume = 0, worst_area = 0, worst_centroid = 0;
};

// Float: the poses are rounded to float first and the oracle is run on those rounded poses, so
// the comparison measures the float algorithm, not the rounding of its input. The templates'
// planes still carry float round-off (6e-8 of L), which moves the surfaces by ~6e-8 L: relative
// to an overlap deeper than 1e-3 L that is 6e-5, inside 1e-4. Shallower overlaps are not compared.
void check_float_against_oracle(const TestShape& a, const TestShape& b, const Posed& pa,
                                const Posed& pb, double scale_v) {
  const Pose<float> fa = to_float(pa), fb = to_float(pb);
  const Posed ra{Vec3d(fa.position), Quatd(fa.orientation).normalized()};
  const Posed rb{Vec3d(fb.position), Quatd(fb.orientation).normalized()};
  const OracleResult ref = oracle(a, ra, b, rb);
  const double ref_v = double(ref.volume);
  if (ref_v <= 1e-3 * scale_v) return;
  const auto f = overlap(a.view_f(), fa, b.view_f(), fb);
  ASSERT_EQ(f.status, OverlapStatus::overlapping);
  ASSERT_LE(std::abs(double(f.volume) - ref_v), kRelFloat * ref_v)
      << "float volume " << f.volume << " oracle " << ref_v;
  ASSERT_LE(norm(Vec3d(f.vector_area) - to_d(ref.vector_area_a)),
            kRelFloat * double(ref.boundary_area));
}

// Compares one pair against the oracle (fatal assertions on a mismatch).
void compare(const TestShape& a, const TestShape& b, const Posed& pa, const Posed& pb, Stats& stats,
             bool check_float) {
  const OracleResult ref = oracle(a, pa, b, pb);
  const auto got = overlap(a, pa, b, pb);
  const double scale_v = std::min(a.shape.volume, b.shape.volume);
  const double scale_l = std::cbrt(scale_v);
  const double ref_v = double(ref.volume);
  ++stats.compared;
  ASSERT_FALSE(got.workspace_overrun);
  ASSERT_NE(got.status, OverlapStatus::degenerate);
  const double dv = std::abs(got.volume - ref_v);
  if (ref_v > kSmallFraction * scale_v) {
    ++stats.overlapping;
    ASSERT_EQ(got.status, OverlapStatus::overlapping);
    ASSERT_LE(dv, kRelDouble * ref_v) << "volume " << got.volume << " oracle " << ref_v;
    stats.worst_volume = std::max(stats.worst_volume, dv / ref_v);
    // S: relative to the overlap's boundary area (S itself may be a small difference of faces).
    const double ds = norm(got.vector_area - to_d(ref.vector_area_a));
    const double area = double(ref.boundary_area);
    ASSERT_LE(ds, kRelDouble * area) << "vector area off by " << ds / area;
    stats.worst_area = std::max(stats.worst_area, ds / area);
    const double dc = norm(got.centroid - to_d(ref.centroid));
    ASSERT_LE(dc, kRelDouble * scale_l) << "centroid off by " << dc / scale_l;
    stats.worst_centroid = std::max(stats.worst_centroid, dc / scale_l);
    if (check_float && ref_v > 1e-3 * scale_v) check_float_against_oracle(a, b, pa, pb, scale_v);
  } else {
    ASSERT_LE(dv, 1e-15 * scale_v + kRelDouble * ref_v);
    if (ref_v == 0.0) {
      ASSERT_NE(got.status, OverlapStatus::overlapping);
    }
  }
}

class BuiltinPairAgainstOracle : public ::testing::TestWithParam<std::pair<int, int>> {};

// 10 000 random poses per built-in pair: half shallow (bounding-sphere overlap up to 10% of the
// radius sum, the typical dense-flow contact) and half deep.
TEST_P(BuiltinPairAgainstOracle, TenThousandRandomPoses) {
  const auto specs = builtin_specs();
  const auto [i, j] = GetParam();
  const TestShape a(specs[i]), b(specs[j]);
  std::mt19937_64 rng(1000 + 31 * i + j);
  Stats stats;
  for (int k = 0; k < 10000; ++k) {
    const bool shallow = k % 2 == 0;
    const auto pair = random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius,
                                              0.0, shallow ? 0.1 : 0.7);
    compare(a, b, pair.a, pair.b, stats, k % 4 == 1);
    if (HasFatalFailure()) {
      ADD_FAILURE() << specs[i] << " vs " << specs[j] << " pose " << k;
      return;
    }
  }
  // The sweep must exercise real overlaps, not only near misses: 1200 (corn, elongated, whose
  // bounding spheres overlap far more often than the kernels) to 5000 of them.
  EXPECT_GT(stats.overlapping, 1000);
  RecordProperty("worst_volume_rel", std::to_string(stats.worst_volume));
  RecordProperty("worst_area_rel", std::to_string(stats.worst_area));
}

std::vector<std::pair<int, int>> all_builtin_pairs() {
  std::vector<std::pair<int, int>> pairs;
  const int n = int(builtin_specs().size());
  for (int i = 0; i < n; ++i)
    for (int j = i; j < n; ++j) pairs.push_back({i, j});
  return pairs;
}

INSTANTIATE_TEST_SUITE_P(AllPairs, BuiltinPairAgainstOracle,
                         ::testing::ValuesIn(all_builtin_pairs()), [](const auto& info) {
                           auto name = [](int k) {
                             const std::string s = builtin_specs()[k];
                             return s.substr(0, s.find(':'));
                           };
                           return name(info.param.first) + "_" + name(info.param.second);
                         });

TEST(OverlapOracle, RandomConvexHullsOf8To40Points) {
  std::mt19937_64 rng(77);
  Stats stats;
  for (int h = 0; h < 400; ++h) {
    const int na = 8 + int(rng() % 33), nb = 8 + int(rng() % 33);
    const TestShape a(make_template("hull_a", random_convex_cloud(rng, na, 0.01)));
    const TestShape b(make_template("hull_b", random_convex_cloud(rng, nb, 0.007)));
    for (int k = 0; k < 25; ++k) {
      const auto pair =
          random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius, 0.0, 0.6);
      compare(a, b, pair.a, pair.b, stats, true);
      if (HasFatalFailure()) {
        ADD_FAILURE() << "hull pair " << h << " pose " << k << " (" << na << ", " << nb << ")";
        return;
      }
    }
  }
  EXPECT_GT(stats.overlapping, 2000);
}

// dV/dx_A = +S: central differences of the volume under translation of A along each axis.
// V is piecewise cubic in a translation, so the central difference is exact up to round-off
// ~1e-16 V / h and to the rare step crossing a change of the polytope's combinatorics; with
// h = 1e-6 L both stay below 1e-7 relative, and 1e-5 leaves room.
TEST(OverlapOracle, VectorAreaIsTheGradientOfTheVolume) {
  std::mt19937_64 rng(21);
  const auto specs = builtin_specs();
  int checked = 0;
  for (std::size_t s = 0; s < specs.size(); ++s) {
    const TestShape a(specs[s]), b(specs[(s + 2) % specs.size()]);
    for (int k = 0; k < 200; ++k) {
      const auto pair =
          random_overlapping_pair(rng, a.shape.bounding_radius, b.shape.bounding_radius, 0.1, 0.5);
      const auto base = overlap(a, pair.a, b, pair.b);
      if (base.volume < 1e-3 * std::min(a.shape.volume, b.shape.volume)) continue;
      const double h = 1e-6 * a.shape.bounding_radius;
      Vec3d gradient;
      for (int axis = 0; axis < 3; ++axis) {
        Posed plus = pair.a, minus = pair.a;
        plus.position[axis] += h;
        minus.position[axis] -= h;
        gradient[axis] =
            (overlap(a, plus, b, pair.b).volume - overlap(a, minus, b, pair.b).volume) / (2 * h);
      }
      ASSERT_LE(norm(gradient - base.vector_area), 1e-5 * norm(base.vector_area))
          << specs[s] << " pose " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
}

}  // namespace
}  // namespace talus::testing
