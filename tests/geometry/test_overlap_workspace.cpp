// The overlap's workspace: the result must not depend on what the workspace held before (on the
// GPU it is uninitialised local memory) nor on its capacity, and overlap_from_mask must give
// overlap_polyhedra's result bit for bit (the GPU batch and step rely on both).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using testing::pose_of;
using testing::TestShape;
using testing::view_of;

template <class Real>
void expect_same_bits(const OverlapResult<Real>& a, const OverlapResult<Real>& b,
                      const char* what) {
  const Real fa[8] = {a.volume,     a.vector_area.x, a.vector_area.y, a.vector_area.z,
                      a.centroid.x, a.centroid.y,    a.centroid.z,    a.depth_hint};
  const Real fb[8] = {b.volume,     b.vector_area.x, b.vector_area.y, b.vector_area.z,
                      b.centroid.x, b.centroid.y,    b.centroid.z,    b.depth_hint};
  EXPECT_EQ(a.status, b.status) << what;
  EXPECT_EQ(std::memcmp(fa, fb, sizeof fa), 0) << what;
  EXPECT_EQ(a.hull_points, b.hull_points) << what;
  EXPECT_EQ(a.workspace_overrun, b.workspace_overrun) << what;
}

struct Case {
  int a, b;
  Posed pose_a, pose_b;
};

// Random pairs at several depths, and face-to-face pairs from exactly touching to 0.1 of the
// width, as placed or moved and tilted by 1e-12 or 1e-9 (of the width, rad): nearly coplanar dual
// points, the hull's hard cases.
std::vector<Case> make_cases(const std::vector<TestShape>& shapes) {
  std::mt19937_64 rng(20261124);
  std::vector<Case> cases;
  const double depths[3][2] = {{0, 0.01}, {0, 0.1}, {0.1, 0.6}};
  for (int i = 0; i < int(shapes.size()); ++i)
    for (int j = 0; j < int(shapes.size()); ++j)
      for (const auto& d : depths)
        for (int k = 0; k < 3; ++k) {
          const PosePair p = random_overlapping_pair(rng, shapes[i].shape.bounding_radius,
                                                     shapes[j].shape.bounding_radius, d[0], d[1]);
          cases.push_back({i, j, p.a, p.b});
        }
  for (int i = 0; i < int(shapes.size()); ++i) {
    const ShapeTemplate& s = shapes[i].shape;
    const int j = (i + 1) % int(shapes.size());
    const ShapeTemplate& t = shapes[j].shape;
    for (int f = 0; f < int(s.faces.size()) && f < 12; ++f)
      for (double tilt : {0.0, 1e-12, 1e-9})
        for (double depth : {0.0, 1e-6, 1e-3, 0.1}) {
          const Vec3d n = s.faces[f].normal;
          const Quatd base = random_rotation(rng);
          const Vec3d axis = random_direction(rng);
          const Quatd turn(std::cos(tilt / 2), axis.x * std::sin(tilt / 2),
                           axis.y * std::sin(tilt / 2), axis.z * std::sin(tilt / 2));
          const Posed pa{Vec3d(0.3, -0.2, 0.1), base};
          // A copy of A, shifted across face f by its width along n less `depth` of it.
          double low = 1e300;
          for (const auto& v : s.vertices) low = std::min(low, dot(n, v));
          const double width = s.faces[f].offset - low;
          const Vec3d jitter = random_direction(rng) * (tilt * width);
          cases.push_back(
              {i, i, pa,
               Posed{pa.position + rotate(base, n * (width * (1 - depth))) + jitter, base * turn}});
          // Face 0 of another shape turned against face f.
          const Vec3d m = t.faces[0].normal;
          const Vec3d c = cross(m, -n);
          const double sin_angle = norm(c), cos_angle = dot(m, -n);
          Quatd align;
          if (sin_angle > 1e-12) {
            const double angle = std::atan2(sin_angle, cos_angle);
            const Vec3d u = c / sin_angle;
            align = Quatd(std::cos(angle / 2), u.x * std::sin(angle / 2), u.y * std::sin(angle / 2),
                          u.z * std::sin(angle / 2));
          } else if (cos_angle < 0) {
            align = Quatd(0, 1, 0, 0);
          }
          const double gap = s.faces[f].offset + t.faces[0].offset - depth * width;
          cases.push_back(
              {i, j, pa, Posed{pa.position + rotate(base, n * gap) + jitter, base * align * turn}});
        }
  }
  return cases;
}

std::vector<TestShape> shapes_of_few_faces() {
  std::vector<TestShape> shapes;
  for (const auto& spec : testing::builtin_specs()) {
    TestShape s(spec);
    if (s.shape.faces.size() <= 32) shapes.push_back(std::move(s));
  }
  return shapes;
}

template <class Real, int Cap>
void check_capacity(const ConvexView<Real>& a, const Pose<Real>& pa, const ConvexView<Real>& b,
                    const Pose<Real>& pb, unsigned long long mask, int m,
                    const OverlapResult<Real>& full) {
  if (m > Cap) return;
  auto ws = std::make_unique<OverlapWorkspace<Real, Cap>>();
  const OverlapResult<Real> r = overlap_from_mask(a, pa, b, pb, mask, *ws);
  // A workspace of m planes holds the hull of m dual points (2m - 4 faces): no overrun.
  EXPECT_FALSE(r.workspace_overrun) << "capacity " << Cap << ", " << m << " planes";
  expect_same_bits(r, full, "overlap_from_mask against overlap_polyhedra");
}

template <class Real>
void mask_matches_polyhedra(const std::vector<TestShape>& shapes, const std::vector<Case>& cases) {
  auto ws = std::make_unique<OverlapWorkspace<Real, 256>>();
  int overlapping = 0, built = 0;
  for (const Case& c : cases) {
    const ConvexView<Real> a = view_of<Real>(shapes[c.a]), b = view_of<Real>(shapes[c.b]);
    const Pose<Real> pa = pose_of<Real>(c.pose_a), pb = pose_of<Real>(c.pose_b);
    const OverlapResult<Real> full = overlap_polyhedra(a, pa, b, pb, *ws);
    unsigned long long mask = 0;
    OverlapResult<Real> early;
    const int m = overlap_cull_mask(a, pa, b, pb, OverlapOptions(), mask, early);
    if (m < 0) {
      expect_same_bits(early, full, "overlap_cull_mask's final result");
      continue;
    }
    ++built;
    overlapping += full.status == OverlapStatus::overlapping;
    check_capacity<Real, 8>(a, pa, b, pb, mask, m, full);
    check_capacity<Real, 16>(a, pa, b, pb, mask, m, full);
    check_capacity<Real, 32>(a, pa, b, pb, mask, m, full);
    check_capacity<Real, 64>(a, pa, b, pb, mask, m, full);
  }
  // The sets must exercise the polytope, not only the early exits.
  EXPECT_GT(built, int(cases.size()) / 3) << overlapping;
  EXPECT_GT(overlapping, int(cases.size()) / 4) << built;
}

TEST(OverlapWorkspace, FromMaskGivesPolyhedraBitsAtEveryCapacity) {
  const std::vector<TestShape> shapes = shapes_of_few_faces();
  const std::vector<Case> cases = make_cases(shapes);
  mask_matches_polyhedra<double>(shapes, cases);
  mask_matches_polyhedra<float>(shapes, cases);
}

// Every byte of the workspace set to `fill` before the overlap: the result must be the same for
// any fill, i.e. nothing is read before it is written in this pair.
template <class Real>
OverlapResult<Real> overlap_in_filled(const ConvexView<Real>& a, const Pose<Real>& pa,
                                      const ConvexView<Real>& b, const Pose<Real>& pb,
                                      unsigned char fill) {
  auto ws = std::make_unique<OverlapWorkspace<Real, 64>>();
  std::memset(static_cast<void*>(ws.get()), fill, sizeof(*ws));
  return overlap_polyhedra(a, pa, b, pb, *ws);
}

template <class Real>
void independent_of_fill(const std::vector<TestShape>& shapes, const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    const ConvexView<Real> a = view_of<Real>(shapes[c.a]), b = view_of<Real>(shapes[c.b]);
    const Pose<Real> pa = pose_of<Real>(c.pose_a), pb = pose_of<Real>(c.pose_b);
    const OverlapResult<Real> zero = overlap_in_filled(a, pa, b, pb, 0x00);
    for (unsigned char fill : {0x01, 0x7f, 0xfe, 0xa5})
      expect_same_bits(overlap_in_filled(a, pa, b, pb, fill), zero, "workspace filled");
  }
}

TEST(OverlapWorkspace, ResultDoesNotDependOnFormerContents) {
  const std::vector<TestShape> shapes = shapes_of_few_faces();
  const std::vector<Case> cases = make_cases(shapes);
  independent_of_fill<double>(shapes, cases);
  independent_of_fill<float>(shapes, cases);
}

// A face of an icosahedron on a tetrahedron's face, touching to round-off (found by a sweep of
// such pairs): the dual points are nearly flat, and the initial simplex once took the second of
// its own vertices again as the fourth, whose faces then found no neighbours (reads and writes
// outside the arrays, a result that depended on the workspace's former contents).
TEST(OverlapWorkspace, NearlyFlatDualPointsBuildASimplexOfFourPoints) {
  const TestShape a("icosahedron:0.009"), b("tetrahedron:0.012");
  const Posed pa{
      {0x1.3333333333333p-2, -0x1.999999999999ap-3, 0x1.999999999999ap-4},
      {-0x1.22e76c4e86f54p-1, 0x1.5f40435445264p-2, -0x1.3404de78cd88ap-1, 0x1.c72fe6c13afcp-2}};
  const Posed pb{
      {0x1.3727eaa54d206p-2, -0x1.9211a512e9a03p-3, 0x1.92f0736bc56a7p-4},
      {-0x1.23a26dcc726e7p-3, 0x1.83e82c7d5a9d5p-1, -0x1.10b65c01b8717p-1, 0x1.65af328a2393ap-2}};
  const OverlapResult<double> zero = overlap_in_filled(a.view(), pa, b.view(), pb, 0x00);
  EXPECT_NE(zero.status, OverlapStatus::degenerate);
  EXPECT_FALSE(zero.workspace_overrun);
  for (unsigned char fill : {0x01, 0x7f, 0xfe, 0xa5})
    expect_same_bits(overlap_in_filled(a.view(), pa, b.view(), pb, fill), zero, "workspace filled");
}

}  // namespace
}  // namespace talus
