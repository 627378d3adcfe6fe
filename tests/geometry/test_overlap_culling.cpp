// The overlap's step 2 by vertex masks (cull_by_masks, overlap_culling.hpp) must make the plane
// loop's decisions (cull_plane with the face-polygon test): the same kept planes, and the same
// separating-plane verdict where it exits. Both are exact filters (docs/geometry.md), so a
// difference would not show in the volume, only in the work: this compares the masks directly.
// The masks' float pass (filtered_pass, for double templates, run on the GPU) must decide each
// plane as the double pass does, or hand it over: that is tested here, on the host, plane by
// plane, at heights inside and around its band.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using namespace overlap_detail;
using testing::pose_of;
using testing::TestShape;
using testing::view_of;

// The plane loop of overlap_cull_mask for templates the masks do not take: every plane of A, then
// of B, through cull_plane with the face test. -1 with `status` at a separating plane.
template <class Real>
int cull_by_loop(const ConvexView<Real>& a, const ConvexView<Real>& b,
                 const OverlapFrame<Real>& frame, unsigned long long& kept, OverlapStatus& status) {
  const ConvexView<Real>* body[2] = {&a, &b};
  kept = 0;
  int m = 0;
  const CullFrame<Real> cf = cull_frame(frame);
  for (int owner = 0; owner < 2; ++owner) {
    const FaceTestFrame<Real> face_frame = face_test_frame(frame, owner);
    for (int f = 0; f < body[owner]->n_faces; ++f) {
      Real lowest = 0;
      const PlaneCull cull =
          cull_plane(*body[owner], *body[1 - owner], frame, cf, owner, f, true, face_frame, lowest);
      if (cull == PlaneCull::beyond) {
        status = beyond_status(lowest, frame.round_off);
        return -1;
      }
      if (cull == PlaneCull::kept) {
        kept |= 1ull << ((owner == 0 ? 0 : a.n_faces) + f);
        ++m;
      }
    }
  }
  return m;
}

// Every pair of built-ins the masks take (at most 64 vertices each and 64 faces together), at
// shallow, medium and deep overlaps and just apart (the bounding spheres overlap, the bodies
// may not), 60 poses each: both must agree exactly. (On the host the masks run the double pass
// alone; the GPU's float pass is tested against it below.)
template <class Real>
void masks_match_loop() {
  std::vector<TestShape> shapes;
  for (const std::string& spec : testing::builtin_specs()) shapes.emplace_back(spec);
  std::mt19937_64 rng(20261123);
  const double depths[4][2] = {{-0.05, 0}, {0, 0.1}, {0.1, 0.3}, {0.3, 0.8}};
  int compared = 0, separated = 0, kept_total = 0;
  for (const TestShape& sa : shapes) {
    for (const TestShape& sb : shapes) {
      const ConvexView<Real> a = view_of<Real>(sa), b = view_of<Real>(sb);
      if (!culls_by_masks(a, b, OverlapOptions())) continue;
      ASSERT_NE(a.vertex_records, nullptr);
      for (const auto& depth : depths) {
        for (int k = 0; k < 60; ++k) {
          const PosePair p = random_overlapping_pair(rng, sa.shape.bounding_radius,
                                                     sb.shape.bounding_radius, depth[0], depth[1]);
          const Pose<Real> pa = pose_of<Real>(p.a), pb = pose_of<Real>(p.b);
          OverlapFrame<Real> frame;
          OverlapResult<Real> unused;
          if (!overlap_frame(a, pa, b, pb, frame, unused)) continue;
          unsigned long long by_loop = 0, by_masks = 0;
          OverlapStatus loop_status = OverlapStatus::overlapping;
          OverlapResult<Real> masks_result;
          const int m_loop = cull_by_loop(a, b, frame, by_loop, loop_status);
          const int m_masks = cull_by_masks(a, b, frame, by_masks, masks_result);
          const std::string what = sa.shape.name + " / " + sb.shape.name + " pose " +
                                   std::to_string(k) + " depth " + std::to_string(depth[1]);
          ++compared;
          ASSERT_EQ(m_masks, m_loop) << what;
          if (m_loop < 0) {
            ++separated;
            EXPECT_EQ(masks_result.status, loop_status) << what;
          } else {
            kept_total += m_loop;
            EXPECT_EQ(by_masks, by_loop) << what;
          }
        }
      }
    }
  }
  // The sweep must reach both exits: separating planes and kept planes (a shallow pair keeps
  // about 5; the deep ones many more).
  EXPECT_GT(compared, 1000);
  EXPECT_GT(separated, compared / 20) << compared;
  EXPECT_GT(kept_total, 4 * (compared - separated)) << compared;
}

TEST(OverlapCulling, MasksMakeThePlaneLoopsDecisionsInDouble) {
  masks_match_loop<double>();
}
TEST(OverlapCulling, MasksMakeThePlaneLoopsDecisionsInFloat) {
  masks_match_loop<float>();
}

// The float pass against the double pass, plane by plane: planes of random direction through
// each vertex of every double built-in that has the float vertices, shifted by heights from 0 to
// a tenth of the radius, both ways, so that the vertex lies inside the band (the float pass must
// hand the plane over), just outside it and far from it (it must decide as the double pass does:
// the same faces outside, the same beyond and below).
TEST(OverlapCulling, FloatPassDecidesAsTheDoublePassOrHandsOver) {
  std::mt19937_64 rng(20261124);
  std::normal_distribution<double> gauss;
  // Heights relative to the radius: 0 and the double round-off's scale (inside the band of
  // 12 * 2^-24 = 7.2e-7 relative, more with the offset), around the band, and far beyond it.
  const double shifts[] = {0, 1e-15, 1e-12, 1e-9, 1e-7, 5e-7, 7e-7, 1e-6, 2e-6, 1e-5, 1e-3, 0.1};
  int shapes = 0, decided = 0, handed_over = 0, far = 0, far_decided = 0;
  for (const std::string& spec : testing::builtin_specs()) {
    const TestShape s(spec);
    const ConvexView<double> filtered = s.view();
    if (!filtered.filter_vertices) continue;
    ++shapes;
    ConvexView<double> exact = filtered;
    exact.filter_vertices = nullptr;
    const double radius = filtered.bounding_radius;
    const double round_off = 64 * Eps<double>::value * 2 * radius;  // as overlap_frame's
    for (int k = 0; k < 40; ++k) {
      Vec3d n(gauss(rng), gauss(rng), gauss(rng));
      n = n * (1 / norm(n));
      for (int v = 0; v < filtered.n_vertices; ++v) {
        for (const double shift : shifts) {
          for (const double sign : {-1.0, 1.0}) {
            const double h = dot(n, filtered.vertices[v]) + sign * shift * radius;
            const PlanePass want = plane_pass(exact, n, h, round_off);
            PlanePass got;
            const std::string what =
                spec + " vertex " + std::to_string(v) + " shift " + std::to_string(sign * shift);
            const bool answered = filtered_pass(filtered, n, h, round_off, got);
            // The band is at least 12 * 2^-24 * R = 7.2e-7 R wide: a vertex nearer the plane
            // must hand it over.
            if (shift <= 5e-7) {
              EXPECT_FALSE(answered) << what;
            }
            if (shift >= 1e-5) {
              ++far;
              far_decided += answered;
            }
            if (!answered) {
              ++handed_over;
              continue;
            }
            ++decided;
            ASSERT_EQ(got.beyond, want.beyond) << what;
            ASSERT_EQ(got.below, want.below) << what;
            ASSERT_EQ(got.outside, want.outside) << what;
          }
        }
      }
    }
  }
  // The dodecahedron, cube, ... (at most 32 faces) have the float vertices; the sweep must reach
  // both branches. A plane 1e-5 R or more from the vertex it passes by is handed over only when
  // another vertex lies within the band, which random directions make rare: at least 90% of
  // them are decided in float.
  EXPECT_GE(shapes, 5);
  EXPECT_GT(handed_over, 0);
  EXPECT_GT(far_decided, 0.9 * far) << far_decided << " of " << far;
  RecordProperty("decided", decided);
  RecordProperty("handed_over", handed_over);
}

}  // namespace
}  // namespace talus
