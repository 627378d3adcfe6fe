// Generated walls: their areas against the closed forms of the polygons they are made of, normals
// facing the particles' side, watertight closed walls, and the transform of mesh walls.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/scene/scene_test_util.hpp"
#include "tests/scene/wall_test_util.hpp"

namespace talus {
namespace {

// A mesh area is a sum of at most a few hundred triangle areas, each within a few ulps: 1e-12
// relative is 1000x round-off, and far below any mistake of a whole triangle (>= 1/(4n) of it).
constexpr double kAreaRelTol = 1e-12;
// Normals and positions are computed from a few products of unit vectors: 1e-14 absolute.
constexpr double kRoundOff = 1e-14;

// Closed forms for a circle of radius r replaced by its inscribed regular n-gon.
double polygon_area(double r, int n) {
  return 0.5 * n * r * r * std::sin(2 * M_PI / n);
}
// The lateral area of the n-gon frustum between radii r1 and r2, height h: n planar trapezoids
// with parallel sides 2 r sin(pi/n) and slant height sqrt(h^2 + (apothem2 - apothem1)^2).
double frustum_side_area(double r1, double r2, double h, int n) {
  const double c = std::cos(M_PI / n), s = std::sin(M_PI / n);
  const double slant = std::sqrt(h * h + (r2 - r1) * c * (r2 - r1) * c);
  return n * (r1 + r2) * s * slant;
}

double distance_to_axis(const Vec3d& p, const Vec3d& base, const Vec3d& axis) {
  const Vec3d d = p - base;
  return norm(d - axis * dot(d, axis));
}

// Every triangle's normal points towards `inside`: the point is on the particles' side of it.
void expect_faces_towards(const TriangleMesh& mesh, const Vec3d& inside) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    EXPECT_GT(dot(triangle_normal(mesh, t), inside - triangle_centroid(mesh, t)), 0)
        << "triangle " << t;
}

const Vec3d kTilted = Vec3d(1, -2, 2) / 3.0;  // a unit axis along no coordinate axis

TEST(WallMeshes, AxisBasisIsRightHandedAndOrthonormal) {
  for (const Vec3d& axis : {Vec3d(0, 0, 1), Vec3d(1, 0, 0), Vec3d(0, -1, 0), kTilted}) {
    Vec3d u, v;
    axis_basis(axis, u, v);
    EXPECT_NEAR(norm(u), 1, kRoundOff);
    EXPECT_NEAR(norm(v), 1, kRoundOff);
    EXPECT_NEAR(dot(u, axis), 0, kRoundOff);
    EXPECT_NEAR(norm(cross(u, v) - axis), 0, kRoundOff);
  }
}

TEST(WallMeshes, PlaneIsASquareFacingItsNormal) {
  PlaneWall plane;
  plane.point = {0.1, -0.2, 0.3};
  plane.normal = kTilted;
  plane.size = 0.5;
  const WallMesh wall = make_wall_mesh(wall_spec(WallKind::plane, plane));
  ASSERT_EQ(wall.mesh.triangles.size(), 2u);
  EXPECT_NEAR(mesh_area(wall.mesh), 0.25, 0.25 * kAreaRelTol);
  for (std::size_t t = 0; t < 2; ++t)
    EXPECT_NEAR(norm(triangle_normal(wall.mesh, t) - plane.normal), 0, kRoundOff);
  for (const Vec3d& p : wall.mesh.vertices) {
    EXPECT_NEAR(dot(p - plane.point, plane.normal), 0, kRoundOff);         // in the plane
    EXPECT_NEAR(norm(p - plane.point), 0.25 * std::sqrt(2.0), kRoundOff);  // a corner
  }
  EXPECT_EQ(boundary_edges(wall.mesh), 4);
  EXPECT_EQ(wall.plate_triangles, 0);
}

TEST(WallMeshes, BoxIsClosedAndFacesInward) {
  BoxWall box;
  box.min = {-0.1, 0, 0.2};
  box.max = {0.3, 0.2, 0.5};
  const double a = 0.4, b = 0.2, c = 0.3;
  const WallMesh closed = make_wall_mesh(wall_spec(WallKind::box, box));
  EXPECT_EQ(closed.mesh.triangles.size(), 12u);
  const double area = 2 * (a * b + b * c + c * a);
  EXPECT_NEAR(mesh_area(closed.mesh), area, area * kAreaRelTol);
  EXPECT_TRUE(is_watertight(closed.mesh));
  expect_faces_towards(closed.mesh, (box.min + box.max) / 2.0);
  // Each normal is a coordinate axis, pointing away from the face it lies on.
  for (std::size_t t = 0; t < 12; ++t) {
    const Vec3d n = triangle_normal(closed.mesh, t);
    EXPECT_NEAR(std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z), 1, kRoundOff);
  }

  box.open_top = true;
  const WallMesh open = make_wall_mesh(wall_spec(WallKind::box, box));
  EXPECT_EQ(open.mesh.triangles.size(), 10u);
  EXPECT_NEAR(mesh_area(open.mesh), area - a * b, area * kAreaRelTol);
  EXPECT_EQ(boundary_edges(open.mesh), 4);  // the rim at max z
  for (std::size_t t = 0; t < 10; ++t)
    EXPECT_GT(triangle_normal(open.mesh, t).z, -1 + kRoundOff);  // no face at the top
  expect_faces_towards(open.mesh, (box.min + box.max) / 2.0);
}

TEST(WallMeshes, CylinderSideAndCapsAgainstThePolygon) {
  CylinderWall cylinder;
  cylinder.base = {0.2, 0.1, -0.3};
  cylinder.axis = kTilted;
  cylinder.radius = 0.05;
  cylinder.height = 0.2;
  cylinder.segments = 48;
  const int n = cylinder.segments;
  const double side = frustum_side_area(0.05, 0.05, 0.2, n), cap = polygon_area(0.05, n);
  const Vec3d middle = cylinder.base + cylinder.axis * 0.1;

  const WallMesh open = make_wall_mesh(wall_spec(WallKind::cylinder, cylinder));
  EXPECT_EQ(open.mesh.triangles.size(), std::size_t(2 * n));
  EXPECT_NEAR(mesh_area(open.mesh), side, side * kAreaRelTol);
  EXPECT_EQ(boundary_edges(open.mesh), 2 * n);
  for (std::size_t t = 0; t < open.mesh.triangles.size(); ++t) {
    // Perpendicular to the axis and pointing at it.
    const Vec3d normal = triangle_normal(open.mesh, t), centroid = triangle_centroid(open.mesh, t);
    EXPECT_NEAR(dot(normal, cylinder.axis), 0, kRoundOff);
    const Vec3d to_axis =
        (cylinder.base - centroid) - cylinder.axis * dot(cylinder.base - centroid, cylinder.axis);
    EXPECT_NEAR(dot(normal, to_axis / norm(to_axis)), 1, 1e-2);  // within the half-segment
  }
  for (const Vec3d& p : open.mesh.vertices)
    EXPECT_NEAR(distance_to_axis(p, cylinder.base, cylinder.axis), 0.05, kRoundOff);

  cylinder.bottom_cap = cylinder.top_cap = true;
  const WallMesh closed = make_wall_mesh(wall_spec(WallKind::cylinder, cylinder));
  EXPECT_NEAR(mesh_area(closed.mesh), side + 2 * cap, side * kAreaRelTol);
  EXPECT_TRUE(is_watertight(closed.mesh));
  expect_faces_towards(closed.mesh, middle);
  // The caps face along the axis: the bottom one up it, the top one down it.
  int up = 0, down = 0;
  for (std::size_t t = 0; t < closed.mesh.triangles.size(); ++t) {
    const double along = dot(triangle_normal(closed.mesh, t), cylinder.axis);
    up += along > 1 - kRoundOff;
    down += along < -1 + kRoundOff;
  }
  EXPECT_EQ(up, n);
  EXPECT_EQ(down, n);

  cylinder.top_cap = false;
  const WallMesh cup = make_wall_mesh(wall_spec(WallKind::cylinder, cylinder));
  EXPECT_NEAR(mesh_area(cup.mesh), side + cap, side * kAreaRelTol);
  EXPECT_EQ(boundary_edges(cup.mesh), n);
  expect_faces_towards(cup.mesh, middle);
}

TEST(WallMeshes, DrumIsClosedAndCentred) {
  DrumWall drum;
  drum.center = {0, 0, 0.05};
  drum.axis = {1, 0, 0};
  drum.radius = 0.1;
  drum.length = 0.12;
  drum.segments = 96;
  const WallMesh wall = make_wall_mesh(wall_spec(WallKind::drum, drum));
  const double area = frustum_side_area(0.1, 0.1, 0.12, 96) + 2 * polygon_area(0.1, 96);
  EXPECT_NEAR(mesh_area(wall.mesh), area, area * kAreaRelTol);
  EXPECT_TRUE(is_watertight(wall.mesh));
  expect_faces_towards(wall.mesh, drum.center);
  expect_faces_towards(wall.mesh, drum.center + Vec3d(0.05, 0.09, 0));  // off-centre, inside
  for (const Vec3d& p : wall.mesh.vertices) {
    EXPECT_LE(std::fabs(p.x - drum.center.x), 0.06 + kRoundOff);
    EXPECT_LE(distance_to_axis(p, drum.center, drum.axis), 0.1 + kRoundOff);
  }
}

TEST(WallMeshes, HopperFrustumAndItsOutletPlate) {
  HopperWall hopper;
  hopper.base = {0, 0, -0.1};
  hopper.axis = kTilted;
  hopper.bottom_radius = 0.01;
  hopper.top_radius = 0.06;
  hopper.height = 0.1;
  hopper.segments = 64;
  const double side = frustum_side_area(0.01, 0.06, 0.1, 64), plate = polygon_area(0.01, 64);
  const Vec3d inside = hopper.base + hopper.axis * 0.05;

  const WallMesh open = make_wall_mesh(wall_spec(WallKind::hopper, hopper));
  EXPECT_NEAR(mesh_area(open.mesh), side, side * kAreaRelTol);
  EXPECT_EQ(open.plate_triangles, 0);
  EXPECT_EQ(boundary_edges(open.mesh), 2 * 64);  // outlet and top rims
  expect_faces_towards(open.mesh, inside);
  // A funnel widening upwards holds particles up: every normal has a component along the axis,
  // tan of the wall's slope: (r2 - r1) cos(pi/n) / h over the slant, as the closed form says.
  const double c = std::cos(M_PI / 64);
  const double rise = 0.05 * c / std::sqrt(0.01 + 0.05 * c * 0.05 * c);
  for (std::size_t t = 0; t < open.mesh.triangles.size(); ++t)
    EXPECT_NEAR(dot(triangle_normal(open.mesh, t), hopper.axis), rise, kRoundOff);

  hopper.outlet.closed = true;
  const WallMesh closed = make_wall_mesh(wall_spec(WallKind::hopper, hopper));
  EXPECT_NEAR(mesh_area(closed.mesh), side + plate, side * kAreaRelTol);
  EXPECT_EQ(closed.plate_triangles, 64);
  EXPECT_EQ(boundary_edges(closed.mesh), 64);  // the top rim only: the plate closes the outlet
  expect_faces_towards(closed.mesh, inside);
  const std::size_t first_plate = closed.mesh.triangles.size() - 64;
  for (std::size_t t = first_plate; t < closed.mesh.triangles.size(); ++t)
    EXPECT_NEAR(dot(triangle_normal(closed.mesh, t), hopper.axis), 1, kRoundOff);
}

TEST(WallMeshes, SiloBinConeAndFlatBottom) {
  SiloWall silo;
  silo.base = {0.3, 0, -0.05};
  silo.axis = {0, 0, 1};
  silo.radius = 0.05;
  silo.height = 0.15;
  silo.cone_height = 0.04;
  silo.outlet_radius = 0.012;
  silo.segments = 32;
  const int n = 32;
  const double bin = frustum_side_area(0.05, 0.05, 0.15, n);
  const double cone = frustum_side_area(0.012, 0.05, 0.04, n);
  const double plate = polygon_area(0.012, n);
  const Vec3d inside = silo.base + silo.axis * 0.1;

  const WallMesh coned = make_wall_mesh(wall_spec(WallKind::silo, silo));
  EXPECT_NEAR(mesh_area(coned.mesh), bin + cone, bin * kAreaRelTol);
  EXPECT_EQ(boundary_edges(coned.mesh), 2 * n);  // the cone meets the bin on shared vertices
  expect_faces_towards(coned.mesh, inside);
  expect_faces_towards(coned.mesh, silo.base + silo.axis * 0.005);  // inside the cone, low

  silo.cone_height = 0;
  silo.outlet.closed = true;
  const WallMesh flat = make_wall_mesh(wall_spec(WallKind::silo, silo));
  const double annulus = polygon_area(0.05, n) - plate;
  EXPECT_NEAR(mesh_area(flat.mesh), bin + annulus + plate, bin * kAreaRelTol);
  EXPECT_EQ(flat.plate_triangles, n);
  EXPECT_EQ(boundary_edges(flat.mesh), n);
  expect_faces_towards(flat.mesh, inside);
  for (const Vec3d& p : flat.mesh.vertices) EXPECT_GE(p.z, silo.base.z - kRoundOff);
}

TEST(WallMeshes, MeshWallIsScaledRotatedAndTranslated) {
  MeshWall mesh;
  mesh.mesh.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  mesh.mesh.triangles = {{0, 1, 2}};
  mesh.scale = 0.5;
  mesh.rotation = Quatd::from_axis_angle(Vec3d(0, 1, 0), M_PI / 2);  // x -> -z, z -> x
  mesh.translation = {1, 2, 3};
  const WallMesh wall = make_wall_mesh(wall_spec(WallKind::mesh, mesh));
  // By hand: scale, then the quarter turn about y (x, y, z) -> (z, y, -x), then the shift.
  const Vec3d expected[] = {{1, 2, 3}, {1, 2, 2}, {1, 2.5, 3}};
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(norm(wall.mesh.vertices[k] - expected[k]), 0, kRoundOff) << "vertex " << k;
  EXPECT_NEAR(mesh_area(wall.mesh), 0.25 * 1, kRoundOff);  // scale^2 times the file's area
  EXPECT_NEAR(norm(triangle_normal(wall.mesh, 0) - Vec3d(1, 0, 0)), 0, kRoundOff);  // z turned
}

TEST(WallMeshes, EveryDocumentedWallLoadsAndFacesItsInside) {
  const std::string dir = scene_data_dir() + "/walls";
  // A point on the particles' side of every triangle of each documented example.
  const std::vector<std::pair<std::string, Vec3d>> walls = {
      {"plane", {0, 0, 0.1}}, {"box", {0, 0, 0.1}},      {"cylinder", {0, 0, 0.1}},
      {"drum", {0, 0, 0.02}}, {"hopper", {0, 0, -0.05}}, {"silo", {0, 0, 0.05}},
      {"mesh", {0, 0, 0}}};
  for (const auto& [kind, inside] : walls) {
    SCOPED_TRACE(kind);
    const Scene scene = parse_scene(
        read_text_file(dir + "/preamble.yaml") + read_text_file(dir + "/" + kind + ".yaml"),
        kind + ".yaml", dir);
    const std::vector<WallMesh> meshes = make_wall_meshes(scene);
    ASSERT_EQ(meshes.size(), 1u);
    EXPECT_FALSE(meshes[0].mesh.triangles.empty());
    expect_faces_towards(meshes[0].mesh, inside);
    EXPECT_EQ(meshes[0].plate_triangles, kind == "hopper" ? 64 : 0);     // the closed funnel
    EXPECT_EQ(outlet_closed_at(scene.walls[0], 0.2), kind == "hopper");  // opens at 0.25 s
    EXPECT_FALSE(outlet_closed_at(scene.walls[0], 0.25));
  }
}

}  // namespace
}  // namespace talus
