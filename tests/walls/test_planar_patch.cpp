// Planar patches (solver/walls/planar_patch.hpp): which parts of the generated walls are found as
// one convex plane, and a particle over a drum's cap clipped once against the patch's plane
// against the same particle clipped against every facet of the fan.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "solver/contact/contact_laws.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/scene/wall_motion.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/walls/planar_patch_build.hpp"
#include "solver/walls/wall_contact.hpp"

namespace talus {
namespace {

WallSpec drum(double radius, double length, int segments) {
  WallSpec w;
  w.kind = WallKind::drum;
  DrumWall d;
  d.center = Vec3d(0.1, -0.2, 0.3);
  d.axis = Vec3d(0, 1, 0);
  d.radius = radius;
  d.length = length;
  d.segments = segments;
  w.shape = d;
  return w;
}

// The drum's two caps are its two patches: the fans after the side's 2 x segments facets, centred
// on the axis, facing into the drum, holding the disc of the inscribed polygon's radius
// R cos(pi / N) (less the build's margin of 1e-9 of the mesh's size: 1e-9 m here, far below
// the 1e-8 m the check allows).
TEST(PlanarPatch, ADrumsCapsAreItsPatches) {
  const int n = 64;
  const double radius = 0.15, length = 0.04;
  const WallMesh mesh = make_wall_mesh(drum(radius, length, n));
  const std::vector<PlanarPatch<double>> patches =
      find_planar_patches<double>(mesh.mesh.vertices, mesh.mesh.triangles);
  ASSERT_EQ(patches.size(), 2u);
  const Vec3d centre(0.1, -0.2, 0.3), axis(0, 1, 0);
  for (int k = 0; k < 2; ++k) {
    const PlanarPatch<double>& p = patches[k];
    EXPECT_EQ(p.first, 2 * n + k * n);
    EXPECT_EQ(p.end, 2 * n + (k + 1) * n);
    const double side = k == 0 ? -1 : 1;  // the bottom cap faces +axis, the top one -axis
    EXPECT_LT(norm(p.centre - (centre + axis * (side * length / 2))), 1e-12);
    EXPECT_LT(norm(p.normal - axis * (-side)), 1e-12);
    EXPECT_NEAR(p.inradius, radius * std::cos(M_PI / n), 1e-8);
  }
}

// A box's faces have two facets each (below kMinPatchFacets): none. A flat-bottomed silo's
// annulus is planar but not convex (two boundary loops): not a patch; its closed outlet's plate
// (a fan) is.
TEST(PlanarPatch, BoxesHaveNoneAnAnnulusIsNotOneAPlateIs) {
  WallSpec box;
  box.kind = WallKind::box;
  box.shape = BoxWall{Vec3d(0, 0, 0), Vec3d(1, 2, 3), false};
  const WallMesh b = make_wall_mesh(box);
  EXPECT_TRUE(find_planar_patches<double>(b.mesh.vertices, b.mesh.triangles).empty());

  WallSpec silo;
  silo.kind = WallKind::silo;
  SiloWall s;
  s.base = Vec3d(0, 0, 0);
  s.axis = Vec3d(0, 0, 1);
  s.radius = 0.2;
  s.height = 0.5;
  s.cone_height = 0;
  s.outlet_radius = 0.05;
  s.outlet.closed = true;
  s.segments = 32;
  silo.shape = s;
  const WallMesh m = make_wall_mesh(silo);
  const std::vector<PlanarPatch<double>> patches =
      find_planar_patches<double>(m.mesh.vertices, m.mesh.triangles);
  ASSERT_EQ(patches.size(), 1u);
  const int total = static_cast<int>(m.mesh.triangles.size());
  EXPECT_EQ(patches[0].first, total - m.plate_triangles);
  EXPECT_EQ(patches[0].end, total);
  EXPECT_NEAR(patches[0].inradius, 0.05 * std::cos(M_PI / 32), 1e-8);
}

// A wall's facets with or without its patches, for the comparison below.
struct Wall {
  std::vector<Vec3d> corners;
  std::vector<PlanarPatch<double>> patches;
  WallFacets<double> facets(bool with_patches, const RigidTransform& at) const {
    WallFacets<double> f;
    f.corners = corners.data();
    f.count = static_cast<int>(corners.size() / 3);
    f.rotation = at.rotation;
    f.translation = at.translation;
    if (with_patches) {
      f.patches = patches.data();
      f.patch_count = static_cast<int>(patches.size());
    }
    return f;
  }
};

// Dodecahedra of 10 mm pressed into a 256-segment drum's cap at random places and tilts, the drum
// turned and moved away from its mesh frame (as a rotating drum is): the contact through the
// patch (one clipping) is the contact of the fan's facets (up to all 256 of them near the
// centre) to round-off. The facets' weights add up to one only to round-off and each facet's
// plane is its corners' (thin triangles: their normals err by ~1e-14), so forces, stiffnesses,
// areas and energies agree to 1e-9 relative and the point to 1e-12 m, under each law. Enough
// poses must be held by the patch, and enough clear of its plane (the test would otherwise
// compare the fan with itself).
TEST(PlanarPatch, ACapsPatchGivesTheContactOfItsFacets) {
  const int n = 256;
  const double radius = 0.15, length = 0.04;
  const WallMesh mesh = make_wall_mesh(drum(radius, length, n));
  RigidTransform at;
  at.rotation = Quatd::from_axis_angle(Vec3d(0, 1, 0), 0.7);
  at.translation = Vec3d(0.01, 0.02, -0.03);
  Wall wall;
  for (const auto& t : mesh.mesh.triangles) {
    for (const int k : t) wall.corners.push_back(at.apply(mesh.mesh.vertices[k]));
  }
  wall.patches = find_planar_patches<double>(mesh.mesh.vertices, mesh.mesh.triangles);
  ASSERT_EQ(wall.patches.size(), 2u);
  const ShapeArrays<double> grain(make_shape("dodecahedron:0.01"));
  const double r = grain.view().bounding_radius;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Vec3d cap_centre(0.1, -0.2 - length / 2, 0.3);  // the bottom cap (facing +y)
  int held = 0, clear = 0, poses = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Within 1.1 R of the cap's centre (some poses reach the rim, where the facets decide),
    // the centre up to 1.4 r above the plane (above r the patch is clear of the particle).
    const double rho = 1.1 * radius * std::sqrt(0.5 * (1 + unit(rng)));
    const double angle = M_PI * unit(rng);
    const double x = rho * std::cos(angle), z = rho * std::sin(angle);
    const Vec3d mesh_centre = cap_centre + Vec3d(x, 1.4 * r * (0.5 + 0.5 * unit(rng)), z);
    Quatd q(unit(rng), unit(rng), unit(rng), unit(rng));
    const Pose<double> pose{at.apply(mesh_centre), q.normalized()};
    for (const ContactModel model :
         {ContactModel::volume, ContactModel::volume_paper, ContactModel::linear}) {
      with_contact_law(model, [&](auto law) {
        using Law = decltype(law);
        const WallContactGeometry<double> fan = polyhedron_wall_geometry<Law>(
            grain.view(), pose, wall.facets(false, at), 1e9, 4e8, 1.3e-5);
        const WallContactGeometry<double> patch = polyhedron_wall_geometry<Law>(
            grain.view(), pose, wall.facets(true, at), 1e9, 4e8, 1.3e-5);
        ASSERT_EQ(fan.in_contact, patch.in_contact) << trial;
        if (!fan.in_contact) return;
        ++poses;
        EXPECT_NEAR(patch.elastic, fan.elastic, 1e-9 * fan.elastic) << trial;
        EXPECT_LT(norm(patch.normal - fan.normal), 1e-9) << trial;
        EXPECT_LT(norm(patch.point - fan.point), 1e-12) << trial;
        EXPECT_NEAR(patch.normal_stiffness, fan.normal_stiffness,
                    1e-9 * fan.normal_stiffness + 1e-30)
            << trial;
        EXPECT_NEAR(patch.tangential_stiffness, fan.tangential_stiffness,
                    1e-9 * fan.tangential_stiffness + 1e-30)
            << trial;
        EXPECT_NEAR(patch.area, fan.area, 1e-9 * fan.area + 1e-30) << trial;
        EXPECT_NEAR(patch.potential, fan.potential, 1e-9 * fan.potential) << trial;
        EXPECT_LT(norm(patch.couple - fan.couple), 1e-9 * fan.elastic * r) << trial;
      });
    }
    const Vec3d foot = mesh_centre - cap_centre;
    if (foot.y > r) {
      ++clear;
    } else if (std::hypot(foot.x, foot.z) + r < wall.patches[0].inradius) {
      ++held;
    }
  }
  EXPECT_GT(poses, 200);  // of 600: the rest do not reach the plane
  EXPECT_GT(held, 80);
  EXPECT_GT(clear, 40);
}

}  // namespace
}  // namespace talus
