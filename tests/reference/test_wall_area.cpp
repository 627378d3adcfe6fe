// The reference particle-triangle contact (reference/geometry/wall_area.hpp) against closed forms
// and against the production clipping (solver/geometry/wall_clip.hpp) on random poses.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "reference/geometry/wall_area.hpp"
#include "solver/geometry/wall_clip.hpp"
#include "tests/geometry/overlap_test_util.hpp"
#include "tests/reference/reference_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::reference {
namespace {

using namespace testing;  // at, box_vertices, to_eigen, kClosedRel (closed-form tolerance)

// A triangle far larger than the particles in the plane z = 0, normal +z.
const Eigen::Vector3d kBigA(-10, -10, 0), kBigB(20, -10, 0), kBigC(-10, 20, 0);

TEST(WallArea, BoxResting_SectionDepthVolumeCentroid) {
  const double lx = 0.01, ly = 0.012, lz = 0.014, h = 0.003;
  const ShapeTemplate box = box_vertices(lx, ly, lz);
  const RefWallContact w = wall_contact(box, at(0.3, -0.2, lz / 2 - h), kBigA, kBigB, kBigC);
  ASSERT_TRUE(w.reaches_plane);
  EXPECT_NEAR(w.section_area, lx * ly, kClosedRel * lx * ly);
  EXPECT_NEAR(w.overlap_area, lx * ly, kClosedRel * lx * ly);
  EXPECT_EQ(w.section_points, 4);
  EXPECT_NEAR(w.depth, h, kClosedRel * lz);
  EXPECT_NEAR(w.volume_below, lx * ly * h, kClosedRel * lx * ly * lz);
  EXPECT_LT((w.overlap_centroid - Eigen::Vector3d(0.3, -0.2, 0)).norm(), kClosedRel * lz);
  EXPECT_EQ(w.normal, Eigen::Vector3d(0, 0, 1));
  // Level: the volume below has its centroid right under the section's (its corners' rounded
  // coordinates still make an axis-aligned box), so the offset is exactly zero.
  EXPECT_LT((w.section_centroid - Eigen::Vector3d(0.3, -0.2, 0)).norm(), kClosedRel * lz);
  EXPECT_LT((w.volume_below_centroid - Eigen::Vector3d(0.3, -0.2, -0.5 * h)).norm(),
            kClosedRel * lz);
  EXPECT_EQ(w.volume_offset, Eigen::Vector3d::Zero());
}

TEST(WallArea, FlippedTriangle_BelowIsTheOtherSide) {
  // Reversing the corners flips the normal to -z: "below" is now z >= 0.
  const double lx = 0.01, ly = 0.012, lz = 0.014, h = 0.003;
  const ShapeTemplate box = box_vertices(lx, ly, lz);
  const RefWallContact w = wall_contact(box, at(0.3, -0.2, lz / 2 - h), kBigA, kBigC, kBigB);
  EXPECT_NEAR(w.volume_below, lx * ly * (lz - h), kClosedRel * lx * ly * lz);
  EXPECT_NEAR(w.depth, lz - h, kClosedRel * lz);
  EXPECT_NEAR(w.overlap_area, lx * ly, kClosedRel * lx * ly);
}

TEST(WallArea, SectionCutByTriangle_ClosedFormAreaAndCentroid) {
  // Square section [-s/2, s/2]^2 at z = 0; triangle x >= 0, y >= 0, x + y <= 3s/4 (in a tilted
  // copy of the frame below too). Common part: the quarter square minus its corner beyond the
  // hypotenuse, a right triangle with legs s/4.
  const double s = 0.016;
  const ShapeTemplate box = box_vertices(s, s, s);
  const double quarter = s * s / 4, corner = s * s / 32;
  const double area = quarter - corner;
  const double centroid_xy = (quarter * s / 4 - corner * 5 * s / 12) / area;
  // The same configuration rotated by q: plane, triangle and particle together.
  for (const Eigen::Quaterniond& q :
       {Eigen::Quaterniond::Identity(), Eigen::Quaterniond(0.8, 0.2, -0.4, 0.4).normalized()}) {
    const RefPose pose = at(0, 0, 0, q);
    const Eigen::Vector3d a = q * Eigen::Vector3d(0, 0, 0);
    const Eigen::Vector3d b = q * Eigen::Vector3d(0.75 * s, 0, 0);
    const Eigen::Vector3d c = q * Eigen::Vector3d(0, 0.75 * s, 0);
    const RefWallContact w = wall_contact(box, pose, a, b, c);
    ASSERT_TRUE(w.reaches_plane);
    EXPECT_NEAR(w.section_area, s * s, kClosedRel * s * s);
    EXPECT_NEAR(w.overlap_area, area, kClosedRel * s * s);
    EXPECT_LT((w.overlap_centroid - q * Eigen::Vector3d(centroid_xy, centroid_xy, 0)).norm(),
              kClosedRel * s);
    EXPECT_NEAR(w.volume_below, s * s * s / 2, kClosedRel * s * s * s);
    EXPECT_NEAR(w.depth, s / 2, kClosedRel * s);
  }
}

TEST(WallArea, AbovePlaneOrBesideTriangle_NoArea) {
  const ShapeTemplate box = box_vertices(0.01, 0.01, 0.01);
  // Above the plane by 1 mm: nothing.
  const RefWallContact above = wall_contact(box, at(0, 0, 0.006), kBigA, kBigB, kBigC);
  EXPECT_FALSE(above.reaches_plane);
  EXPECT_EQ(above.section_area, 0.0);
  EXPECT_EQ(above.volume_below, 0.0);
  // Through the plane, but beside a small triangle: a section, none of it on the triangle.
  const RefWallContact beside =
      wall_contact(box, at(0, 0, 0), Eigen::Vector3d(0.02, 0, 0), Eigen::Vector3d(0.03, 0, 0),
                   Eigen::Vector3d(0.02, 0.01, 0));
  EXPECT_TRUE(beside.reaches_plane);
  EXPECT_NEAR(beside.section_area, 1e-4, kClosedRel * 1e-4);
  EXPECT_EQ(beside.overlap_area, 0.0);
  EXPECT_NEAR(beside.volume_below, 5e-7, kClosedRel * 1e-6);
}

// Production against reference on random poses: triangles about the particle's size (so that the
// section is often cut by the triangle's edges), particle centres within 0.9 R of the plane.
// Both work from the same double vertices; the production's round-off (world offset up to 1 m,
// body-frame projection, Sutherland-Hodgman intersections, shoelace) is a few eps of 1 m in
// position, i.e. ~1e-14 of R, changing areas by ~1e-13 of the section's area (more for a sliver
// section near a vertex: measured 1.4e-11) and the volume by ~1e-14 of the particle's; 1e-9 of
// those scales is far above that and far below a missed corner or a wrong clip (order-one
// errors).
TEST(WallArea, AgreesWithProduction_RandomPoses) {
  const std::vector<std::string> specs = talus::testing::builtin_specs();
  std::mt19937_64 rng(77031);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int compared = 0, with_overlap_area = 0, above = 0, with_offset = 0;
  double worst_area = 0, worst_volume = 0, worst_centroid = 0, worst_depth = 0, worst_offset = 0;
  // 9 shapes x 64 draws = 576 poses, each slow with the exact kernel (its time:
  // benchmarks/history/README.md).
  for (const std::string& spec : specs) {
    const talus::testing::TestShape shape(spec);
    const double radius = shape.shape.bounding_radius;
    for (int draw = 0; draw < 64; ++draw) {
      const Vec3d normal = random_direction(rng);
      const Vec3d origin{unit(rng), unit(rng), unit(rng)};  // up to 1 m away: far, as walls are
      Vec3d u = cross(normal, std::abs(normal.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0});
      u = u / norm(u);
      const Vec3d v = cross(normal, u);
      // Corners within 1.5 R of the origin in the plane, counter-clockwise about +normal.
      Vec3d corner[3];
      for (int k = 0; k < 3; ++k) {
        const double angle = 2.0943951023931953 * k + 0.5 * unit(rng);
        const double r = radius * (0.6 + 0.9 * std::abs(unit(rng)));
        corner[k] = origin + u * (r * std::cos(angle)) + v * (r * std::sin(angle));
      }
      const Posed pose{origin + u * (radius * unit(rng)) + v * (radius * unit(rng)) +
                           normal * (0.9 * radius * unit(rng)),
                       random_rotation(rng)};
      const WallContact<double> prod =
          clip_against_triangle(shape.view(), pose, corner[0], corner[1], corner[2]);
      const RefWallContact ref = wall_contact(shape.shape, to_ref_pose(pose), to_eigen(corner[0]),
                                              to_eigen(corner[1]), to_eigen(corner[2]));
      ASSERT_NE(prod.status, WallContactStatus::degenerate);
      if (!ref.reaches_plane) {  // the centre is within 0.9 R, but the body may still miss
        EXPECT_EQ(prod.status, WallContactStatus::none) << spec << " draw " << draw;
        EXPECT_EQ(prod.section_area, 0.0) << spec << " draw " << draw;
        ++above;
        continue;
      }
      ++compared;
      // Relative to the section's area; a body wholly below the plane has none (both must say 0).
      const double section = std::max(ref.section_area, prod.section_area);
      const double da = section > 0 ? std::max(std::abs(prod.section_area - ref.section_area),
                                               std::abs(prod.overlap_area - ref.overlap_area)) /
                                          section
                                    : 0.0;
      const double dv = std::abs(prod.volume_below - ref.volume_below) / shape.shape.volume;
      const double dd = std::abs(prod.depth - ref.depth) / radius;
      worst_area = std::max(worst_area, da);
      worst_volume = std::max(worst_volume, dv);
      worst_depth = std::max(worst_depth, dd);
      EXPECT_LT(da, 1e-9) << spec << " draw " << draw;
      EXPECT_LT(dv, 1e-9) << spec << " draw " << draw;
      EXPECT_LT(dd, 1e-9) << spec << " draw " << draw;
      EXPECT_LT((to_eigen(prod.normal) - ref.normal).norm(), 1e-12);  // one unit vector, rounded
      // The centroid is area-weighted: compared where the clipped area is not a sliver.
      if (ref.overlap_area > 1e-3 * section) {
        ++with_overlap_area;
        const double dc = (to_eigen(prod.overlap_centroid) - ref.overlap_centroid).norm() / radius;
        worst_centroid = std::max(worst_centroid, dc);
        EXPECT_LT(dc, 1e-9) << spec << " draw " << draw;
      }
      // The volume laws' offset of the volume below from the section (a ratio of moments to the
      // volume): compared where neither the volume nor the section is a sliver.
      if (ref.volume_below > 1e-3 * shape.shape.volume &&
          ref.section_area > 1e-3 * radius * radius) {
        ++with_offset;
        const double doff = (to_eigen(prod.volume_offset) - ref.volume_offset).norm() / radius;
        worst_offset = std::max(worst_offset, doff);
        EXPECT_LT(doff, 1e-9) << spec << " draw " << draw;
        EXPECT_LT(std::abs(ref.volume_offset.dot(ref.normal)), 1e-15 * radius);  // in the plane
      }
    }
  }
  std::printf(
      "compared %d poses (%d with clipped area, %d more not reaching the plane, %d offsets); "
      "worst relative errors: area %.2e, volume below %.2e, depth %.2e, centroid %.2e, volume "
      "offset %.2e\n",
      compared, with_overlap_area, above, with_offset, worst_area, worst_volume, worst_depth,
      worst_centroid, worst_offset);
  EXPECT_GE(compared, 500);
  EXPECT_GE(with_overlap_area, 250);  // the sample must exercise the clipping, not only misses
  EXPECT_GE(with_offset, 250);
}

}  // namespace
}  // namespace talus::reference
