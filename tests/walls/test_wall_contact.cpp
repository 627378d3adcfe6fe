// One particle against one wall (solver/walls/wall_contact.hpp): the area weighting of §2.4 makes
// a particle over facet edges or vertices count once, and the sphere's nearest-facet rule is
// exact there; the facets of a corner each push at their own point.
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

// A tilted cube pressed into the corner of a floor (z = 0) and a side wall (x = 0), one wall of
// two facets in different planes: the contact's force at its point plus its couple turn the
// cube as each facet's force at the facet's own point does (each facet alone is the same facet
// computation, so the sums agree to round-off, 1e-12 of |F| R). Without the couple the torques
// differ by 0.8 % (linear) to 9 % (volume laws) of |F| R here: one force at one averaged point
// is not the facets' forces.
TEST(WallContact, FacetsOfACornerPushAtTheirOwnPoints) {
  const ShapeArrays<double> cube(make_shape("cube:0.01"));
  const Pose<double> pose{Vec3d(kHalfEdge - 2e-5, 0.001, kHalfEdge - 3e-5),
                          Quatd::from_axis_angle(Vec3d(0.6, 0, 0.8), 0.01).normalized()};
  const std::vector<Vec3d> floor = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  const std::vector<Vec3d> side = {{0, -1, -1}, {0, 1, -1}, {0, 0, 1}};
  std::vector<Vec3d> both = floor;
  both.insert(both.end(), side.begin(), side.end());
  for (const ContactModel model :
       {ContactModel::volume, ContactModel::volume_paper, ContactModel::linear}) {
    with_contact_law(model, [&](auto law) {
      using Law = decltype(law);
      const auto geometry = [&](const std::vector<Vec3d>& corners) {
        return polyhedron_wall_geometry<Law>(cube.view(), pose, facets_of(corners), 1e9, 4e8,
                                             1.3e-5);
      };
      const WallContactGeometry<double> corner = geometry(both), f = geometry(floor),
                                        s = geometry(side);
      ASSERT_TRUE(corner.in_contact && f.in_contact && s.in_contact);
      // The force on the particle is -elastic n (n from the particle into the wall).
      const Vec3d force_f = f.normal * -f.elastic, force_s = s.normal * -s.elastic;
      const Vec3d force = corner.normal * -corner.elastic;
      const Vec3d x = pose.position;
      const Vec3d facets = cross(f.point - x, force_f) + cross(s.point - x, force_s);
      const Vec3d contact = cross(corner.point - x, force) + corner.couple;
      const double scale = norm(force) * 0.01;
      EXPECT_LT(norm(force - (force_f + force_s)), 1e-12 * norm(force));
      EXPECT_LT(norm(contact - facets), 1e-12 * scale);
      EXPECT_GT(norm(corner.couple), 1e-3 * scale) << norm(corner.couple) / scale;
      EXPECT_LT(norm(f.couple), 1e-12 * scale) << norm(corner.couple) / scale;  // one facet: none
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
