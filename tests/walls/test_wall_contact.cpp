// One particle against one wall (solver/walls/wall_contact.hpp): the area weighting of §2.4 makes
// a particle over facet edges or vertices count once, and the sphere's nearest-facet rule is
// exact there.
#include <gtest/gtest.h>

#include <vector>

#include "solver/contact/contact_laws.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/walls/wall_contact.hpp"

namespace talus {
namespace {

// The square [-s, s]^2 at z = 0 (normal +z) as two triangles split along a diagonal, or as the
// four triangles of a fan about the centre.
std::vector<Vec3d> square_two(double s) {
  return {{-s, -s, 0}, {s, -s, 0}, {s, s, 0}, {-s, -s, 0}, {s, s, 0}, {-s, s, 0}};
}
std::vector<Vec3d> square_fan(double s) {
  const Vec3d o(0, 0, 0), a(-s, -s, 0), b(s, -s, 0), c(s, s, 0), d(-s, s, 0);
  return {o, a, b, o, b, c, o, c, d, o, d, a};
}

// Without a grid: every facet is tested (brute force).
WallFacets<double> facets_of(const std::vector<Vec3d>& corners) {
  WallFacets<double> f;
  f.corners = corners.data();
  f.count = static_cast<int>(corners.size() / 3);
  return f;
}

// "cube:D" has circumscribed diameter D: half its edge is D / (2 sqrt 3).
constexpr double kHalfEdge = 0.01 / (2 * 1.7320508075688772);

// A tilted cube sunk into the wall right over the shared vertex of the fan and across the
// diagonal of the two-triangle split: the elastic force, normal, stiffness and point are those
// of one large facet under it (one contact, counted once), to round-off of the clipping (1e-12).
TEST(WallContact, AreaWeightingCountsAParticleOverEdgesAndVerticesOnce) {
  const ShapeArrays<double> cube(make_shape("cube:0.01"));
  const Pose<double> pose{Vec3d(0, 0, kHalfEdge),
                          Quatd::from_axis_angle(Vec3d(0.6, 0.8, 0), 0.2).normalized()};
  const std::vector<Vec3d> big = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  for (const ContactModel model :
       {ContactModel::volume, ContactModel::volume_paper, ContactModel::linear}) {
    with_contact_law(model, [&](auto law) {
      using Law = decltype(law);
      const WallContactGeometry<double> one =
          polyhedron_wall_geometry<Law>(cube.view(), pose, facets_of(big), 1e9, 4e8, 1.3e-5);
      ASSERT_TRUE(one.in_contact);
      EXPECT_NEAR(one.normal.z, -1.0, 1e-15);  // from the particle into the wall
      for (const std::vector<Vec3d>& mesh : {square_two(0.05), square_fan(0.05)}) {
        const WallContactGeometry<double> split =
            polyhedron_wall_geometry<Law>(cube.view(), pose, facets_of(mesh), 1e9, 4e8, 1.3e-5);
        ASSERT_TRUE(split.in_contact);
        EXPECT_NEAR(split.elastic, one.elastic, 1e-12 * one.elastic);
        EXPECT_NEAR(split.normal_stiffness, one.normal_stiffness,
                    1e-12 * one.normal_stiffness + 1e-30);
        EXPECT_NEAR(split.area, one.area, 1e-12 * one.area);
        EXPECT_NEAR(split.potential, one.potential, 1e-12 * one.potential);
        EXPECT_LT(norm(split.point - one.point), 1e-12);
      }
    });
  }
}

// Half of the cube's section beyond the wall's edge: weight 1/2, so half the elastic force.
TEST(WallContact, SectionHalfOverTheEdgeHalvesTheForce) {
  const ShapeArrays<double> cube(make_shape("cube:0.01"));
  const Pose<double> centred{Vec3d(0, 0, kHalfEdge - 1e-4), Quatd()};
  const Pose<double> on_edge{Vec3d(0.05, 0, kHalfEdge - 1e-4), Quatd()};
  const std::vector<Vec3d> mesh = square_two(0.05);
  const WallContactGeometry<double> full =
      polyhedron_wall_geometry<LinearLaw>(cube.view(), centred, facets_of(mesh), 1e4, 0.0, 0.0);
  const WallContactGeometry<double> half =
      polyhedron_wall_geometry<LinearLaw>(cube.view(), on_edge, facets_of(mesh), 1e4, 0.0, 0.0);
  ASSERT_TRUE(full.in_contact && half.in_contact);
  EXPECT_NEAR(full.elastic, 1e4 * 1e-4, 1e-12);  // K_N delta, delta = 0.1 mm
  EXPECT_NEAR(half.elastic, 0.5 * full.elastic, 1e-12);
  EXPECT_NEAR(full.potential, 0.5 * 1e4 * 1e-4 * 1e-4, 1e-15);  // K_N delta^2 / 2
  EXPECT_NEAR(half.point.x, 0.05 - kHalfEdge / 2, 1e-12);  // the centroid of the part on the wall
}

// A sphere sliding across the shared edge of two coplanar facets keeps one contact of the same
// depth (nearest-facet rule), and the centre beyond the outer edge sees the edge.
TEST(WallContact, SphereNearestFacetIsExactAcrossEdges) {
  const std::vector<Vec3d> mesh = square_two(0.05);
  for (const double x : {-0.02, 0.0, 0.001, 0.03}) {
    const WallContactGeometry<double> g =
        sphere_wall_geometry(Vec3d(x, x, 0.004), 0.005, facets_of(mesh), 1e4);
    ASSERT_TRUE(g.in_contact) << x;
    EXPECT_NEAR(g.elastic, 1e4 * 0.001, 1e-15) << x;
    EXPECT_NEAR(g.normal.z, -1.0, 1e-15);
    EXPECT_NEAR(g.point.z, -0.0005, 1e-15);  // midway between q (z = 0) and the deepest point
  }
  const WallContactGeometry<double> beyond =
      sphere_wall_geometry(Vec3d(0.053, 0, 0.0), 0.005, facets_of(mesh), 1e4);
  ASSERT_TRUE(beyond.in_contact);
  EXPECT_NEAR(beyond.normal.x, -1.0, 1e-15);
  EXPECT_NEAR(beyond.elastic, 1e4 * 0.002, 1e-12);
  EXPECT_FALSE(sphere_wall_geometry(Vec3d(0, 0, 0.006), 0.005, facets_of(mesh), 1e4).in_contact);
}

// The velocity of a rotating wall's material point: w axis x (x - point).
TEST(WallContact, RotatingWallPointVelocity) {
  WallMotionData<double> m;
  m.kind = 1;
  m.axis = Vec3d(0, 0, 1);
  m.point = Vec3d(1, 0, 0);
  m.angular_speed = 2.0;
  const Vec3d v = m.velocity_at(Vec3d(2, 0, 5));
  EXPECT_DOUBLE_EQ(v.y, 2.0);
  EXPECT_DOUBLE_EQ(v.x, 0.0);
}

}  // namespace
}  // namespace talus
