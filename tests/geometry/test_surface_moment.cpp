// The overlap's surface moment M (overlap.hpp): the rate at which a rotation of A about its
// centroid x_A changes the overlap volume is e . (M + (c - x_A) x S), e the rotation's axis, which
// is what makes a law of the volume alone conserve energy with rotation (docs/contact.md). Checked
// against central differences of the volume over random overlapping pairs of every built-in shape,
// through both of the overlap's paths (the vertex enumeration and the dual hull), and at the
// wedge of the rounded retry (test_overlap_hard_cases.cpp's cylinders).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::testing {
namespace {

// dV/dtheta about axis e through A's centroid, by central differences of step h (rad).
double volume_rate(const TestShape& a, const Posed& pa, const TestShape& b, const Posed& pb,
                   const Vec3d& e, double h, OverlapOptions options) {
  Posed plus = pa, minus = pa;
  plus.orientation = Quatd::from_axis_angle(e, h) * pa.orientation;
  minus.orientation = Quatd::from_axis_angle(e, -h) * pa.orientation;
  return (overlap(a, plus, b, pb, options).volume - overlap(a, minus, b, pb, options).volume) /
         (2 * h);
}

// The rate the moment predicts against the difference. A central difference errs by h^2 / 6
// times the volume's third derivative in the angle (for these overlaps, of 2 % to 20 % of the
// radius, below 1e-7 of |S| R at h = 1e-5) plus the volume's round-off over h (V eps / h ~ 1e-11
// of |S| R): 1e-5 of |S| R bounds both with room, while leaving the moment out (the centroid as
// the only point) errs by |M|, ~1e-2 of |S| R and more (the test fails so).
void expect_rotation_rates(const TestShape& a, const Posed& pa, const TestShape& b, const Posed& pb,
                           OverlapOptions options, const std::string& what, double h = 1e-5) {
  const auto r = overlap(a, pa, b, pb, options);
  if (r.status != OverlapStatus::overlapping) return;
  const Vec3d torque_arm = r.surface_moment + cross(r.centroid - pa.position, r.vector_area);
  const double scale = norm(r.vector_area) * a.shape.bounding_radius;
  for (const Vec3d& e : {Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1)}) {
    const double rate = volume_rate(a, pa, b, pb, e, h, options);
    EXPECT_NEAR(dot(e, torque_arm), rate, 1e-5 * scale) << what;
  }
}

TEST(SurfaceMoment, IsTheVolumesRateUnderRotationForEveryShape) {
  std::mt19937_64 rng(7);
  int checked = 0, enumerated = 0;
  for (const std::string& spec : builtin_specs()) {
    const TestShape s(spec);
    for (int k = 0; k < 60; ++k) {
      const PosePair pair =
          random_overlapping_pair(rng, s.shape.bounding_radius, s.shape.bounding_radius, 0.02, 0.2);
      for (const bool enumerate : {true, false}) {
        OverlapOptions options;
        options.enumerate = enumerate;
        const auto r = overlap(s, pair.a, s, pair.b, options);
        if (r.status != OverlapStatus::overlapping) continue;
        ++checked;
        enumerated += r.enumerated;
        expect_rotation_rates(s, pair.a, s, pair.b, options, spec + " #" + std::to_string(k));
      }
    }
  }
  // Both paths seen: the draw must not leave either untested.
  EXPECT_GT(checked, 200);
  EXPECT_GT(enumerated, 20);
}

// A cube face down on a cube, tilted 1e-3 rad: a thin wedge whose moment is almost all of the
// couple (the centroid lies near the face's centre, the surface near the deeper edge).
TEST(SurfaceMoment, TiltedFaceOnFace) {
  const TestShape c("cube:0.01");
  const double side = 0.01 / std::sqrt(3.0);
  const Posed a{Vec3d(0, 0, 0), Quatd()};
  const Posed b{Vec3d(0.001, 0, side - 2e-6), Quatd::from_axis_angle(Vec3d(0, 1, 0), 1e-3)};
  for (const bool enumerate : {true, false}) {
    OverlapOptions options;
    options.enumerate = enumerate;
    expect_rotation_rates(c, input_frame_pose(c.shape, a.position), c,
                          input_frame_pose(c.shape, b.position, b.orientation), options,
                          enumerate ? "enumerated" : "hull");
  }
}

// The poured cylinders' wedge (2.7e-9 m deep, faces 8e-7 rad apart) at a pose whose first dual
// hull fails, so the rounded retry computes it. The wedge changes shape over a tilt of ~4e-7
// rad: h = 1e-10 rad keeps the difference's curvature error far below the bound, and its
// round-off, V eps / h = 1e-13 * 2e-16 / 1e-10 ~ 2e-19, is 1e-12 of |S| R (2e-7).
TEST(SurfaceMoment, WedgeOfTheRoundedRetry) {
  const TestShape c(wedge_cylinder_spec());
  const Posed a = wedge_cylinder_a();
  const Posed b = wedge_cylinder_b_retry();
  ASSERT_EQ(overlap(c, a, c, b).status, OverlapStatus::overlapping);
  expect_rotation_rates(c, a, c, b, OverlapOptions(), "wedge", 1e-10);
}

}  // namespace
}  // namespace talus::testing
