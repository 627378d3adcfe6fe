// BLAZE-DEM simple contact (solver/geometry/simple_contact.hpp): closed forms for spheres and
// sphere–cube features; polyhedron–polyhedron SAT against closed forms, an exact brute-force
// Minkowski-difference oracle and a sampled-direction oracle; antisymmetry; degenerate input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "solver/geometry/simple_contact.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "tests/geometry/test_shapes_local.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using test_local::LocalShape;
using test_local::make_box;
using test_local::make_cube;

const double kPi = 3.14159265358979323846;

// Closed forms in double on numbers of order one: a handful of rounded operations each, so
// 1e-14 (about 50 eps) is round-off with margin, and far below any modelling error.
const double kTight = 1e-14;

void expect_vec_near(const Vec3d& got, const Vec3d& want, double tol, const char* what) {
  EXPECT_NEAR(got.x, want.x, tol) << what;
  EXPECT_NEAR(got.y, want.y, tol) << what;
  EXPECT_NEAR(got.z, want.z, tol) << what;
}

bool all_finite(const SimpleContact<double>& c) {
  return std::isfinite(c.depth) && std::isfinite(c.normal.x) && std::isfinite(c.normal.y) &&
         std::isfinite(c.normal.z) && std::isfinite(c.point.x) && std::isfinite(c.point.y) &&
         std::isfinite(c.point.z);
}

Quatd rotation_between(const Vec3d& from, const Vec3d& to) {
  const Vec3d axis = cross(from, to);
  return Quatd::from_axis_angle(axis / norm(axis), std::acos(dot(from, to)));
}

Vec3d to_world(const Posed& pose, const Vec3d& body) {
  return pose.position + rotate(pose.orientation, body);
}

TEST(SimpleContact, SphereSphere_ClosedForms) {
  const Vec3d a{0.1, 0.2, 0.3}, dir = Vec3d{2, -1, 2} / 3.0;
  const SimpleContact<double> c = sphere_sphere_contact(a, 0.5, a + dir * 0.8, 0.4);
  EXPECT_TRUE(c.touching);
  EXPECT_NEAR(c.depth, 0.1, kTight);
  expect_vec_near(c.normal, dir, kTight, "normal");
  expect_vec_near(c.point, a + dir * 0.45, kTight, "point: middle of the overlap");
  const SimpleContact<double> back = sphere_sphere_contact(a + dir * 0.8, 0.4, a, 0.5);
  expect_vec_near(back.normal, -dir, kTight, "normal(B, A) = -normal(A, B)");
  expect_vec_near(back.point, c.point, kTight, "same point");

  const SimpleContact<double> apart = sphere_sphere_contact(a, 0.5, a + dir * 0.95, 0.4);
  EXPECT_FALSE(apart.touching);
  EXPECT_EQ(apart.depth, 0.0);
  // Coincident centres: any unit normal, finite everything, depth = r_a + r_b.
  const SimpleContact<double> same = sphere_sphere_contact(a, 0.5, a, 0.4);
  EXPECT_TRUE(same.touching);
  EXPECT_NEAR(same.depth, 0.9, kTight);
  EXPECT_NEAR(norm(same.normal), 1.0, kTight);
  EXPECT_TRUE(all_finite(same));
}

// A posed cube and spheres against its face, edge and corner, and with its centre inside.
TEST(SimpleContact, SphereCube_FaceEdgeCornerInside) {
  const double s = 0.2, r = 0.05, delta = 0.01;
  const auto cube = make_cube<double>(s);
  const Vec3d axis = Vec3d{1, 2, -0.5} / norm(Vec3d{1, 2, -0.5});
  const Posed pose{{0.5, -0.3, 0.1}, Quatd::from_axis_angle(axis, 0.8)};
  struct Case {
    const char* name;
    Vec3d surface_point, outward;  // body frame: nearest surface point, unit direction to centre
  };
  const double h = s / 2;
  const Case cases[] = {{"face", {0.02, -0.03, h}, {0, 0, 1}},
                        {"edge", {h, 0.03, h}, Vec3d{1, 0, 1} / std::sqrt(2.0)},
                        {"corner", {h, h, h}, Vec3d{1, 1, 1} / std::sqrt(3.0)}};
  for (const Case& k : cases) {
    const Vec3d center = k.surface_point + k.outward * (r - delta);
    const SimpleContact<double> c =
        sphere_polyhedron_contact(to_world(pose, center), r, cube.view(), pose);
    EXPECT_TRUE(c.touching) << k.name;
    EXPECT_NEAR(c.depth, delta, kTight) << k.name;
    expect_vec_near(c.normal, rotate(pose.orientation, -k.outward), kTight, k.name);
    // Halfway between the surface point and the sphere's deepest point.
    expect_vec_near(c.point, to_world(pose, k.surface_point - k.outward * (delta / 2)), kTight,
                    k.name);
    const SimpleContact<double> back =
        polyhedron_sphere_contact(cube.view(), pose, to_world(pose, center), r);
    expect_vec_near(back.normal, -c.normal, 0.0, k.name);
    // Just apart along the same direction.
    const SimpleContact<double> apart = sphere_polyhedron_contact(
        to_world(pose, k.surface_point + k.outward * (r + delta)), r, cube.view(), pose);
    EXPECT_FALSE(apart.touching) << k.name;
    EXPECT_EQ(apart.depth, 0.0) << k.name;
  }
  // Centre inside, nearest the +z face (0.1 s away; the others 0.4 s and more).
  const Vec3d inside{0.1 * s, 0.05 * s, 0.4 * s};
  const SimpleContact<double> c =
      sphere_polyhedron_contact(to_world(pose, inside), r, cube.view(), pose);
  EXPECT_TRUE(c.touching);
  EXPECT_NEAR(c.depth, r + 0.1 * s, kTight);
  expect_vec_near(c.normal, rotate(pose.orientation, Vec3d{0, 0, -1}), kTight, "inside normal");
  const Vec3d foot{0.1 * s, 0.05 * s, h}, deepest = inside - Vec3d{0, 0, r};
  expect_vec_near(c.point, to_world(pose, (foot + deepest) / 2.0), kTight, "inside point");
  // Centre exactly on a face: depth r, normal into the cube, finite.
  const SimpleContact<double> on =
      sphere_polyhedron_contact(to_world(pose, {0.01, 0.02, h}), r, cube.view(), pose);
  EXPECT_NEAR(on.depth, r, kTight);
  expect_vec_near(on.normal, rotate(pose.orientation, Vec3d{0, 0, -1}), kTight, "on face");
}

// ---- Polyhedron–polyhedron ----

std::vector<Vec3d> world_vertices(const LocalShape<double>& shape, const Posed& pose) {
  std::vector<Vec3d> out;
  for (const Vec3d& v : shape.vertices) out.push_back(to_world(pose, v));
  return out;
}

// Overlap of the projections along unit L, oriented: max_A - min_B (B on A's +L side).
double overlap_along(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b, const Vec3d& l) {
  double max_a = -1e300, min_b = 1e300;
  for (const Vec3d& p : a) max_a = std::max(max_a, dot(p, l));
  for (const Vec3d& p : b) min_b = std::min(min_b, dot(p, l));
  return max_a - min_b;
}

// Exact penetration depth by brute force: the Minkowski difference A - B is the hull of all
// vertex differences; every triple of them whose plane leaves all points on one side spans a
// facet plane; the depth is the least distance from the origin to a facet plane (negative when
// the origin is outside, i.e. the bodies are apart). Independent of the SAT's axis enumeration.
double exact_depth(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b) {
  std::vector<Vec3d> md;
  for (const Vec3d& p : a)
    for (const Vec3d& q : b) md.push_back(p - q);
  double scale = 0;
  for (const Vec3d& p : md) scale = std::max(scale, norm(p));
  const size_t n = md.size();
  double depth = 1e300;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t k = j + 1; k < n; ++k) {
        Vec3d normal = cross(md[j] - md[i], md[k] - md[i]);
        const double length = norm(normal);
        if (length < 1e-9 * scale * scale) continue;  // (nearly) collinear triple
        normal = normal / length;
        int above = 0, below = 0;
        for (const Vec3d& p : md) {
          const double s = dot(normal, p - md[i]);
          above += s > 1e-12 * scale;
          below += s < -1e-12 * scale;
        }
        if (above > 0 && below > 0) continue;
        if (above > 0) normal = -normal;  // outward
        depth = std::min(depth, dot(normal, md[i]));
      }
  return depth;
}

// Directions on a k x k grid on each face of the cube, projected to the unit sphere: every unit
// vector is within chord sqrt(2) / k of one of them (see below).
std::vector<Vec3d> grid_directions(int k) {
  std::vector<Vec3d> directions;
  for (int face = 0; face < 6; ++face)
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        const double u = -1 + (i + 0.5) * 2.0 / k, v = -1 + (j + 0.5) * 2.0 / k;
        const double sign = face % 2 ? -1 : 1;
        const Vec3d p = face / 2 == 0   ? Vec3d{sign, u, v}
                        : face / 2 == 1 ? Vec3d{u, sign, v}
                                        : Vec3d{u, v, sign};
        directions.push_back(p / norm(p));
      }
  return directions;
}

TEST(SimpleContact, CubeOnCube_FaceToFaceExact) {
  const double s = 1.0, h = 0.05;
  const auto cube = make_cube<double>(s);
  // Axis aligned, B offset laterally: depth h, normal +z, point at the common patch's centre.
  const Posed a{{0, 0, 0}, Quatd()}, b{{0.3, -0.2, s - h}, Quatd()};
  const SimpleContact<double> c = polyhedron_polyhedron_contact(cube.view(), a, cube.view(), b);
  EXPECT_TRUE(c.touching);
  EXPECT_NEAR(c.depth, h, 4 * Eps<double>::value);  // s - (s - h): one rounding
  expect_vec_near(c.normal, {0, 0, 1}, 0.0, "normal");
  expect_vec_near(c.point, {0.15, -0.1, s / 2 - h / 2}, kTight, "patch centre");

  // Both posed by a common rotation, B also yawed about the shared normal: still face to face.
  const Vec3d axis = Vec3d{0.3, -1, 0.6} / norm(Vec3d{0.3, -1, 0.6});
  const Quatd q = Quatd::from_axis_angle(axis, 1.2);
  const Posed ra{{0.4, 0.1, -0.2}, q};
  const Posed rb{to_world(ra, {0.1, 0.05, s - h}), q * Quatd::from_axis_angle({0, 0, 1}, 0.5)};
  const SimpleContact<double> d = polyhedron_polyhedron_contact(cube.view(), ra, cube.view(), rb);
  EXPECT_NEAR(d.depth, h, kTight);
  expect_vec_near(d.normal, rotate(q, Vec3d{0, 0, 1}), kTight, "rotated normal");
  const SimpleContact<double> back =
      polyhedron_polyhedron_contact(cube.view(), rb, cube.view(), ra);
  expect_vec_near(back.normal, -d.normal, kTight, "antisymmetric");
  EXPECT_NEAR(back.depth, d.depth, kTight);
}

TEST(SimpleContact, ContactPoints_VertexFaceEdgeEdgeSmallOnLarge) {
  const double h = 0.02;
  const auto slab = make_box<double>(1, 1, 0.2);
  const auto cube = make_cube<double>(0.2);
  const Posed origin{{0, 0, 0}, Quatd()};
  // Small face on a large one: the small face's centre.
  const SimpleContact<double> small = polyhedron_polyhedron_contact(
      slab.view(), origin, cube.view(), Posed{{0.3, -0.4, 0.3 - h}, Quatd()});
  EXPECT_NEAR(small.depth, h, kTight);
  expect_vec_near(small.point, {0.3, -0.4, 0.2 - h / 2}, kTight, "small on large");
  // Corner down onto the slab: the corner, halfway into the overlap.
  const Quatd corner_down = rotation_between(Vec3d{-1, -1, -1} / std::sqrt(3.0), {0, 0, -1});
  const double half_diagonal = 0.1 * std::sqrt(3.0);
  const SimpleContact<double> vertex = polyhedron_polyhedron_contact(
      slab.view(), origin, cube.view(), Posed{{0.3, -0.1, 0.2 + half_diagonal - h}, corner_down});
  EXPECT_NEAR(vertex.depth, h, kTight);
  expect_vec_near(vertex.normal, {0, 0, 1}, kTight, "vertex-face normal");
  expect_vec_near(vertex.point, {0.3, -0.1, 0.2 - h / 2}, kTight, "vertex-face point");
  // Crossed edges: A rolled 45 degrees about x (top edge along x at z = s / sqrt2), B rolled 45
  // degrees about y (bottom edge along y at x = x0): they cross at (x0, 0).
  const double s = 1.0, x0 = 0.1, lift = s / std::sqrt(2.0);
  const auto unit_cube = make_cube<double>(s);
  const Posed ea{{0, 0, 0}, Quatd::from_axis_angle({1, 0, 0}, kPi / 4)};
  const Posed eb{{x0, 0, 2 * lift - h}, Quatd::from_axis_angle({0, 1, 0}, kPi / 4)};
  const SimpleContact<double> edge =
      polyhedron_polyhedron_contact(unit_cube.view(), ea, unit_cube.view(), eb);
  EXPECT_NEAR(edge.depth, h, kTight);
  expect_vec_near(edge.normal, {0, 0, 1}, kTight, "edge-edge normal");
  expect_vec_near(edge.point, {x0, 0, lift - h / 2}, kTight, "edge-edge point");
  const double exact = exact_depth(world_vertices(unit_cube, ea), world_vertices(unit_cube, eb));
  EXPECT_NEAR(exact, h, kTight);  // the closed form is the true minimum translation distance
}

// Random pairs of cubes, boxes and tetrahedra against two oracles.
//  1. Exact (brute-force Minkowski-difference hull): |SAT - exact| <= 1e-12 (round-off of
//     unit-size coordinates through a few dozen operations, with margin), and "touching" agrees.
//  2. Sampled directions (what the SAT is a shortcut for): f(L) = min over the two orientations
//     of the projection-interval overlap, sampled on a k x k grid on each face of the cube,
//     projected to the sphere. The SAT depth must be <= the sampled minimum (it is the true
//     minimum over all directions) and within M rho of it: f is M-Lipschitz in the chord distance
//     with M = max |x| over the Minkowski difference, and every direction has a sample within
//     chord rho <= sqrt(2) / k (half a grid cell's diagonal on the face z = 1; radial projection
//     of points outside the unit ball onto the sphere does not increase distances).
TEST(SimpleContact, RandomPolyhedra_AgainstBruteForceOracles) {
  std::mt19937_64 rng(314159);
  const LocalShape<double> shapes[] = {make_cube<double>(1.0), make_box<double>(0.6, 0.4, 0.25),
                                       test_local::make_tetrahedron<double>(1.4)};
  std::uniform_real_distribution<double> unit(0, 1);
  const int k = 120;
  const std::vector<Vec3d> directions = grid_directions(k);
  const double rho = std::sqrt(2.0) / k;
  int touching = 0, apart = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const LocalShape<double>& sa = shapes[trial % 3];
    const LocalShape<double>& sb = shapes[(trial / 3) % 3];
    const double reach = sa.bounding_radius + sb.bounding_radius;
    Vec3d dir{unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5};
    dir = dir / norm(dir);
    const Posed pa{{0.2, -0.1, 0.3}, random_rotation(rng)};
    const Posed pb{pa.position + dir * (reach * (0.3 + 0.6 * unit(rng))), random_rotation(rng)};
    const auto wa = world_vertices(sa, pa), wb = world_vertices(sb, pb);
    const double exact = exact_depth(wa, wb);
    const SimpleContact<double> c = polyhedron_polyhedron_contact(sa.view(), pa, sb.view(), pb);
    if (std::abs(exact) < 1e-9) continue;  // grazing: either answer is right
    ASSERT_EQ(c.touching, exact > 0) << "trial " << trial << " exact " << exact;
    const SimpleContact<double> back = polyhedron_polyhedron_contact(sb.view(), pb, sa.view(), pa);
    EXPECT_EQ(back.touching, c.touching);
    if (!c.touching) {
      ++apart;
      continue;
    }
    ++touching;
    EXPECT_NEAR(c.depth, exact, 1e-12) << "trial " << trial;
    // The returned normal realises the depth: the overlap along it equals the depth.
    EXPECT_NEAR(overlap_along(wa, wb, c.normal), c.depth, 1e-12) << "trial " << trial;
    EXPECT_NEAR(norm(c.normal), 1.0, 1e-14);
    // Antisymmetry, and the same point from either side.
    EXPECT_NEAR(back.depth, c.depth, 1e-12);
    expect_vec_near(back.normal, -c.normal, 1e-12, "normal(B, A) = -normal(A, B)");
    expect_vec_near(back.point, c.point, 1e-12, "point(B, A) = point(A, B)");

    double sampled = 1e300, lipschitz = 0;
    for (const Vec3d& l : directions) {
      sampled = std::min(sampled, std::min(overlap_along(wa, wb, l), overlap_along(wb, wa, l)));
    }
    for (const Vec3d& p : wa)
      for (const Vec3d& q : wb) lipschitz = std::max(lipschitz, norm(p - q));
    EXPECT_LE(c.depth, sampled + 1e-12) << "trial " << trial;
    EXPECT_LE(sampled - c.depth, lipschitz * rho) << "trial " << trial;
  }
  EXPECT_GT(touching, 15);  // both branches exercised
  EXPECT_GT(apart, 5);
}

// Built-in shapes with many edges (dodecahedron: 30, mineral: 48), through the production
// template pipeline, against the sampled-direction oracle (the exact hull oracle would need
// 400^3 triples); the tolerance argument is the one of RandomPolyhedra_AgainstBruteForceOracles.
TEST(SimpleContact, BuiltinPolyhedra_AgainstSampledOracle) {
  std::mt19937_64 rng(2718);
  const char* specs[] = {"dodecahedron:0.01", "icosahedron:0.012", "mineral:0.01", "corn:0.01"};
  const int k = 100;
  const std::vector<Vec3d> directions = grid_directions(k);
  const double rho = std::sqrt(2.0) / k;
  std::uniform_real_distribution<double> unit(0, 1);
  int touching = 0;
  for (int trial = 0; trial < 16; ++trial) {
    const ShapeTemplate ta = make_builtin(specs[trial % 4]), tb = make_builtin(specs[trial / 4]);
    const ShapeArrays<double> sa(ta), sb(tb);
    const double reach = ta.bounding_radius + tb.bounding_radius;
    Vec3d dir{unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5};
    dir = dir / norm(dir);
    const Posed pa{{0.02, -0.01, 0.03}, random_rotation(rng)};
    const Posed pb{pa.position + dir * (reach * (0.3 + 0.4 * unit(rng))), random_rotation(rng)};
    std::vector<Vec3d> wa, wb;
    for (const Vec3d& v : ta.vertices) wa.push_back(to_world(pa, v));
    for (const Vec3d& v : tb.vertices) wb.push_back(to_world(pb, v));
    const SimpleContact<double> c = polyhedron_polyhedron_contact(sa.view(), pa, sb.view(), pb);
    double sampled = 1e300, lipschitz = 0;
    for (const Vec3d& l : directions) {
      sampled = std::min(sampled, std::min(overlap_along(wa, wb, l), overlap_along(wb, wa, l)));
    }
    for (const Vec3d& p : wa)
      for (const Vec3d& q : wb) lipschitz = std::max(lipschitz, norm(p - q));
    if (sampled < 0) {  // a sampled separating direction proves the bodies apart
      EXPECT_FALSE(c.touching) << "trial " << trial;
      continue;
    }
    ASSERT_TRUE(c.touching) << "trial " << trial;
    ++touching;
    // Round-off of 1 cm coordinates: 1e-15 m is ~50 eps of them.
    EXPECT_LE(c.depth, sampled + 1e-15) << "trial " << trial;
    EXPECT_LE(sampled - c.depth, lipschitz * rho) << "trial " << trial;
    EXPECT_NEAR(overlap_along(wa, wb, c.normal), c.depth, 1e-15) << "trial " << trial;
    const SimpleContact<double> back = polyhedron_polyhedron_contact(sb.view(), pb, sa.view(), pa);
    EXPECT_NEAR(back.depth, c.depth, 1e-15);
    expect_vec_near(back.normal, -c.normal, 1e-12, "normal(B, A) = -normal(A, B)");
  }
  EXPECT_GT(touching, 8);
}

// Stacked cubes with B turned by a tiny angle: edge pairs at angles below sqrt(eps) ~ 1.5e-8 are
// skipped, which may overestimate the depth by O(angle x edge length) (the sliver face of the
// Minkowski difference they span); above it they are kept and the result is exact.
TEST(SimpleContact, NearlyParallelEdges_StableAndNearExact) {
  const auto cube = make_cube<double>(1.0);
  const Vec3d axis = Vec3d{0.3, 0.5, 0.8} / norm(Vec3d{0.3, 0.5, 0.8});
  const Posed a{{0, 0, 0}, Quatd()};
  for (double angle : {0.0, 1e-14, 1e-11, 1e-9, 1e-7, 1e-5, 1e-3}) {
    const Posed b{{0.2, 0.1, 1 - 0.05}, Quatd::from_axis_angle(axis, angle)};
    const SimpleContact<double> c = polyhedron_polyhedron_contact(cube.view(), a, cube.view(), b);
    const double exact = exact_depth(world_vertices(cube, a), world_vertices(cube, b));
    ASSERT_TRUE(c.touching);
    EXPECT_TRUE(all_finite(c));
    EXPECT_LE(std::abs(c.depth - exact), 1e-12 + 4 * angle) << "angle " << angle;
    EXPECT_NEAR(c.normal.z, 1.0, 1e-12 + 4 * angle) << "angle " << angle;
  }
}

// Two equal cubes with equal overlaps along x and y: the tie is broken the same way from either
// side, although the face lists are enumerated in different world orders (B is turned 90 degrees).
TEST(SimpleContact, SymmetricTie_NormalStillAntisymmetric) {
  const auto cube = make_cube<double>(1.0);
  const double h = 0.1;
  const Posed a{{0, 0, 0}, Quatd()};
  const Posed b{{1 - h, 1 - h, 0}, Quatd::from_axis_angle({0, 0, 1}, kPi / 2)};
  const SimpleContact<double> ab = polyhedron_polyhedron_contact(cube.view(), a, cube.view(), b);
  const SimpleContact<double> ba = polyhedron_polyhedron_contact(cube.view(), b, cube.view(), a);
  EXPECT_NEAR(ab.depth, h, kTight);
  EXPECT_NEAR(ba.depth, h, kTight);
  expect_vec_near(ba.normal, -ab.normal, kTight, "antisymmetric under a tie");
  EXPECT_NEAR(std::abs(ab.normal.x) + std::abs(ab.normal.y), 1.0, kTight);  // x or y
}

TEST(SimpleContact, FloatMatchesDouble) {
  const auto cube_d = make_cube<double>(1.0);
  const auto cube_f = make_cube<float>(1.0);
  const Vec3d axis = Vec3d{0.3, -1, 0.6} / norm(Vec3d{0.3, -1, 0.6});
  const Posed a{{0.4, 0.1, -0.2}, Quatd::from_axis_angle(axis, 1.2)};
  const Posed b{to_world(a, {0.3, 0.25, 0.93}), Quatd::from_axis_angle({0.6, 0, 0.8}, 0.3)};
  const SimpleContact<double> d = polyhedron_polyhedron_contact(cube_d.view(), a, cube_d.view(), b);
  const SimpleContact<float> f = polyhedron_polyhedron_contact(
      cube_f.view(), Pose<float>{Vec3f(a.position), Quat<float>(a.orientation)}, cube_f.view(),
      Pose<float>{Vec3f(b.position), Quat<float>(b.orientation)});
  ASSERT_TRUE(d.touching);
  ASSERT_TRUE(f.touching);
  // Float round-off of unit-size coordinates through ~20 operations: 20 * 6e-8 ~ 1e-6; 1e-5 leaves
  // margin, and stays far below the depth itself (~0.1).
  EXPECT_NEAR(f.depth, d.depth, 1e-5);
  expect_vec_near(Vec3d(f.normal), d.normal, 1e-5, "float normal");
  const SimpleContact<float> sf =
      sphere_polyhedron_contact(Vec3f(to_world(a, {0.2, 0.1, 0.55})), 0.1f, cube_f.view(),
                                Pose<float>{Vec3f(a.position), Quat<float>(a.orientation)});
  EXPECT_NEAR(sf.depth, 0.05f, 1e-5f);
}

TEST(SimpleContact, NonFiniteInput_NotTouchingAndFinite) {
  const auto cube = make_cube<double>(1.0);
  const double nan = std::nan(""), inf = INFINITY;
  const Posed good{{0, 0, 0}, Quatd()};
  const SimpleContact<double> c[] = {
      sphere_sphere_contact<double>({nan, 0, 0}, 1.0, {0, 0, 0}, 1.0),
      sphere_sphere_contact<double>({0, 0, 0}, inf, {0, 0, 0}, 1.0),
      sphere_polyhedron_contact<double>({0, nan, 0}, 0.1, cube.view(), good),
      polyhedron_polyhedron_contact(cube.view(), good, cube.view(),
                                    Posed{{0.5, 0, 0}, Quatd(nan, 0, 0, 0)}),
      polyhedron_polyhedron_contact(cube.view(), Posed{{inf, 0, 0}, Quatd()}, cube.view(), good)};
  for (const SimpleContact<double>& r : c) {
    EXPECT_FALSE(r.touching);
    EXPECT_TRUE(all_finite(r));
  }
}

}  // namespace
}  // namespace talus
