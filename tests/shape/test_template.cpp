// Templates (paper §2.1): mass properties against closed forms, the body frame, merged faces, the
// built-in shapes and the flat arrays handed to the geometry code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/shape/template_builder.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Closed forms against computed sums of a few dozen terms: 1e-12 relative leaves ~4 orders of
// magnitude above double round-off and catches any wrong coefficient.
constexpr double kRel = 1e-12;

void expect_rel(double actual, double expected, double rel = kRel) {
  EXPECT_NEAR(actual, expected, rel * std::abs(expected))
      << "relative error " << (actual - expected) / expected;
}

struct Platonic {
  const char* name;
  int faces, vertices, edges, face_sides;
  double edge_per_radius;  // edge length / circumradius
  double volume_coeff;     // V / a^3
  double inertia_coeff;    // I / (V a^2), the same about every axis
};

const double s5 = std::sqrt(5.0);
const Platonic kPlatonic[] = {
    {"tetrahedron", 4, 4, 6, 3, 4 / std::sqrt(6.0), 1 / (6 * std::sqrt(2.0)), 1.0 / 20},
    {"cube", 6, 8, 12, 4, 2 / std::sqrt(3.0), 1, 1.0 / 6},
    {"octahedron", 8, 6, 12, 3, std::sqrt(2.0), std::sqrt(2.0) / 3, 1.0 / 10},
    {"dodecahedron", 12, 20, 30, 5, 4 / (std::sqrt(3.0) * (1 + s5)), (15 + 7 * s5) / 4,
     (95 + 39 * s5) / 300},
    {"icosahedron", 20, 12, 30, 3, 4 / std::sqrt(10 + 2 * s5), 5 * (3 + s5) / 12, (3 + s5) / 20},
};

// Faces unit and outward, loops planar, counter-clockwise from outside and made of true corners.
void expect_valid_faces(const ShapeTemplate& shape) {
  const double tol = 1e-12 * shape.bounding_radius;  // round-off of metre-scale coordinates
  for (const Face& face : shape.faces) {
    EXPECT_NEAR(norm(face.normal), 1.0, 1e-14);
    EXPECT_GT(face.offset, 0);
    for (const Vec3d& v : shape.vertices) EXPECT_LE(dot(face.normal, v), face.offset + tol);
    const std::size_t n = face.loop.size();
    ASSERT_GE(n, 3u);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3d& a = shape.vertices[face.loop[k]];
      const Vec3d& b = shape.vertices[face.loop[(k + 1) % n]];
      const Vec3d& c = shape.vertices[face.loop[(k + 2) % n]];
      EXPECT_NEAR(dot(face.normal, a), face.offset, tol);
      // Turning left seen from outside, by a clear angle: a convex corner, not a midpoint.
      const Vec3d turn = cross(b - a, c - b);
      EXPECT_GT(dot(turn, face.normal), 1e-6 * norm(b - a) * norm(c - b));
    }
  }
  EXPECT_EQ(shape.vertices.size() - shape.edges.size() + shape.faces.size(), 2u);
  std::size_t fan = 0;
  for (const Face& face : shape.faces) fan += face.loop.size() - 2;
  EXPECT_EQ(shape.triangles.size(), fan);
}

// Body frame: centroid at the origin and diagonal inertia equal to the principal moments.
void expect_principal_frame(const ShapeTemplate& shape) {
  const MassProperties body = mass_properties(shape.vertices, shape.triangles);
  const double r = shape.bounding_radius, top = shape.principal_moments.z;
  expect_rel(body.volume, shape.volume);
  EXPECT_LT(norm(body.centroid), 1e-12 * r);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(body.inertia[i][j], i == j ? shape.principal_moments[i] : 0.0, 1e-12 * top);
  EXPECT_LE(shape.principal_moments.x, shape.principal_moments.y * (1 + 1e-13));
  EXPECT_LE(shape.principal_moments.y, shape.principal_moments.z * (1 + 1e-13));
  EXPECT_NEAR(shape.body_to_input.norm(), 1.0, 1e-15);
}

class PlatonicSolid : public testing::TestWithParam<Platonic> {};

TEST_P(PlatonicSolid, MatchesClosedForms) {
  const Platonic& p = GetParam();
  const double diameter = 0.01, radius = diameter / 2, a = p.edge_per_radius * radius;
  const ShapeTemplate shape = make_builtin(std::string(p.name) + ":0.01");
  EXPECT_EQ(int(shape.faces.size()), p.faces);
  EXPECT_EQ(int(shape.vertices.size()), p.vertices);
  EXPECT_EQ(int(shape.edges.size()), p.edges);
  for (const Face& face : shape.faces) EXPECT_EQ(int(face.loop.size()), p.face_sides);
  const double volume = p.volume_coeff * a * a * a;
  expect_rel(shape.volume, volume);
  for (int k = 0; k < 3; ++k)
    expect_rel(shape.principal_moments[k], p.inertia_coeff * volume * a * a);
  expect_rel(shape.bounding_radius, radius);
  for (const Vec3d& v : shape.vertices) expect_rel(norm(v), radius);  // all on the sphere
  for (int e = 0; e < p.edges; ++e)
    expect_rel(norm(shape.vertices[shape.edges[e][0]] - shape.vertices[shape.edges[e][1]]), a);
  expect_valid_faces(shape);
  expect_principal_frame(shape);
}

INSTANTIATE_TEST_SUITE_P(Shapes, PlatonicSolid, testing::ValuesIn(kPlatonic),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Cuboid, MatchesClosedFormsAndPutsTheLongestSideAlongTheFirstAxis) {
  const double a = 0.01, b = 0.02, c = 0.03;
  const ShapeTemplate shape = make_builtin("cuboid:0.01,0.02,0.03");
  EXPECT_EQ(shape.faces.size(), 6u);
  EXPECT_EQ(shape.vertices.size(), 8u);
  EXPECT_EQ(shape.edges.size(), 12u);
  const double volume = a * b * c;
  expect_rel(shape.volume, volume);
  // Smallest moment about the longest side: (a^2 + b^2) V / 12, etc.
  expect_rel(shape.principal_moments.x, volume * (a * a + b * b) / 12);
  expect_rel(shape.principal_moments.y, volume * (a * a + c * c) / 12);
  expect_rel(shape.principal_moments.z, volume * (b * b + c * c) / 12);
  expect_rel(shape.bounding_radius, std::sqrt(a * a + b * b + c * c) / 2);
  for (const Vec3d& v : shape.vertices) {
    expect_rel(std::abs(v.x), c / 2);
    expect_rel(std::abs(v.y), b / 2);
    expect_rel(std::abs(v.z), a / 2);
  }
  expect_valid_faces(shape);
  expect_principal_frame(shape);
}

TEST(Cylinder, PaperTableOneIsTheTwentySidedPrismAndDiffersFromTheSmoothCylinderAsPredicted) {
  // Paper §3.1, Table 1: D = 8 mm, L = 5.3 mm, rho = 1245 kg/m^3, a 20-gon prism (Fig. 9a).
  const double diameter = 8e-3, length = 5.3e-3, density = 1245, r = diameter / 2;
  const int n = 20;
  const TriangleMesh mesh = cylinder_mesh(diameter, length, n);
  EXPECT_EQ(mesh.vertices.size(), 42u);   // 40 rim vertices + 2 cap centres
  EXPECT_EQ(mesh.triangles.size(), 80u);  // 2 x 20 cap fans + 40 side triangles
  const ShapeTemplate shape = make_builtin("cylinder:0.008,0.0053");
  EXPECT_EQ(shape.vertices.size(), 40u);  // the cap centres lie inside the caps
  EXPECT_EQ(shape.faces.size(), 22u);     // 20 side rectangles + 2 caps
  EXPECT_EQ(shape.edges.size(), 60u);

  // Regular N-gon of circumradius r, theta = 2 pi / N: area A = N r^2 sin(theta) / 2; polar
  // second moment about its centre J = N r^4 sin(theta) (2 + cos(theta)) / 12 (N triangles
  // (0, a, b) with integral |x|^2 = area (a.a + a.b + b.b) / 6). Prism: V = A L,
  // I_axis = J L, I_transverse = J L / 2 + A L^3 / 12.
  const double theta = 2 * kPi / n;
  const double area = n * r * r * std::sin(theta) / 2;
  const double polar = n * std::pow(r, 4) * std::sin(theta) * (2 + std::cos(theta)) / 12;
  const double volume = area * length;
  const double i_axis = polar * length,
               i_transverse = polar * length / 2 + area * std::pow(length, 3) / 12;
  expect_rel(shape.volume, volume);
  expect_rel(shape.principal_moments.x, i_transverse);
  expect_rel(shape.principal_moments.y, i_transverse);
  expect_rel(shape.principal_moments.z, i_axis);
  expect_rel(shape.bounding_radius, std::sqrt(r * r + length * length / 4));

  // The paper's Table 1 values are this prism's, to the digits printed (V = 2.62e-7 m^3,
  // I_xx = I_yy = 2.047e-9, I_zz = 2.567e-9 kg m^2): half a unit in the last digit.
  EXPECT_NEAR(shape.volume, 2.62e-7, 0.005e-7);
  EXPECT_NEAR(density * shape.principal_moments.x, 2.047e-9, 0.0005e-9);
  EXPECT_NEAR(density * shape.principal_moments.z, 2.567e-9, 0.0005e-9);

  // Against the smooth cylinder (V = pi r^2 L, I_axis = pi r^4 L / 2,
  // I_transverse = pi r^2 L (3 r^2 + L^2) / 12) the polygon's factors are exact:
  const double smooth_volume = kPi * r * r * length;
  const double smooth_axis = kPi * std::pow(r, 4) * length / 2;
  const double volume_ratio = std::sin(theta) / theta;                                // area ratio
  const double axis_ratio = n * std::sin(theta) * (2 + std::cos(theta)) / (6 * kPi);  // J ratio
  expect_rel(shape.volume / smooth_volume, volume_ratio);
  expect_rel(shape.principal_moments.z / smooth_axis, axis_ratio);
  // ... which for N = 20 means 1.64 % less volume (mass) and 3.24 % less axial moment.
  EXPECT_NEAR(1 - volume_ratio, 0.016368, 1e-6);
  EXPECT_NEAR(1 - axis_ratio, 0.032416, 1e-6);
  expect_valid_faces(shape);
  expect_principal_frame(shape);
}

TEST(Cylinder, SideCountIsHonoured) {
  const ShapeTemplate hexagonal = make_builtin("cylinder:0.01,0.02,6");
  EXPECT_EQ(hexagonal.vertices.size(), 12u);
  EXPECT_EQ(hexagonal.faces.size(), 8u);
  // Regular hexagon of circumradius 5 mm: area 3 sqrt(3) r^2 / 2.
  expect_rel(hexagonal.volume, 3 * std::sqrt(3.0) / 2 * 25e-6 * 0.02);
}

TEST(Mineral, HasEighteenVerticesAndThirtyTwoTriangularFaces) {
  const ShapeTemplate shape = make_builtin("mineral:0.02");
  EXPECT_EQ(shape.vertices.size(), 18u);
  EXPECT_EQ(shape.faces.size(), 32u);
  EXPECT_EQ(shape.edges.size(), 48u);  // 3V - 6 for a triangulated polyhedron
  for (const Face& face : shape.faces) EXPECT_EQ(face.loop.size(), 3u);
  expect_rel(shape.bounding_radius, 0.01);
  // Irregular: three clearly distinct principal moments.
  EXPECT_GT(shape.principal_moments.y / shape.principal_moments.x, 1.05);
  EXPECT_GT(shape.principal_moments.z / shape.principal_moments.y, 1.05);
  expect_valid_faces(shape);
  expect_principal_frame(shape);
  // Deterministic.
  const ShapeTemplate again = make_builtin("mineral:0.02");
  EXPECT_EQ(again.volume, shape.volume);
}

TEST(Corn, IsAFlattenedWedgeWithEveryPointOnItsHull) {
  const ShapeTemplate shape = make_builtin("corn:0.01");
  EXPECT_EQ(shape.vertices.size(), 20u);
  expect_rel(shape.bounding_radius, 0.005);
  // Extents along the principal axes: long (tip to crown) > wide > thin.
  Vec3d low, high;
  for (const Vec3d& v : shape.vertices)
    for (int k = 0; k < 3; ++k) low[k] = std::min(low[k], v[k]), high[k] = std::max(high[k], v[k]);
  const Vec3d extent = high - low;
  EXPECT_GT(extent.x, 1.1 * extent.y);
  EXPECT_GT(extent.y, 1.5 * extent.z);
  expect_valid_faces(shape);
  expect_principal_frame(shape);
}

// Faces of a built-in that share an edge bend by at least 5 degrees: a nearly flat pair would be
// two planes the overlap's dual hull can barely tell apart (an ill-conditioned shape for float),
// and would have been merged had it been meant flat.
TEST(Templates, NeighbouringFacesOfEveryBuiltinBendByAtLeastFiveDegrees) {
  for (const std::string& name : builtin_names()) {
    const std::string spec = name == "cuboid"     ? "cuboid:1,2,3"
                             : name == "cylinder" ? "cylinder:0.008,0.0053"
                                                  : name + ":0.01";
    EXPECT_GE(smallest_edge_bend_degrees(make_builtin(spec)), 5.0) << spec;
  }
}

TEST(Templates, MassPropertiesAreInvariantUnderRigidMotionsAndPermutations) {
  std::mt19937_64 rng(23);
  for (const char* spec : {"mineral:0.02", "corn:0.01", "cylinder:0.008,0.0053", "cuboid:1,2,3",
                           "dodecahedron:0.05", "tetrahedron:3"}) {
    const ShapeTemplate base = make_builtin(spec);
    // Input: the base vertices plus points inside faces and edges and at the centroid, which must
    // not become vertices.
    std::vector<Vec3d> points = base.vertices;
    for (const auto& e : base.edges)
      points.push_back((base.vertices[e[0]] * 0.3 + base.vertices[e[1]] * 0.7));
    for (const auto& t : base.triangles)
      points.push_back((base.vertices[t[0]] + base.vertices[t[1]] + base.vertices[t[2]]) / 3.0);
    points.push_back({0, 0, 0});
    for (int trial = 0; trial < 5; ++trial) {
      const Quatd q = random_rotation(rng);
      const Vec3d shift = Vec3d{1.0, -2.0, 0.5} * (5 * base.bounding_radius * trial);
      std::vector<Vec3d> input;
      for (const Vec3d& p : points) input.push_back(rotate(q, p) + shift);
      std::shuffle(input.begin(), input.end(), rng);
      const ShapeTemplate shape = make_template("moved", input);
      SCOPED_TRACE(std::string(spec) + " trial " + std::to_string(trial));
      ASSERT_EQ(shape.vertices.size(), base.vertices.size());
      EXPECT_EQ(shape.faces.size(), base.faces.size());
      expect_rel(shape.volume, base.volume);
      for (int k = 0; k < 3; ++k) expect_rel(shape.principal_moments[k], base.principal_moments[k]);
      expect_rel(shape.bounding_radius, base.bounding_radius);
      EXPECT_LT(norm(shape.input_centroid - shift), 1e-12 * (base.bounding_radius + norm(shift)));
      // input = input_centroid + R body: every body vertex maps onto an input point.
      for (const Vec3d& v : shape.vertices) {
        const Vec3d x = body_to_input_point(shape, v);
        double nearest = 1e300;
        for (const Vec3d& p : input) nearest = std::min(nearest, norm(p - x));
        EXPECT_LT(nearest, 1e-12 * (base.bounding_radius + norm(shift)));
      }
      expect_valid_faces(shape);
    }
  }
}

TEST(Templates, HullVerticesKeepInputOrder) {
  // The cube's corners given last, after interior points: they keep their relative order.
  std::vector<Vec3d> points = {{0, 0, 0}, {0.1, 0.2, 0.3}};
  for (int i = 0; i < 8; ++i)
    points.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
  const ShapeTemplate shape = make_template("cube", points);
  ASSERT_EQ(shape.vertices.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    const Vec3d x = body_to_input_point(shape, shape.vertices[i]);
    EXPECT_LT(norm(x - points[2 + i]), 1e-15);
  }
}

template <class Real>
void check_arrays(const ShapeTemplate& shape, Real tol) {
  const ShapeArrays<Real> arrays(shape);
  const ConvexView<Real> view = arrays.view();
  ASSERT_EQ(view.n_vertices, int(shape.vertices.size()));
  ASSERT_EQ(view.n_faces, int(shape.faces.size()));
  ASSERT_EQ(view.n_edges, int(shape.edges.size()));
  ASSERT_EQ(view.n_triangles, int(shape.triangles.size()));
  EXPECT_EQ(view.volume, Real(shape.volume));
  EXPECT_GE(view.bounding_radius, Real(shape.bounding_radius));
  for (int e = 0; e < view.n_edges; ++e) {
    EXPECT_EQ(view.edges[2 * e], shape.edges[e][0]);
    EXPECT_EQ(view.edges[2 * e + 1], shape.edges[e][1]);
  }
  for (int t = 0; t < view.n_triangles; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(view.triangles[3 * t + k], shape.triangles[t][k]);
  for (int v = 0; v < view.n_vertices; ++v) {
    EXPECT_LE(norm(view.vertices[v]), view.bounding_radius);
    for (int f = 0; f < view.n_faces; ++f)
      EXPECT_LE(dot(view.face_normals[f], view.vertices[v]), view.face_offsets[f]);
  }
  for (int f = 0; f < view.n_faces; ++f)
    EXPECT_NEAR(view.face_offsets[f], Real(shape.faces[f].offset), tol * shape.bounding_radius);
  // The support point in +x (Eq. 2) is the vertex with the largest x.
  Mat3<Real> identity = rotation_matrix(Quat<Real>());
  const Vec3<Real> support = support_point(view, identity, Vec3<Real>(), Vec3<Real>(1, 0, 0));
  Real best = view.vertices[0].x;
  for (int v = 0; v < view.n_vertices; ++v) best = std::max(best, view.vertices[v].x);
  EXPECT_EQ(support.x, best);
}

TEST(ShapeArrays, ViewExposesEveryFieldInDoubleAndFloat) {
  for (const char* spec : {"mineral:0.02", "cylinder:0.008,0.0053", "icosahedron:1"}) {
    SCOPED_TRACE(spec);
    const ShapeTemplate shape = make_builtin(spec);
    check_arrays<double>(shape, 1e-15);  // offsets as built, up to one rounding
    check_arrays<float>(shape, 1e-6);    // offsets re-taken from rounded vertices: float epsilon
  }
}

}  // namespace
}  // namespace talus
