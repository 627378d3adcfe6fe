// Templates of dense point sets (issue 17): a 10,002-vertex UV sphere, 2,000 random points on a
// sphere and a 10,000-vertex cylinder, at the default tolerance and at the mesh files' coarser one
// (where neighbouring points lie closer to each other's planes than the tolerance).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "solver/shape/builtins.hpp"
#include "solver/shape/hull.hpp"
#include "solver/shape/mesh_io.hpp"
#include "solver/shape/template_builder.hpp"

namespace talus {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string temp_path(const std::string& name) {
  return testing::TempDir() + "talus_dense_" + std::to_string(::getpid()) + "_" + name;
}

// Unit-radius UV sphere: two poles and `rings` latitude rings of `segments` points, with its own
// outward triangulation (quads split in two, fans at the poles).
TriangleMesh uv_sphere(int rings, int segments) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 1}, {0, 0, -1}};
  for (int i = 1; i <= rings; ++i) {
    const double polar = kPi * i / (rings + 1);
    for (int j = 0; j < segments; ++j) {
      const double azimuth = 2 * kPi * j / segments;
      mesh.vertices.push_back({std::sin(polar) * std::cos(azimuth),
                               std::sin(polar) * std::sin(azimuth), std::cos(polar)});
    }
  }
  const auto at = [&](int ring, int j) { return 2 + (ring - 1) * segments + j % segments; };
  for (int j = 0; j < segments; ++j) {
    mesh.triangles.push_back({0, at(1, j), at(1, j + 1)});
    mesh.triangles.push_back({1, at(rings, j + 1), at(rings, j)});
  }
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return mesh;
}

std::vector<Vec3d> random_on_sphere(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  std::vector<Vec3d> points;
  for (int i = 0; i < n; ++i) {
    const Vec3d d{gauss(rng), gauss(rng), gauss(rng)};
    points.push_back(d / norm(d));
  }
  return points;
}

// How far the farthest input point lies outside the farthest face plane (<= 0: all inside).
double worst_outside(const std::vector<Vec3d>& points, const ShapeTemplate& shape) {
  double worst = -1e300;
  for (const Vec3d& p : points) {
    const Vec3d body = rotate_inverse(shape.body_to_input, p - shape.input_centroid);
    for (const Face& face : shape.faces)
      worst = std::max(worst, dot(face.normal, body) - face.offset);
  }
  return worst;
}

// Convexity: how far the worst template vertex lies outside a face plane.
double worst_fold(const ShapeTemplate& shape) {
  double worst = -1e300;
  for (const Vec3d& v : shape.vertices)
    for (const Face& face : shape.faces) worst = std::max(worst, dot(face.normal, v) - face.offset);
  return worst;
}

// Every face's loop vertices lie on its plane within tol (the faces are planar).
double worst_off_plane(const ShapeTemplate& shape) {
  double worst = 0;
  for (const Face& face : shape.faces)
    for (int v : face.loop)
      worst = std::max(worst, std::abs(dot(face.normal, shape.vertices[v]) - face.offset));
  return worst;
}

}  // namespace

// At the default tolerance (1e-10 of the extent) every point of the UV sphere is a corner and
// each quad between two rings (an isosceles trapezoid, planar up to round-off) is one face.
// Before the hull decided visibility at that tolerance only, this set was refused.
TEST(DenseHulls, UvSphereOf10002VerticesKeepsEveryVertexAndMergesEachQuad) {
  const TriangleMesh mesh = uv_sphere(100, 100);
  ASSERT_EQ(mesh.vertices.size(), 10002u);
  const ShapeTemplate shape = make_template("uv", mesh.vertices);
  EXPECT_EQ(shape.vertices.size(), 10002u);
  EXPECT_EQ(shape.faces.size(), 99u * 100 + 2 * 100);  // quads between rings, triangles at poles
  // The mesh's own triangulation gives the same polyhedron independently of the hull: volume
  // and moments agree to round-off of sums of 20,000 terms (1e-12 relative).
  const MassProperties exact = mass_properties(mesh.vertices, mesh.triangles);
  EXPECT_NEAR(shape.volume, exact.volume, 1e-12 * exact.volume);
  const SymmetricEigen moments = symmetric_eigen(exact.inertia);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(shape.principal_moments[k], moments.values[k], 1e-12 * moments.values[k]);
  // ... and it is 0.09 % smaller than the sphere it is inscribed in (a loose sanity bound).
  EXPECT_NEAR(shape.volume / (4 * kPi / 3), 1, 1.5e-3);
  // Faces planar, surface convex and every point inside, to a few round-offs of a unit sphere
  // (1e-14; the tolerance 2e-10 would hide a fold of that size).
  EXPECT_LE(worst_off_plane(shape), 1e-14);
  EXPECT_LE(worst_fold(shape), 1e-14);
  EXPECT_LE(worst_outside(mesh.vertices, shape), 1e-14);
}

// Through a mesh file the tolerance is 1e-6 of the extent (2e-6 here), and the quads near the poles
// are thinner than that: points there lie within the tolerance of their neighbours' planes, so
// some merge. The template must still be convex, hold every point and keep the volume.
TEST(DenseHulls, UvSphereOf10002VerticesLoadsFromAnObjFile) {
  const TriangleMesh mesh = uv_sphere(100, 100);
  const std::string path = temp_path("uv_sphere.obj");
  write_obj(path, mesh);
  testing::internal::CaptureStderr();
  const ShapeTemplate shape = load_shape_file(path);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");  // a convex mesh: no warning
  const double tol = hull_tolerance(mesh.vertices, kMeshFileRelTol);
  EXPECT_LE(shape.vertices.size(), 10002u);
  EXPECT_GE(shape.vertices.size(), 9000u);
  // Moving faces by at most tol changes the volume by at most tol times the area (4 pi):
  // relative 3 tol = 6e-6.
  const double exact = mass_properties(mesh.vertices, mesh.triangles).volume;
  EXPECT_NEAR(shape.volume, exact, 4 * kPi * tol);
  // A merged face's corners lie within tol of its seed triangle's plane; the template refits the
  // plane (Newell normal, offset through the outermost corner), so they lie within 2 tol of that.
  // Every point lies within 2 tol too: a dropped point is within tol of its own facet, and that
  // facet's corners within tol of the face the rebuilt hull puts there (one rebuild is made for
  // this set; convex_hull allows 1 + kCornerPasses tolerances in general).
  EXPECT_LE(worst_off_plane(shape), 2 * tol);
  EXPECT_LE(worst_fold(shape), 2 * tol);
  EXPECT_LE(worst_outside(mesh.vertices, shape), 2 * tol);
  std::remove(path.c_str());
}

// Random points are the hardest case for the coarse tolerance: some pairs lie 1e-5 apart, so
// that a point is within the tolerance of many neighbouring planes at once.
TEST(DenseHulls, TwoThousandRandomPointsOnASphereAtBothTolerances) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<Vec3d> points = random_on_sphere(2000, seed);
    // Default tolerance: every point a corner, triangulated (F = 2V - 4).
    const ShapeTemplate fine = make_template("random", points);
    EXPECT_EQ(fine.vertices.size(), 2000u) << "seed " << seed;
    EXPECT_EQ(fine.faces.size(), 3996u) << "seed " << seed;
    EXPECT_LE(worst_fold(fine), 1e-14) << "seed " << seed;
    EXPECT_LE(worst_outside(points, fine), 1e-14) << "seed " << seed;
    // Mesh-file tolerance: neighbouring triangles within it of one plane merge into quads (fewer
    // faces); a point is dropped only where it lies within it of a face through its neighbours,
    // rare at this density (closest pairs ~2e-3 apart bulge by ~5e-7). Volume within tol x area.
    const ShapeTemplate coarse = make_template("random", points, kMeshFileRelTol);
    const double tol = hull_tolerance(points, kMeshFileRelTol);
    EXPECT_LT(coarse.faces.size(), 3996u) << "seed " << seed;
    EXPECT_GE(coarse.vertices.size(), 1990u) << "seed " << seed;
    EXPECT_NEAR(coarse.volume, fine.volume, 4 * kPi * tol) << "seed " << seed;
    EXPECT_LE(worst_off_plane(coarse), 2 * tol) << "seed " << seed;  // as for the UV sphere
    EXPECT_LE(worst_fold(coarse), 2 * tol) << "seed " << seed;
    EXPECT_LE(worst_outside(points, coarse), 2 * tol) << "seed " << seed;
  }
}

// `cylinder:D,L,N` with N = 5000 (10,000 rim vertices): this hung (quadratic rescans, and a
// triangulation that refined one rim far ahead of the other).
TEST(DenseHulls, CylinderOfTenThousandVerticesIsTheExactPrism) {
  const double diameter = 8e-3, length = 5.3e-3, r = diameter / 2;
  const int n = 5000;
  const ShapeTemplate shape = make_builtin("cylinder:0.008,0.0053,5000");
  EXPECT_EQ(shape.vertices.size(), 10000u);
  EXPECT_EQ(shape.faces.size(), 5002u);  // 5000 side rectangles + 2 caps
  EXPECT_EQ(shape.edges.size(), 15000u);
  // Regular N-gon prism (see Cylinder.PaperTableOne...): exact closed forms; the sums over 10^4
  // faces agree to 1e-10 relative (the moments lose a few digits to the parallel-axis shift).
  const double theta = 2 * kPi / n;
  const double area = n * r * r * std::sin(theta) / 2;
  const double polar = n * std::pow(r, 4) * std::sin(theta) * (2 + std::cos(theta)) / 12;
  EXPECT_NEAR(shape.volume, area * length, 1e-10 * area * length);
  const double i_transverse = polar * length / 2 + area * std::pow(length, 3) / 12;
  EXPECT_NEAR(shape.principal_moments.x, i_transverse, 1e-10 * i_transverse);
  EXPECT_NEAR(shape.principal_moments.y, i_transverse, 1e-10 * i_transverse);
  EXPECT_NEAR(shape.principal_moments.z, polar * length, 1e-10 * polar * length);
  // Round-off of an 8 mm body: 1e-17 m is 1e-15 relative.
  EXPECT_LE(worst_fold(shape), 1e-17);
  EXPECT_LE(worst_off_plane(shape), 1e-17);
}

// The same cylinder from a binary STL: at 1e-6 of the extent (8e-9 m) each rim point lies within
// the tolerance of its neighbours' side planes (sagitta r theta^2 = 6.3e-9 m), so side faces merge
// in runs and the rim keeps fewer corners; the volume stays within tol x area.
TEST(DenseHulls, CylinderOfTenThousandVerticesLoadsFromABinaryStl) {
  const TriangleMesh mesh = cylinder_mesh(8e-3, 5.3e-3, 5000);
  const std::string path = temp_path("cylinder.stl");
  write_stl(path, mesh, true);
  testing::internal::CaptureStderr();
  const ShapeTemplate shape = load_shape_file(path);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  const TriangleMesh stored = read_stl(path);  // the float-rounded points
  const double tol = hull_tolerance(stored.vertices, kMeshFileRelTol);
  EXPECT_LT(shape.vertices.size(), 10000u);
  EXPECT_GT(shape.vertices.size(), 2000u);
  EXPECT_EQ(shape.faces.size(), shape.vertices.size() / 2 + 2);  // still a prism
  const double r = 4e-3, surface = 2 * kPi * r * (r + 5.3e-3);
  const double exact = mass_properties(stored.vertices, stored.triangles).volume;
  EXPECT_NEAR(shape.volume, exact, surface * tol);
  EXPECT_LE(worst_off_plane(shape), 2 * tol);  // as for the UV sphere from a file
  EXPECT_LE(worst_fold(shape), 2 * tol);
  EXPECT_LE(worst_outside(stored.vertices, shape), 2 * tol);
  std::remove(path.c_str());
}

// Past kMaxTemplatePoints the build is refused at once, naming the count and the limit (the caller
// names the shape: load_shape_file puts the file first), rather than left to run for minutes; one
// point fewer is not refused for its size (here: for its flatness).
TEST(DenseHulls, CloudsAboveTheLimitAreRefusedNamingTheLimit) {
  std::vector<Vec3d> points(kMaxTemplatePoints + 1, Vec3d{1, 2, 3});
  try {
    make_template("huge.stl", points);
    ADD_FAILURE() << "built a template of " << points.size() << " points";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "250001 points; a template is built from at most 250000");
  }
  points.pop_back();
  try {
    make_template("huge.stl", points);
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("coincide"), std::string::npos) << e.what();
  }
}

}  // namespace talus
