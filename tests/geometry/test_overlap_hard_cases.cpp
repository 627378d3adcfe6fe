// The named hard cases of the overlap (docs/design.md, "Hard cases stay numerically stable"): each
// must give finite numbers, a sensible status and no workspace overrun, and the right volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "tests/geometry/overlap_test_util.hpp"

namespace talus::testing {
namespace {

void expect_sane(const OverlapResult<double>& r) {
  EXPECT_TRUE(std::isfinite(r.volume) && r.volume >= 0);
  EXPECT_TRUE(std::isfinite(norm(r.vector_area)));
  EXPECT_TRUE(std::isfinite(norm(r.centroid)));
  EXPECT_FALSE(r.workspace_overrun);
  EXPECT_NE(r.status, OverlapStatus::degenerate);
}

// The oracle's answer for the same double inputs; `rel` is the relative tolerance of the case.
void expect_matches_oracle(const TestShape& a, const Posed& pa, const TestShape& b, const Posed& pb,
                           double rel) {
  const auto got = overlap(a, pa, b, pb);
  const auto ref = oracle(a, pa, b, pb);
  expect_sane(got);
  EXPECT_NEAR(got.volume, double(ref.volume), rel * double(ref.volume));
  EXPECT_LE(norm(got.vector_area - to_d(ref.vector_area_a)), rel * double(ref.boundary_area));
}

constexpr double kSide = 0.01;  // cube side, m

// A spec with every digit of a size (std::to_string keeps only six decimals).
std::string spec(const std::string& name, double size) {
  char text[64];
  std::snprintf(text, sizeof text, "%s:%.17g", name.c_str(), size);
  return text;
}

TestShape cube() {
  return TestShape(spec("cube", kSide * std::sqrt(3.0)));
}

// A cube sliding on a cube, faces parallel, side faces coplanar (twins): the overlap is a box and
// the normal is the face normal up to the +x side face the slide exposes.
TEST(OverlapHardCases, FaceOnFaceCubeSlidingOnCube) {
  const TestShape c = cube();
  const double h = 1e-5, s = 0.003;  // overlap depth and slide, m
  const auto r =
      overlap(c, input_frame_pose(c.shape, {}), c, input_frame_pose(c.shape, {s, 0, kSide - h}));
  expect_sane(r);
  ASSERT_EQ(r.status, OverlapStatus::overlapping);
  // Round-off of kSide - h against h: 1e-16 * 0.01 / 1e-5 = 1e-13 relative; 1e-10 is safe.
  EXPECT_NEAR(r.volume, (kSide - s) * kSide * h, 1e-10 * r.volume);
  EXPECT_NEAR(r.vector_area.x, kSide * h, 1e-10 * kSide * kSide);
  EXPECT_NEAR(r.vector_area.y, 0.0, 1e-10 * kSide * kSide);  // the y twins cancel
  EXPECT_NEAR(r.vector_area.z, (kSide - s) * kSide, 1e-10 * kSide * kSide);
}

// Two 10 mm cubes (circumscribed) resting face on face, a little misaligned, 3e-8 m deep: the
// state of a settled stack (tests/step/test_hard_cases.cpp) where the LP's Chebyshev centre sits
// at the thin slab's rim and the dual hull left the origin outside (the overlap was reported
// degenerate and stopped the run). The analytic-centre retry gives the oracle's overlap. The
// slab's depth is 3e-6 of the size, so the round-off of the planes' offsets (1e-16 of the size)
// is ~3e-11 of the depth: 1e-8 relative leaves room for the cancellation in the cones.
TEST(OverlapHardCases, ThinSlabOfStackedCubesWithTheCentreAtTheRim) {
  const TestShape c(spec("cube", 0.01));
  const Posed a{Vec3d(-5.9127484898533271e-08, -6.242773007091092e-08, 0.0028866335662466672),
                Quatd(0.7071144223874849, -0.70709913982896611, -7.2321982100207524e-06,
                      -7.2419111540230652e-06)};
  const Posed b{Vec3d(-1.7732197103352409e-07, -1.869643892676637e-07, 0.0086601068265122396),
                Quatd(0.70711442553614767, -0.70709913668017088, -7.2394950741648449e-06,
                      -7.2409122637539861e-06)};
  expect_matches_oracle(c, a, c, b, 1e-8);
  EXPECT_EQ(overlap(c, a, c, b).status, OverlapStatus::overlapping);
}

// Two of the poured bed's cylinders (experiments/beds: the paper's 20-sided prism at 10 mm) as
// the GPU step met them at t = 0.16 s, where the overlap was reported degenerate, and the same
// pair moved by a few ulps (the GPU's fused multiply-adds round differently from the host's):
// end face on end face, a wedge 2.7e-9 m deep under faces 7 mm wide whose planes are 8e-7 rad
// apart, with the Chebyshev centre at the rim. Before the rounded retry 17 % of such poses failed
// (3,333 of 20,000). The oracle's volume within 1e-7: the planes' offsets carry round-off of
// ~1e-18 m, 4e-10 of the depth, and the cones from the centre cancel by another factor ~10
// (2.6e-9 measured).
TEST(OverlapHardCases, PouredCylindersWedgeAtTheGpuFailure) {
  const TestShape c(wedge_cylinder_spec());
  const Posed a = wedge_cylinder_a();
  const Posed b = wedge_cylinder_b_gpu();
  expect_matches_oracle(c, a, c, b, 1e-7);
  std::mt19937_64 random(15);
  std::uniform_real_distribution<double> unit(-0.5, 0.5);
  double worst = 0;
  for (int t = 0; t < 64; ++t) {
    Posed moved = b;
    const double eps = 1e-15 * (1 << (t % 8));  // relative: a few ulps to ~500
    moved.position += Vec3d(unit(random), unit(random), unit(random)) * (eps * 0.01);
    moved.orientation =
        Quatd(b.orientation.w + eps * unit(random), b.orientation.x + eps * unit(random),
              b.orientation.y + eps * unit(random), b.orientation.z + eps * unit(random));
    const auto got = overlap(c, a, c, moved);
    const auto ref = oracle(c, a, c, moved);
    ASSERT_EQ(got.status, OverlapStatus::overlapping) << "pose " << t;
    worst = std::max(worst, std::abs(got.volume / double(ref.volume) - 1));
  }
  EXPECT_LT(worst, 1e-7);
}

// Two cubes turned 45 degrees about crossing axes so that an edge of each crosses an edge of the
// other: the overlap is a thin tetrahedron-like wedge.
TEST(OverlapHardCases, EdgeEdgeCrossing) {
  const TestShape c = cube();
  const double pi = std::acos(-1.0);
  const Quatd qa = Quatd::from_axis_angle({1, 0, 0}, pi / 4);
  const Quatd qb = Quatd::from_axis_angle({0, 1, 0}, pi / 4);
  const double reach = kSide / std::sqrt(2.0);  // centre to the turned edge
  const Posed pa = input_frame_pose(c.shape, {}, qa);
  const Posed pb = input_frame_pose(c.shape, {0, 0, 2 * reach - 1e-4}, qb);
  // Double inputs carry 1e-16 * 0.01 m against a 1e-4 m crossing: 1e-9 relative holds.
  expect_matches_oracle(c, pa, c, pb, 1e-9);
  EXPECT_EQ(overlap(c, pa, c, pb).status, OverlapStatus::overlapping);
}

// A cube corner pushed into a large cube's face along the corner's diagonal: the cut-off corner
// is a tetrahedron of volume (sqrt(3)/2) d^3 whose base, an equilateral triangle of area
// (3 sqrt(3)/2) d^2, lies on the big cube's face.
TEST(OverlapHardCases, VertexIntoFace) {
  const TestShape big(spec("cube", 0.05 * std::sqrt(3.0)));
  const TestShape c = cube();
  // Turn the diagonal (1,1,1)/sqrt(3) onto -z.
  const Vec3d from = Vec3d(1, 1, 1) / std::sqrt(3.0), to(0, 0, -1);
  const Vec3d axis = cross(from, to) / norm(cross(from, to));
  const Quatd q = Quatd::from_axis_angle(axis, std::acos(dot(from, to)));
  const double d = 2e-4;
  const double corner = kSide * std::sqrt(3.0) / 2;  // centre to corner
  const auto r = overlap(big, input_frame_pose(big.shape, {}), c,
                         input_frame_pose(c.shape, {0, 0, 0.025 + corner - d}, q));
  expect_sane(r);
  ASSERT_EQ(r.status, OverlapStatus::overlapping);
  // The corner depth d = 2e-4 m is set against 0.025 m positions: 1e-16 * 0.025 / 2e-4 ~ 1e-14
  // relative per length, cubed: 1e-10 leaves room.
  EXPECT_NEAR(r.volume, std::sqrt(3.0) / 2 * d * d * d, 1e-10 * r.volume);
  EXPECT_NEAR(r.vector_area.z, 1.5 * std::sqrt(3.0) * d * d, 1e-10 * d * d);
  EXPECT_LT(std::hypot(r.vector_area.x, r.vector_area.y), 1e-10 * d * d);
}

TEST(OverlapHardCases, CoincidentCopies) {
  for (const char* spec : {"cylinder:0.008,0.0053", "mineral:0.01", "corn:0.01"}) {
    SCOPED_TRACE(spec);
    const TestShape s(spec);
    const Posed p{{1.0, 2.0, -0.5}, Quatd(0.9, 0.1, -0.3, 0.2).normalized()};
    const auto r = overlap(s, p, s, p);
    expect_sane(r);
    EXPECT_NEAR(r.volume, s.shape.volume, 1e-12 * s.shape.volume);
    EXPECT_LT(norm(r.vector_area), 1e-12 * std::pow(s.shape.volume, 2.0 / 3.0));
  }
}

TEST(OverlapHardCases, OneInsideTheOther) {
  const TestShape big("cylinder:0.008,0.0053"), small("tetrahedron:0.002");
  const Posed pa{{0, 0, 0}, Quatd()};
  const Posed pb{{0.001, 0.0005, -0.0003}, Quatd(0.7, 0.2, 0.1, -0.4).normalized()};
  const auto r = overlap(big, pa, small, pb);
  expect_sane(r);
  EXPECT_NEAR(r.volume, small.shape.volume, 1e-12 * small.shape.volume);
  EXPECT_LT(norm(r.centroid - pb.position), 1e-15);
}

// An overlap of 1e-12 of the volume: the depth 1e-12 * side is set by subtracting positions of
// size 0.01 m, which carries 1e-16 * 0.01 m, i.e. 1e-4 of the depth. The oracle sees the same
// doubles, so we agree with it to that input round-off, 1e-3.
TEST(OverlapHardCases, OverlapOfOneTrillionthOfTheVolume) {
  const TestShape c = cube();
  const Posed pa = input_frame_pose(c.shape, {});
  const Posed pb = input_frame_pose(c.shape, {0.002, -0.001, kSide * (1 - 1e-12)});
  const auto r = overlap(c, pa, c, pb);
  expect_sane(r);
  ASSERT_EQ(r.status, OverlapStatus::overlapping);
  const double ref = double(oracle(c, pa, c, pb).volume);
  EXPECT_NEAR(r.volume, ref, 1e-3 * ref);
  EXPECT_NEAR(r.volume / c.shape.volume, 0.8 * 0.9 * 1e-12, 1e-3 * 1e-12);
  EXPECT_NEAR(r.vector_area.z / norm(r.vector_area), 1.0, 1e-6);
}

TEST(OverlapHardCases, EightyFacetCylinderAgainstItselfRotatedByANanoradian) {
  const TestShape cyl("cylinder:0.008,0.0053");
  ASSERT_EQ(cylinder_mesh(0.008, 0.0053).triangles.size(), 80u);  // the paper's mesh (§3.1)
  ASSERT_EQ(cyl.shape.faces.size(), 22u);                         // 20 sides and 2 caps
  for (const Vec3d axis : {Vec3d(0, 0, 1), Vec3d(1, 0, 0), Vec3d(0.6, 0.8, 0)}) {
    const Posed pa{{0.01, 0.02, 0.03}, Quatd()};
    const Posed pb{pa.position, Quatd::from_axis_angle(axis, 1e-9)};
    const auto r = overlap(cyl, pa, cyl, pb);
    expect_sane(r);
    ASSERT_EQ(r.status, OverlapStatus::overlapping);
    // Nearly every face plane has a near-twin 1e-9 rad away; the slivers between them are
    // O(1e-9) of the volume, so the volume is the cylinder's to 1e-8.
    EXPECT_NEAR(r.volume, cyl.shape.volume, 1e-8 * cyl.shape.volume);
    const auto ref = oracle(cyl, pa, cyl, pb);
    EXPECT_NEAR(r.volume, double(ref.volume), 1e-9 * double(ref.volume));
    // The near-twin planes are merged and their face split half and half between A and B; the
    // oracle splits each face where the two planes cross, which for these rotations is the
    // face's middle up to the crossing line's conditioning, eps / 1e-9 ~ 2e-7 of the face: S
    // agrees to that, not to 1e-9.
    EXPECT_LE(norm(r.vector_area - to_d(ref.vector_area_a)), 1e-6 * double(ref.boundary_area));
  }
}

TEST(OverlapHardCases, SizeRatioOneToOneHundred) {
  const TestShape big("cube:0.01"), tiny("dodecahedron:0.0001");
  const double half = 0.01 / std::sqrt(3.0) / 2;
  const Posed pa = input_frame_pose(big.shape, {});
  for (const double depth_fraction : {0.1, 0.5, 0.9}) {
    const Posed pb{{0.001, -0.002, half + 0.00005 * (1 - 2 * depth_fraction)},
                   Quatd(0.3, 0.4, 0.5, 0.6).normalized()};
    // The small body's surfaces are placed with 1e-16 * 0.005 m error against a 1e-4 m body:
    // 1e-11 relative per length, 1e-9 is safe.
    expect_matches_oracle(big, pa, tiny, pb, 1e-9);
    expect_matches_oracle(tiny, pb, big, pa, 1e-9);
  }
}

TEST(OverlapHardCases, ExactTouchingFaceToFace) {
  const TestShape d("dodecahedron:0.01");
  const Vec3d n = d.shape.faces[0].normal;
  const double inradius = d.shape.faces[0].offset;
  const Posed pa{{0, 0, 0}, Quatd()};
  const Posed pb{n * (2 * inradius), Quatd()};  // the opposite face lands on face 0
  const auto r = overlap(d, pa, d, pb);
  expect_sane(r);
  EXPECT_EQ(r.status, OverlapStatus::touching);
  EXPECT_EQ(r.volume, 0.0);
}

// A workspace too small for the pair reports the overrun instead of writing past its arrays.
TEST(OverlapHardCases, TooSmallWorkspaceReportsOverrun) {
  const TestShape cyl("cylinder:0.008,0.0053");
  OverlapWorkspace<double, 8> small;
  const auto r = overlap_polyhedra(cyl.view(), Posed{{0, 0, 0}, Quatd()}, cyl.view(),
                                   Posed{{0.001, 0, 0}, Quatd()}, small);
  EXPECT_TRUE(r.workspace_overrun);
  EXPECT_EQ(r.status, OverlapStatus::degenerate);
  EXPECT_EQ(r.volume, 0.0);
}

TEST(OverlapHardCases, NonFiniteInputIsDegenerate) {
  const TestShape c = cube();
  const double nan = std::nan("");
  const auto r = overlap(c, Posed{{0, 0, 0}, Quatd()}, c, Posed{{nan, 0, 0}, Quatd()});
  EXPECT_EQ(r.status, OverlapStatus::degenerate);
  EXPECT_EQ(r.volume, 0.0);
}

}  // namespace
}  // namespace talus::testing
