// Particle–triangle clipping (solver/geometry/wall_clip.hpp, paper §2.4, Algorithm VII) against
// closed forms, the long-double oracle, float/double agreement and degenerate inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "solver/geometry/wall_clip.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "tests/geometry/test_shapes_local.hpp"
#include "tests/support/oracle.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using test_local::make_box;
using test_local::make_cube;

const double kPi = 3.14159265358979323846;

template <class Real>
Pose<Real> pose_of(const Vec3d& position, const Quatd& orientation = Quatd()) {
  return {Vec3<Real>(position), Quat<Real>(orientation)};
}

// Rotation taking unit vector `from` onto unit vector `to` (not antiparallel).
Quatd rotation_between(const Vec3d& from, const Vec3d& to) {
  const Vec3d axis = cross(from, to);
  if (norm(axis) < 1e-12) {
    return dot(from, to) > 0 ? Quatd()
                             : Quatd::from_axis_angle(
                                   std::abs(from.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0}, kPi);
  }
  return Quatd::from_axis_angle(axis / norm(axis), std::acos(dot(from, to)));
}

bool all_finite(const WallContact<double>& w) {
  return std::isfinite(w.overlap_area) && std::isfinite(w.section_area) && std::isfinite(w.depth) &&
         std::isfinite(w.volume_below) && std::isfinite(w.overlap_centroid.x) &&
         std::isfinite(w.overlap_centroid.y) && std::isfinite(w.overlap_centroid.z) &&
         std::isfinite(w.normal.x) && std::isfinite(w.normal.y) && std::isfinite(w.normal.z);
}

// A triangle far larger than the particles, normal +z, containing the square |x|, |y| < 9.
const Vec3d kBigA{-10, -10, 0}, kBigB{20, -10, 0}, kBigC{-10, 20, 0};

WallContact<double> clip_big(const test_local::LocalShape<double>& shape, const Posed& pose) {
  return clip_against_triangle(shape.view(), pose, kBigA, kBigB, kBigC);
}

// Relative tolerance of the flat and tilted closed forms in double. Every number is a short
// chain of products of particle-size coordinates (no accumulation over many terms), so the error is
// a few tens of eps times the particle size; relative to a quantity of size (s/h)^k smaller it
// grows by that factor (s/h <= 10 here): 20 * 2.2e-16 * 10^2 = 4.4e-13 < 1e-12.
const double kClosedFormRel = 1e-12;

TEST(WallClip, CubeResting_FlatAreaDepthVolume) {
  const double side = 0.02, h = 0.003;
  const auto cube = make_cube<double>(side);
  // Yawed about the wall normal: still flat, so the closed forms hold whatever the yaw.
  for (double yaw : {0.0, 0.3, 1.1}) {
    const Posed pose{{0.3, -0.2, side / 2 - h}, Quatd::from_axis_angle({0, 0, 1}, yaw)};
    const WallContact<double> w = clip_big(cube, pose);
    EXPECT_EQ(w.status, WallContactStatus::overlapping);
    EXPECT_NEAR(w.overlap_area, side * side, kClosedFormRel * side * side);
    EXPECT_NEAR(w.section_area, side * side, kClosedFormRel * side * side);
    EXPECT_NEAR(w.depth, h, kClosedFormRel * h);
    EXPECT_NEAR(w.volume_below, side * side * h, kClosedFormRel * side * side * h);
    EXPECT_NEAR(w.overlap_centroid.x, 0.3, kClosedFormRel * side);
    EXPECT_NEAR(w.overlap_centroid.y, -0.2, kClosedFormRel * side);
    EXPECT_NEAR(w.overlap_centroid.z, 0.0, kClosedFormRel * side);
    EXPECT_NEAR(w.area_fraction(), 1.0, kClosedFormRel);
    EXPECT_EQ(w.section_points, 4);
    EXPECT_DOUBLE_EQ(w.normal.z, 1.0);
    EXPECT_FALSE(w.overrun);
  }
}

// Triangle with its edge a-b on the line x = 0, interior at x > 0; normal +z.
const Vec3d kEdgeA{0, 1, 0}, kEdgeB{0, -1, 0}, kEdgeC{2, 0, 0};

TEST(WallClip, CubeStraddlingAnEdge_AnalyticClippedArea) {
  const double side = 0.1, h = 0.01, x0 = 0.02;
  const auto cube = make_cube<double>(side);
  const Posed pose{{x0, 0, side / 2 - h}, Quatd()};
  const WallContact<double> w = clip_against_triangle(cube.view(), pose, kEdgeA, kEdgeB, kEdgeC);
  EXPECT_EQ(w.status, WallContactStatus::overlapping);
  const double width = x0 + side / 2;  // part of the square with x >= 0
  EXPECT_NEAR(w.overlap_area, side * width, kClosedFormRel * side * side);
  EXPECT_NEAR(w.section_area, side * side, kClosedFormRel * side * side);
  EXPECT_NEAR(w.overlap_centroid.x, width / 2, kClosedFormRel * side);
  EXPECT_NEAR(w.overlap_centroid.y, 0.0, kClosedFormRel * side);
  // The plane quantities do not depend on the triangle's extent.
  EXPECT_NEAR(w.volume_below, side * side * h, kClosedFormRel * side * side * h);

  // Yawed 45 degrees and centred on the edge: the diamond is cut in half, leaving the right
  // triangle (0, +-s/sqrt2), (s/sqrt2, 0), whose centroid is at x = s / (3 sqrt 2).
  const Posed diamond{{0, 0, side / 2 - h}, Quatd::from_axis_angle({0, 0, 1}, kPi / 4)};
  const WallContact<double> d = clip_against_triangle(cube.view(), diamond, kEdgeA, kEdgeB, kEdgeC);
  EXPECT_NEAR(d.overlap_area, side * side / 2, kClosedFormRel * side * side);
  EXPECT_NEAR(d.overlap_centroid.x, side / (3 * std::sqrt(2.0)), kClosedFormRel * side);
  EXPECT_NEAR(d.area_fraction(), 0.5, kClosedFormRel);
}

TEST(WallClip, CubeOverATriangleCorner_AnalyticClippedArea) {
  const double side = 0.1, h = 0.01, x0 = 0.01, y0 = -0.03;
  const auto cube = make_cube<double>(side);
  // Right angle at the origin, legs along +x and +y.
  const WallContact<double> w = clip_against_triangle(
      cube.view(), Posed{{x0, y0, side / 2 - h}, Quatd()}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const double wx = x0 + side / 2, wy = y0 + side / 2;
  EXPECT_NEAR(w.overlap_area, wx * wy, kClosedFormRel * side * side);
  EXPECT_NEAR(w.overlap_centroid.x, wx / 2, kClosedFormRel * side);
  EXPECT_NEAR(w.overlap_centroid.y, wy / 2, kClosedFormRel * side);
}

// §2.4: a particle over the shared edge of two coplanar facets is counted once: the two
// overlap areas add up to the section, so the area fractions add up to one.
TEST(WallClip, TwoFacetsSharingAnEdge_AreaFractionsSumToOne) {
  const double side = 0.1;
  const auto cube = make_cube<double>(side);
  const Vec3d axis{0.2, -0.3, 0.93};
  const Posed pose{{0.013, -0.021, side / 2 - 0.02},
                   Quatd::from_axis_angle(axis / norm(axis), 0.4)};
  // The square [-1, 1]^2 split along its diagonal.
  const Vec3d p00{-1, -1, 0}, p10{1, -1, 0}, p11{1, 1, 0}, p01{-1, 1, 0};
  const WallContact<double> first = clip_against_triangle(cube.view(), pose, p00, p10, p11);
  const WallContact<double> second = clip_against_triangle(cube.view(), pose, p00, p11, p01);
  EXPECT_GT(first.overlap_area, 0.1 * first.section_area);  // the particle is over the diagonal
  EXPECT_GT(second.overlap_area, 0.1 * first.section_area);
  EXPECT_NEAR(first.section_area, second.section_area, 1e-15);
  EXPECT_NEAR(first.area_fraction() + second.area_fraction(), 1.0, kClosedFormRel);
}

TEST(WallClip, TiltedCube_ClosedFormVolumesBelow) {
  const double side = 0.1, theta = 0.3;  // tilted about x; theta < 45 degrees
  const auto cube = make_cube<double>(side);
  const double sn = std::sin(theta), cs = std::cos(theta);
  const Quatd tilt = Quatd::from_axis_angle({1, 0, 0}, theta);
  // The lowest edge (along x) is at depth h below the plane.
  auto pose_at = [&](double h) { return Posed{{0, 0, side / 2 * (sn + cs) - h}, tilt}; };

  // h <= s sin(theta): the cross-section below is a triangle of area h^2 / sin(2 theta).
  const double h1 = 0.01;
  const WallContact<double> w1 = clip_big(cube, pose_at(h1));
  EXPECT_NEAR(w1.depth, h1, kClosedFormRel * side);
  const double v1 = side * h1 * h1 / std::sin(2 * theta);
  EXPECT_NEAR(w1.volume_below, v1, kClosedFormRel * v1);
  EXPECT_NEAR(w1.section_area, side * 2 * h1 / std::sin(2 * theta), kClosedFormRel * side * side);

  // s sin(theta) <= h <= s cos(theta): the triangle of area s^2 tan(theta) / 2, then a band of
  // constant horizontal width s / cos(theta).
  const double h2 = 0.05;
  const WallContact<double> w2 = clip_big(cube, pose_at(h2));
  const double v2 = side * (side * side * std::tan(theta) / 2 + (h2 - side * sn) * side / cs);
  EXPECT_NEAR(w2.volume_below, v2, kClosedFormRel * v2);
  EXPECT_NEAR(w2.section_area, side * side / cs, kClosedFormRel * side * side);

  // Corner down (body diagonal vertical), then yawed: below h <= s / sqrt(3) the part below is
  // the corner tetrahedron with three orthogonal edges of length sqrt(3) h: volume sqrt(3) h^3 / 2,
  // section an equilateral triangle of side sqrt(6) h: area 3 sqrt(3) h^2 / 2.
  const Quatd corner_down = Quatd::from_axis_angle({0, 0, 1}, 0.7) *
                            rotation_between(Vec3d{-1, -1, -1} / std::sqrt(3.0), {0, 0, -1});
  const double h3 = 0.02;
  const WallContact<double> w3 =
      clip_big(cube, Posed{{0.05, 0.02, side * std::sqrt(3.0) / 2 - h3}, corner_down});
  const double v3 = std::sqrt(3.0) * h3 * h3 * h3 / 2;
  EXPECT_NEAR(w3.depth, h3, kClosedFormRel * side);
  EXPECT_NEAR(w3.volume_below, v3, kClosedFormRel * v3);
  EXPECT_NEAR(w3.section_area, 3 * std::sqrt(3.0) * h3 * h3 / 2, kClosedFormRel * side * side);
  EXPECT_EQ(w3.section_points, 3);
  EXPECT_NEAR(w3.overlap_centroid.x, 0.05, kClosedFormRel * side);  // below the corner
  EXPECT_NEAR(w3.overlap_centroid.y, 0.02, kClosedFormRel * side);
}

TEST(WallClip, TriangleInsideTheSection_AreaIsTheTriangle) {
  const double side = 1.0;
  const auto cube = make_cube<double>(side);
  const Vec3d a{0.1, 0.1, 0}, b{0.3, 0.1, 0}, c{0.1, 0.25, 0};
  const WallContact<double> w =
      clip_against_triangle(cube.view(), Posed{{0, 0, side / 2 - 0.1}, Quatd()}, a, b, c);
  EXPECT_EQ(w.status, WallContactStatus::overlapping);
  EXPECT_NEAR(w.overlap_area, 0.5 * 0.2 * 0.15, kClosedFormRel * side * side);
  const Vec3d centroid = (a + b + c) / 3.0;
  EXPECT_NEAR(w.overlap_centroid.x, centroid.x, kClosedFormRel * side);
  EXPECT_NEAR(w.overlap_centroid.y, centroid.y, kClosedFormRel * side);
  EXPECT_NEAR(w.section_area, side * side, kClosedFormRel * side * side);
}

// Random poses of a box and a tetrahedron against a tilted large triangle, compared with the
// long-double half-space oracle (independent code): volume below and section area.
TEST(WallClip, RandomPoses_MatchTheOracle) {
  std::mt19937_64 rng(20240611);
  const auto box = make_box<double>(0.03, 0.02, 0.012);
  const auto tetra = test_local::make_tetrahedron<double>(0.05);
  const Vec3d a{-1, -1, 0.1}, b{2, -1, -0.2}, c{-1, 2, 0.3};
  const Vec3d n = cross(b - a, c - a) / norm(cross(b - a, c - a));
  std::uniform_real_distribution<double> offset(-0.9, 0.9);
  int overlapping = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const auto& shape = (trial % 2) ? box : tetra;
    const double r = shape.bounding_radius;
    // Centre on the plane's normal line through (0.1, 0.1, .), at signed distance in (-0.9, 0.9) r.
    const Vec3d foot = a + Vec3d{1.1, 1.1, 0} - n * dot(n, Vec3d{1.1, 1.1, 0});
    const Posed pose{foot + n * (offset(rng) * r), random_rotation(rng)};
    const WallContact<double> w = clip_against_triangle(shape.view(), pose, a, b, c);
    const ShapeTemplate tpl = shape.to_template();
    const Vec3l nl(n);
    const long double plane_offset = dot(nl, Vec3l(a));
    const long double volume = oracle_volume_below_plane(tpl, pose, nl, plane_offset);
    const auto section = oracle_section_polygon(tpl, pose, nl, plane_offset);
    Vec3l twice_area_vector;
    for (size_t k = 0; k < section.size(); ++k) {
      twice_area_vector += cross(section[k], section[(k + 1) % section.size()]);
    }
    const double section_area = double(dot(twice_area_vector, nl) / 2);
    // Oracle in long double; ours in double with particle-size coordinates: a few hundred eps of
    // r^3 and r^2 covers the round-off of ~20 terms.
    EXPECT_NEAR(w.volume_below, double(volume), 1e-13 * r * r * r) << "trial " << trial;
    EXPECT_NEAR(w.section_area, section_area, 1e-13 * r * r) << "trial " << trial;
    EXPECT_NEAR(w.overlap_area, w.section_area, 1e-13 * r * r);  // the triangle covers it
    overlapping += w.status == WallContactStatus::overlapping;
  }
  EXPECT_GT(overlapping, 150);  // the test exercises real sections, not misses
}

// Built-in shapes (through the production template pipeline) against the same oracle, including
// the 80-facet-sided cylinder whose axial section has 80 points.
TEST(WallClip, BuiltinShapes_MatchTheOracle) {
  std::mt19937_64 rng(99);
  const Vec3d a{-1, -1, 0.02}, b{2, -1, -0.01}, c{-1, 2, 0.01};
  const Vec3d n = cross(b - a, c - a) / norm(cross(b - a, c - a));
  std::uniform_real_distribution<double> offset(-0.9, 0.9);
  for (const char* spec : {"dodecahedron:0.01", "icosahedron:0.01", "mineral:0.01", "corn:0.01",
                           "cylinder:0.008,0.0053,80"}) {
    const ShapeTemplate shape = make_builtin(spec);
    const ShapeArrays<double> arrays(shape);
    const double r = shape.bounding_radius;
    for (int trial = 0; trial < 40; ++trial) {
      const Vec3d foot = a + Vec3d{1.1, 1.1, 0} - n * dot(n, Vec3d{1.1, 1.1, 0});
      const Posed pose{foot + n * (offset(rng) * r), random_rotation(rng)};
      const WallContact<double> w = clip_against_triangle(arrays.view(), pose, a, b, c);
      const Vec3l nl(n);
      const long double plane_offset = dot(nl, Vec3l(a));
      const auto section = oracle_section_polygon(shape, pose, nl, plane_offset);
      Vec3l twice_area_vector;
      for (size_t k = 0; k < section.size(); ++k) {
        twice_area_vector += cross(section[k], section[(k + 1) % section.size()]);
      }
      ASSERT_FALSE(w.overrun) << spec;
      // As in RandomPoses_MatchTheOracle, with up to 160 triangles: 1e-12 of r^k.
      EXPECT_NEAR(w.volume_below, double(oracle_volume_below_plane(shape, pose, nl, plane_offset)),
                  1e-12 * r * r * r)
          << spec << " trial " << trial;
      EXPECT_NEAR(w.section_area, double(dot(twice_area_vector, nl) / 2), 1e-12 * r * r)
          << spec << " trial " << trial;
    }
  }
  // An 80-sided cylinder cut across its axis: an 80-point section, the regular 80-gon of
  // circumradius D / 2. The body frame is the principal frame, so find the axis from a cap.
  const ShapeTemplate cylinder = make_builtin("cylinder:0.008,0.0053,80");
  const ShapeArrays<double> arrays(cylinder);
  Vec3d cap_normal;
  for (const Face& face : cylinder.faces) {
    if (face.loop.size() == 80) cap_normal = face.normal;
  }
  const Posed across{{0, 0, 0.001}, rotation_between(cap_normal, {0, 0, 1})};
  const WallContact<double> w = clip_against_triangle(arrays.view(), across, kBigA, kBigB, kBigC);
  EXPECT_EQ(w.section_points, 80);
  EXPECT_FALSE(w.overrun);
  const double radius = 0.004, ngon = 40 * radius * radius * std::sin(2 * kPi / 80);
  // The rim vertices pass through the template pipeline (hull, principal frame): 1e-12 relative.
  EXPECT_NEAR(w.section_area, ngon, 1e-12 * ngon);
  EXPECT_EQ(w.status, WallContactStatus::overlapping);
  // A capacity below 80 overruns and says so.
  EXPECT_TRUE(
      (clip_against_triangle<double, 64>(arrays.view(), across, kBigA, kBigB, kBigC).overrun));
}

// The same random poses in float and in double.
TEST(WallClip, FloatAgreesWithDouble) {
  std::mt19937_64 rng(7);
  const auto box_d = make_box<double>(0.03, 0.02, 0.012);
  const auto box_f = make_box<float>(0.03, 0.02, 0.012);
  const double r = box_d.bounding_radius;
  const Vec3d a{-0.2, -0.2, 0}, b{0.25, -0.2, 0.01}, c{-0.2, 0.25, -0.01};
  std::uniform_real_distribution<double> unit(-1, 1);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Posed pose{{0.3 * r * unit(rng), 0.3 * r * unit(rng), 0.7 * r * unit(rng)},
                     random_rotation(rng)};
    const WallContact<double> wd = clip_against_triangle(box_d.view(), pose, a, b, c);
    const WallContact<float> wf =
        clip_against_triangle(box_f.view(), pose_of<float>(pose.position, pose.orientation),
                              Vec3f(a), Vec3f(b), Vec3f(c));
    // Statuses may differ only within float round-off of the plane; skip those rare poses.
    if (wd.depth < 1e-4 * r) continue;
    ++compared;
    EXPECT_EQ(wd.status, wf.status);
    // Float round-off: the unit roundoff 6e-8 times a few tens of operations on particle-size
    // numbers, ~1e-6 of r^k (6e-7 observed); 1e-5 leaves margin and still catches a real error.
    EXPECT_NEAR(wf.depth, wd.depth, 1e-5 * r);
    EXPECT_NEAR(wf.overlap_area, wd.overlap_area, 1e-5 * r * r);
    EXPECT_NEAR(wf.section_area, wd.section_area, 1e-5 * r * r);
    EXPECT_NEAR(wf.volume_below, wd.volume_below, 1e-5 * r * r * r);
    EXPECT_NEAR(wf.overlap_centroid.x, wd.overlap_centroid.x, 1e-5 * r);
    EXPECT_NEAR(wf.overlap_centroid.y, wd.overlap_centroid.y, 1e-5 * r);
    EXPECT_NEAR(wf.overlap_centroid.z, wd.overlap_centroid.z, 1e-5 * r);
  }
  EXPECT_GT(compared, 100);
}

TEST(WallClip, ExactlyTouching_FiniteAndTouching) {
  const double side = 0.1;
  const auto cube = make_cube<double>(side);
  // Face on the plane: the contact patch is the face, with no depth and no volume.
  const WallContact<double> face = clip_big(cube, Posed{{0.1, 0.2, side / 2}, Quatd()});
  EXPECT_EQ(face.status, WallContactStatus::touching);
  EXPECT_EQ(face.depth, 0.0);
  EXPECT_EQ(face.volume_below, 0.0);
  EXPECT_NEAR(face.overlap_area, side * side, kClosedFormRel * side * side);
  EXPECT_TRUE(all_finite(face));

  // A corner on the plane (to round-off): a single section point, zero area.
  const Quatd corner_down = rotation_between(Vec3d{-1, -1, -1} / std::sqrt(3.0), {0, 0, -1});
  const WallContact<double> corner =
      clip_big(cube, Posed{{0, 0, side * std::sqrt(3.0) / 2}, corner_down});
  EXPECT_EQ(corner.status, WallContactStatus::touching);
  EXPECT_EQ(corner.overlap_area, 0.0);
  EXPECT_LT(corner.depth, 1e-15);
  EXPECT_LT(corner.volume_below, 1e-30);
  EXPECT_NEAR(corner.overlap_centroid.z, 0.0, 1e-15);
  EXPECT_TRUE(all_finite(corner));
}

TEST(WallClip, ParticleLyingInThePlaneFromBelow) {
  // The whole cube below the plane with its top face in it: the section is that face.
  const double side = 0.1;
  const auto cube = make_cube<double>(side);
  const WallContact<double> w = clip_big(cube, Posed{{0, 0, -side / 2}, Quatd()});
  EXPECT_EQ(w.status, WallContactStatus::overlapping);
  EXPECT_NEAR(w.depth, side, kClosedFormRel * side);
  EXPECT_NEAR(w.volume_below, side * side * side, kClosedFormRel * side * side * side);
  EXPECT_NEAR(w.overlap_area, side * side, kClosedFormRel * side * side);
  // Deeper still: no section, no overlap area, but the plane quantities are reported.
  const WallContact<double> deep = clip_big(cube, Posed{{0, 0, -side}, Quatd()});
  EXPECT_EQ(deep.status, WallContactStatus::none);
  EXPECT_EQ(deep.overlap_area, 0.0);
  EXPECT_EQ(deep.area_fraction(), 0.0);
  EXPECT_NEAR(deep.volume_below, side * side * side, kClosedFormRel * side * side * side);
  EXPECT_TRUE(all_finite(deep));
}

TEST(WallClip, DegenerateTriangles_DegenerateAndZero) {
  const auto cube = make_cube<double>(0.1);
  const Posed pose{{0, 0, 0.04}, Quatd()};
  const Vec3d a{-1, -1, 0};
  for (const auto& bc : {std::pair<Vec3d, Vec3d>{{1, 1, 0}, {2, 2, 0}},  // collinear
                         std::pair<Vec3d, Vec3d>{a, a},                  // a point
                         std::pair<Vec3d, Vec3d>{{1, -1, 0}, {1, -1, 1e-20}}}) {
    const WallContact<double> w = clip_against_triangle(cube.view(), pose, a, bc.first, bc.second);
    EXPECT_EQ(w.status, WallContactStatus::degenerate);
    EXPECT_EQ(w.overlap_area, 0.0);
    EXPECT_EQ(w.volume_below, 0.0);
    EXPECT_TRUE(all_finite(w));
  }
  const double nan = std::nan("");
  const WallContact<double> w =
      clip_against_triangle(cube.view(), Posed{{nan, 0, 0}, Quatd()}, kBigA, kBigB, kBigC);
  EXPECT_EQ(w.status, WallContactStatus::degenerate);
  EXPECT_TRUE(all_finite(w));
}

TEST(WallClip, FarAwayOrOffTheTriangle_None) {
  const auto cube = make_cube<double>(0.1);
  const WallContact<double> above = clip_big(cube, Posed{{0, 0, 5}, Quatd()});
  EXPECT_EQ(above.status, WallContactStatus::none);
  EXPECT_EQ(above.depth, 0.0);
  EXPECT_TRUE(all_finite(above));
  // Through the plane but beside the triangle: no overlap area, plane quantities still there.
  const WallContact<double> beside =
      clip_against_triangle(cube.view(), Posed{{-0.5, 0, 0.02}, Quatd()}, kEdgeA, kEdgeB, kEdgeC);
  EXPECT_EQ(beside.status, WallContactStatus::none);
  EXPECT_EQ(beside.overlap_area, 0.0);
  EXPECT_NEAR(beside.volume_below, 0.01 * 0.03, kClosedFormRel * 0.01 * 0.03);
  EXPECT_TRUE(all_finite(beside));
}

TEST(WallClip, SectionCapacityOverrun_FlaggedNotWritten) {
  const auto cube = make_cube<double>(0.1);
  // The flat section has 4 points; a capacity of 3 must flag, not write past the arrays.
  const WallContact<double> w = clip_against_triangle<double, 3>(
      cube.view(), Posed{{0, 0, 0.04}, Quatd()}, kBigA, kBigB, kBigC);
  EXPECT_TRUE(w.overrun);
  EXPECT_EQ(w.status, WallContactStatus::degenerate);
  EXPECT_TRUE(all_finite(w));
  const WallContact<double> fits = clip_against_triangle<double, 4>(
      cube.view(), Posed{{0, 0, 0.04}, Quatd()}, kBigA, kBigB, kBigC);
  EXPECT_FALSE(fits.overrun);
  EXPECT_EQ(fits.status, WallContactStatus::overlapping);
}

}  // namespace
}  // namespace talus
