// The overlap's step 2 by vertex masks (cull_by_masks, overlap_culling.hpp) must make the plane
// loop's decisions (cull_plane with the face-polygon test): the same kept planes, and the same
// separating-plane verdict where it exits. Both are exact filters (docs/geometry.md), so a
// difference would not show in the volume, only in the work: this compares the masks directly.
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
// may not), 60 poses each. The masks culling runs three times: with the templates' vertex
// records (the face test folded into the vertex pass), with their face_corners (a view without
// records) and with the face loops alone (neither): all four must agree exactly.
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
      ASSERT_NE(a.face_corners, nullptr);
      ASSERT_NE(a.vertex_records, nullptr);
      ConvexView<Real> a_corners = a, b_corners = b;
      a_corners.vertex_records = b_corners.vertex_records = nullptr;
      ConvexView<Real> a_loops = a_corners, b_loops = b_corners;
      a_loops.face_corners = b_loops.face_corners = nullptr;
      for (const auto& depth : depths) {
        for (int k = 0; k < 60; ++k) {
          const PosePair p = random_overlapping_pair(rng, sa.shape.bounding_radius,
                                                     sb.shape.bounding_radius, depth[0], depth[1]);
          const Pose<Real> pa = pose_of<Real>(p.a), pb = pose_of<Real>(p.b);
          OverlapFrame<Real> frame;
          OverlapResult<Real> unused;
          if (!overlap_frame(a, pa, b, pb, frame, unused)) continue;
          unsigned long long by_loop = 0, by_masks = 0, by_corners = 0, by_loops_masks = 0;
          OverlapStatus loop_status = OverlapStatus::overlapping;
          OverlapResult<Real> masks_result, corners_result, loops_result;
          const int m_loop = cull_by_loop(a, b, frame, by_loop, loop_status);
          const int m_masks = cull_by_masks(a, b, frame, by_masks, masks_result);
          const int m_corners =
              cull_by_masks(a_corners, b_corners, frame, by_corners, corners_result);
          const int m_loops = cull_by_masks(a_loops, b_loops, frame, by_loops_masks, loops_result);
          const std::string what = sa.shape.name + " / " + sb.shape.name + " pose " +
                                   std::to_string(k) + " depth " + std::to_string(depth[1]);
          ++compared;
          ASSERT_EQ(m_masks, m_loop) << what;
          ASSERT_EQ(m_corners, m_loop) << what;
          ASSERT_EQ(m_loops, m_loop) << what;
          if (m_loop < 0) {
            ++separated;
            EXPECT_EQ(masks_result.status, loop_status) << what;
            EXPECT_EQ(corners_result.status, loop_status) << what;
            EXPECT_EQ(loops_result.status, loop_status) << what;
          } else {
            kept_total += m_loop;
            EXPECT_EQ(by_masks, by_loop) << what;
            EXPECT_EQ(by_corners, by_loop) << what;
            EXPECT_EQ(by_loops_masks, by_loop) << what;
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

}  // namespace
}  // namespace talus
