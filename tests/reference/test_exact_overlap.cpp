// The reference overlap (reference/geometry/exact_overlap.hpp) against closed forms, against
// the production dual-space overlap (solver/geometry/overlap_polyhedra.hpp) on random poses, and
// its surface moment against the rate of its volume under a turn.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <random>

#include "reference/geometry/exact_overlap.hpp"
#include "tests/geometry/overlap_test_util.hpp"
#include "tests/reference/reference_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::reference {
namespace {

using namespace testing;  // at, box_vertices, to_eigen, kClosedRel

TEST(ExactOverlap, AxisAlignedBoxes_VolumeCentroidVectorArea) {
  // Sides 10, 12, 14 mm; B moved by (8, 1, 0.5) mm: the overlap is the box 2 x 11 x 13.5 mm
  // spanning x in [3, 5], y in [-5, 6], z in [-6.5, 7] mm.
  const ShapeTemplate a = box_vertices(0.010, 0.012, 0.014);
  const RefOverlap r = exact_overlap(a, at(0, 0, 0), a, at(0.008, 0.001, 0.0005));
  ASSERT_TRUE(r.overlapping);
  EXPECT_FALSE(r.touching);
  const double v = 0.002 * 0.011 * 0.0135;
  EXPECT_NEAR(r.volume, v, kClosedRel * v);
  const Eigen::Vector3d c(0.004, 0.0005, 0.00025);
  EXPECT_LT((r.centroid - c).norm(), kClosedRel * 0.01);
  // On A: its +x face (11 x 13.5), +y face (2 x 13.5), +z face (2 x 11), in mm^2.
  const Eigen::Vector3d s(0.011 * 0.0135, 0.002 * 0.0135, 0.002 * 0.011);
  EXPECT_LT((r.vector_area_a - s).norm(), kClosedRel * s.norm());
  const double boundary = 2 * (0.002 * 0.011 + 0.002 * 0.0135 + 0.011 * 0.0135);
  EXPECT_NEAR(r.boundary_area, boundary, kClosedRel * boundary);
}

TEST(ExactOverlap, SwappedBodies_VectorAreaReverses) {
  // dV/dx_B = -S: the same overlap seen from B has the opposite vector area (its faces on B are
  // x = 3, y = -5, z = -6.5 mm, with the same areas as A's faces above).
  const ShapeTemplate a = box_vertices(0.010, 0.012, 0.014);
  const RefOverlap ab = exact_overlap(a, at(0, 0, 0), a, at(0.008, 0.001, 0.0005));
  const RefOverlap ba = exact_overlap(a, at(0.008, 0.001, 0.0005), a, at(0, 0, 0));
  EXPECT_LT((ab.vector_area_a + ba.vector_area_a).norm(), kClosedRel * ab.vector_area_a.norm());
  EXPECT_NEAR(ab.volume, ba.volume, kClosedRel * ab.volume);
}

TEST(ExactOverlap, SharedFace_CountsHalf) {
  // A: 0.5 x 0.25 x 0.125 m. B: a 0.0625 m cube whose top is A's top (z = 0.0625) and which sticks
  // out through A's +x face (x = 0.25). The overlap is x in [0.21875, 0.25], |y| <= 0.03125,
  // z in [0, 0.0625]: its +x face lies on A only (weight 1), its top on both (weight 1/2).
  const ShapeTemplate a = box_vertices(0.5, 0.25, 0.125);
  const ShapeTemplate b = box_vertices(0.0625, 0.0625, 0.0625);
  const RefOverlap r = exact_overlap(a, at(0, 0, 0), b, at(0.25, 0, 0.03125));
  ASSERT_TRUE(r.overlapping);
  const double v = 0.03125 * 0.0625 * 0.0625;
  EXPECT_NEAR(r.volume, v, kClosedRel * v);
  const Eigen::Vector3d s(0.0625 * 0.0625, 0, 0.5 * 0.03125 * 0.0625);
  EXPECT_LT((r.vector_area_a - s).norm(), kClosedRel * s.norm());
}

TEST(ExactOverlap, CopyOfItself_TemplateVolumeZeroVectorArea) {
  // Every facet lies on both surfaces and counts half: the halves of a closed surface sum to 0.
  for (const std::string spec : {"dodecahedron:0.01", "mineral:0.01", "cylinder:0.008,0.0053"}) {
    const ShapeTemplate s = make_builtin(spec);
    const RefPose pose = at(0.3, -0.1, 0.02, Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized());
    const RefOverlap r = exact_overlap(s, pose, s, pose);
    ASSERT_TRUE(r.overlapping) << spec;
    EXPECT_NEAR(r.volume, s.volume, kClosedRel * s.volume) << spec;
    EXPECT_LT((r.centroid - pose.position).norm(), kClosedRel * s.bounding_radius) << spec;
    EXPECT_LT(r.vector_area_a.norm(), kClosedRel * r.boundary_area) << spec;
    EXPECT_GT(r.boundary_area, 0.0) << spec;
  }
}

TEST(ExactOverlap, Nested_SmallBodyVolumeZeroVectorArea) {
  // A small icosahedron well inside a large cube: the overlap is the small body; none of its
  // facets lies on the cube, and as A the small body's closed surface sums to zero.
  const ShapeTemplate big = box_vertices(0.05, 0.05, 0.05);
  const ShapeTemplate small = make_builtin("icosahedron:0.01");
  const RefPose small_pose = at(0.003, -0.002, 0.004, Eigen::Quaterniond(0.6, 0.8, 0, 0));
  for (bool small_is_a : {false, true}) {
    const RefOverlap r = small_is_a ? exact_overlap(small, small_pose, big, at(0, 0, 0))
                                    : exact_overlap(big, at(0, 0, 0), small, small_pose);
    ASSERT_TRUE(r.overlapping);
    EXPECT_NEAR(r.volume, small.volume, kClosedRel * small.volume);
    EXPECT_LT((r.centroid - small_pose.position).norm(), kClosedRel * 0.01);
    EXPECT_LT(r.vector_area_a.norm(), kClosedRel * r.boundary_area);
  }
}

TEST(ExactOverlap, Touching_ZeroVolumeNotOverlapping) {
  // Binary-exact sizes and offsets, so the contact is exactly a face, an edge or a corner.
  const ShapeTemplate box = box_vertices(0.5, 0.25, 0.125);
  const struct {
    double x, y, z;
  } offsets[] = {{0.5, 0.0, 0.0},      // face to face (partial: y shifted below)
                 {0.5, 0.125, 0.0},    // face to face, half the face
                 {0.5, 0.25, 0.0},     // edge to edge
                 {0.5, 0.25, 0.125}};  // corner to corner
  for (const auto& o : offsets) {
    const RefOverlap r = exact_overlap(box, at(0, 0, 0), box, at(o.x, o.y, o.z));
    EXPECT_TRUE(r.touching) << o.x << " " << o.y << " " << o.z;
    EXPECT_FALSE(r.overlapping);
    EXPECT_EQ(r.volume, 0.0);
    EXPECT_EQ(r.vector_area_a.norm(), 0.0);
  }
  // One ulp-scale gap (2^-40 m) apart: separate.
  const RefOverlap gap = exact_overlap(box, at(0, 0, 0), box, at(0.5 + std::ldexp(1.0, -40), 0, 0));
  EXPECT_FALSE(gap.touching);
  EXPECT_FALSE(gap.overlapping);
  // The same gap the other way: a slab 2^-40 m thick, volume 0.25 * 0.125 * 2^-40 exactly.
  const RefOverlap thin =
      exact_overlap(box, at(0, 0, 0), box, at(0.5 - std::ldexp(1.0, -40), 0, 0));
  ASSERT_TRUE(thin.overlapping);
  const double v = 0.25 * 0.125 * std::ldexp(1.0, -40);
  EXPECT_NEAR(thin.volume, v, 1e-6 * v);  // about a vertex 0.5 m away: 2^-40 / 2^-53 ulps lost
}

// Production against reference on random pose pairs of the built-ins. Both compute the same
// polytope from the same double vertices; they differ by the round-off of the production's own
// world transform, plane offsets and dual-space hull: a few hundred eps of the particle size R in
// position (~1e-16 m here). A boundary displaced by delta changes V by at most A_P delta and S by
// at most (perimeter of the facets) delta ~ A_P delta / (facet size). Relative to the overlap's
// boundary area A_P (for S) and to A_P R (for V, which is >= 3 V for a convex body inside a
// sphere of radius R), 1e-9 is far above that round-off (1e-13) and far below any error of a
// misplaced facet, a missed vertex or a wrong weight (those are relative errors of order the
// facet's share of the boundary).
TEST(ExactOverlap, AgreesWithProduction_RandomPairsOfBuiltins) {
  const std::vector<std::string> specs = talus::testing::builtin_specs();
  std::vector<talus::testing::TestShape> shapes;
  for (const auto& spec : specs) shapes.emplace_back(spec);
  std::mt19937_64 rng(20240611);
  // 9 x 9 ordered pairs x 16 draws = 1296, of which about half overlap (bounding spheres overlap,
  // the polyhedra often do not). The reference is slow per pair with the exact kernel (its time
  // in Release: benchmarks/history/README.md): sized for well under 60 s on 2 cores.
  const int draws_per_pair = 16;
  int compared = 0, separate_both = 0;
  double worst_volume = 0, worst_vector_area = 0, worst_centroid = 0;
  for (size_t i = 0; i < shapes.size(); ++i) {
    for (size_t j = 0; j < shapes.size(); ++j) {
      const auto& sa = shapes[i];
      const auto& sb = shapes[j];
      for (int draw = 0; draw < draws_per_pair; ++draw) {
        const PosePair poses = random_overlapping_pair(rng, sa.shape.bounding_radius,
                                                       sb.shape.bounding_radius, 0.0, 0.6);
        const OverlapResult<double> prod = talus::testing::overlap(sa, poses.a, sb, poses.b);
        const RefOverlap ref =
            exact_overlap(sa.shape, to_ref_pose(poses.a), sb.shape, to_ref_pose(poses.b));
        ASSERT_FALSE(prod.workspace_overrun);
        const double radius = std::max(sa.shape.bounding_radius, sb.shape.bounding_radius);
        const double volume_scale = ref.boundary_area * radius;
        const bool prod_overlapping = prod.status == OverlapStatus::overlapping;
        if (!ref.overlapping && !prod_overlapping) {
          ++separate_both;
          continue;
        }
        // A sliver below the tolerance may be classified either way by round-off.
        if (ref.overlapping != prod_overlapping) {
          EXPECT_LT(std::max(ref.volume, prod.volume), 1e-9 * volume_scale)
              << specs[i] << " vs " << specs[j] << " draw " << draw;
          continue;
        }
        ++compared;
        const double dv = std::abs(prod.volume - ref.volume) / volume_scale;
        const double ds =
            (to_eigen(prod.vector_area) - ref.vector_area_a).norm() / ref.boundary_area;
        const double dc = (to_eigen(prod.centroid) - ref.centroid).norm() / radius;
        worst_volume = std::max(worst_volume, dv);
        worst_vector_area = std::max(worst_vector_area, ds);
        worst_centroid = std::max(worst_centroid, dc);
        EXPECT_LT(dv, 1e-9) << specs[i] << " vs " << specs[j] << " draw " << draw;
        EXPECT_LT(ds, 1e-9) << specs[i] << " vs " << specs[j] << " draw " << draw;
        // The centroid is V-weighted: a sliver's centroid moves by (displacement x A_P / V), so
        // it is compared only where V is not a sliver (V > 1e-3 A_P R).
        if (ref.volume > 1e-3 * volume_scale) {
          EXPECT_LT(dc, 1e-9) << specs[i] << " vs " << specs[j] << " draw " << draw;
        }
      }
    }
  }
  std::printf(
      "compared %d overlapping pairs (%d separate in both); worst relative errors: "
      "volume %.2e, vector area %.2e, centroid %.2e\n",
      compared, separate_both, worst_volume, worst_vector_area, worst_centroid);
  EXPECT_GE(compared, 500);
}

// The surface moment M of A's part of the boundary (RefOverlap::surface_moment_a) is what makes
// the default law's couple exact: turning a body by theta about a unit axis e through its
// centroid moves its surface at e x (r - x), so dV/dtheta_A = e . ((c - x_A) x S + M) and, B's
// part being the rest of the closed surface (S_B = -S, M_B = -M), dV/dtheta_B = -e . ((c - x_B)
// x S + M). Checked against a central difference of the exact volume, the body's orientation
// turned by +-h about e. Error budget, relative to A_P R (A_P the overlap's boundary area, R the
// larger bounding radius; |dV/dtheta| <= A_P R): truncation h^2 |d3V/dtheta3| / 6 with
// |d3V/dtheta3| ~ A_P R (a boundary of size R swept at lever R): ~1e-13 for h = 1e-6; round-off
// of the volume (a sum of double products, ~1e-15 A_P R about a vertex) and of the turned
// vertices (rounded once, 1e-18 m times A_P) over 2h: ~1e-9. A kink of V (a vertex crossing a
// face within +-h) would add O(h) only at the rare poses where one falls inside the interval.
// 1e-7 is above both and far below a missed facet or weight (an O(1) relative error in M).
TEST(ExactOverlap, SurfaceMomentIsTheVolumeRateUnderATurn) {
  const std::vector<std::string> specs = {"cube:0.01", "tetrahedron:0.012", "dodecahedron:0.01",
                                          "mineral:0.01"};
  std::mt19937_64 rng(7350012);
  const double h = 1e-6;
  int checked = 0;
  double worst = 0;
  for (size_t i = 0; i < specs.size(); ++i) {
    for (size_t j = i; j < specs.size(); ++j) {
      const ShapeTemplate a = make_builtin(specs[i]), b = make_builtin(specs[j]);
      const double radius = std::max(a.bounding_radius, b.bounding_radius);
      for (int draw = 0, found = 0; found < 2 && draw < 50; ++draw) {
        const PosePair poses =
            random_overlapping_pair(rng, a.bounding_radius, b.bounding_radius, 0.15, 0.4);
        const RefPose pa = to_ref_pose(poses.a), pb = to_ref_pose(poses.b);
        const RefOverlap r = exact_overlap(a, pa, b, pb);
        const double scale = r.boundary_area * radius;            // A_P R
        if (!r.overlapping || r.volume < 1e-3 * scale) continue;  // no slivers
        ++found;
        const Eigen::Vector3d tilted = to_eigen(random_direction(rng));
        for (const Eigen::Vector3d& e : turn_axes(tilted)) {
          const double rate_a = (exact_overlap(a, turned(pa, e, h), b, pb).volume -
                                 exact_overlap(a, turned(pa, e, -h), b, pb).volume) /
                                (2 * h);
          const double rate_b = (exact_overlap(a, pa, b, turned(pb, e, h)).volume -
                                 exact_overlap(a, pa, b, turned(pb, e, -h)).volume) /
                                (2 * h);
          const Eigen::Vector3d& s = r.vector_area_a;
          const Eigen::Vector3d& m = r.surface_moment_a;
          const double expected_a = e.dot((r.centroid - pa.position).cross(s) + m);
          const double expected_b = -e.dot((r.centroid - pb.position).cross(s) + m);
          const double error =
              std::max(std::abs(rate_a - expected_a), std::abs(rate_b - expected_b)) / scale;
          worst = std::max(worst, error);
          EXPECT_LT(error, 1e-7) << specs[i] << " vs " << specs[j] << " draw " << draw
                                 << ": dV/dtheta_A " << rate_a << " vs " << expected_a
                                 << ", dV/dtheta_B " << rate_b << " vs " << expected_b;
          ++checked;
        }
        // M is not negligible here (else the check would test the lever term alone).
        EXPECT_GT(r.surface_moment_a.norm(), 1e-3 * scale) << specs[i] << " vs " << specs[j];
      }
    }
  }
  std::printf("surface moment vs dV/dtheta: %d turns, worst error %.2e of A_P R\n", checked, worst);
  EXPECT_EQ(checked, 10 * 2 * 4);  // 10 shape pairs, 2 poses each, 4 axes
}

// Closed forms. Two boxes (AxisAlignedBoxes): each of A's faces on the overlap has its centroid
// on the overlap's centroid moved along the face's normal, so every lever is parallel to its
// area vector and M = 0. A triangular prism B (vertical, z in [-1, 1]) poking its edge into the
// unit cube A's +x face: the overlap is the prism over the triangle (1/4, 0), (1/2, -1/16),
// (1/2, 3/16), z in [-1/2, 1/2] (A's top and bottom, on A only). A's +x face on it, y in
// [y1, y2] = [-1/16, 3/16], area (y2 - y1) along +x, has its centroid at y = (y1 + y2) / 2, the
// overlap's at (y1 + y2) / 3: lever y (y1 + y2) / 6, so M_z = -(y2^2 - y1^2) / 6 = -1/192 (the top
// and bottom triangles' levers are along z, their area vectors too). Check: turning A about z
// moves its +x face by -y dtheta, dV/dtheta = -(y2^2 - y1^2) / 2 = z . (c x S) + M_z.
TEST(ExactOverlap, SurfaceMoment_ClosedForms) {
  const ShapeTemplate boxes = box_vertices(0.010, 0.012, 0.014);
  const RefOverlap r = exact_overlap(boxes, at(0, 0, 0), boxes, at(0.008, 0.001, 0.0005));
  EXPECT_LT(r.surface_moment_a.norm(), kClosedRel * 0.01 * r.vector_area_a.norm());

  const ShapeTemplate cube = box_vertices(1, 1, 1);
  ShapeTemplate prism;
  prism.name = "prism";
  for (const double z : {-1.0, 1.0}) {
    prism.vertices.push_back({0.25, 0, z});
    prism.vertices.push_back({0.75, -0.125, z});
    prism.vertices.push_back({0.75, 0.375, z});
  }
  prism.volume = 0.5 * 0.5 * 0.5 * 2;
  const RefOverlap p = exact_overlap(cube, at(0, 0, 0), prism, at(0, 0, 0));
  ASSERT_TRUE(p.overlapping);
  const double y1 = -0.0625, y2 = 0.1875;
  EXPECT_NEAR(p.volume, 0.5 * 0.25 * (y2 - y1), kClosedRel);
  EXPECT_LT((p.vector_area_a - Eigen::Vector3d(y2 - y1, 0, 0)).norm(), kClosedRel);
  const Eigen::Vector3d moment(0, 0, -(y2 * y2 - y1 * y1) / 6);
  EXPECT_NEAR(moment.z(), -1.0 / 192, 1e-18);
  EXPECT_LT((p.surface_moment_a - moment).norm(), kClosedRel * std::abs(moment.z()));
  const double rate = Eigen::Vector3d::UnitZ().dot(p.centroid.cross(p.vector_area_a)) + moment.z();
  EXPECT_NEAR(rate, -(y2 * y2 - y1 * y1) / 2, kClosedRel);
}

}  // namespace
}  // namespace talus::reference
