// Convex hull, the symmetric eigen-solver and the rotation helpers behind the templates (§2.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

#include "solver/shape/hull.hpp"
#include "solver/shape/template_builder.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using Triangles = std::vector<std::array<int, 3>>;

std::set<int> hull_vertices(const Triangles& triangles) {
  std::set<int> vertices;
  for (const auto& t : triangles) vertices.insert(t.begin(), t.end());
  return vertices;
}

// Closed 2-manifold: every directed edge once, with its reverse; Euler characteristic 2.
void expect_closed_surface(const Triangles& triangles) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " used twice";
    ASSERT_EQ(directed.count({edge.second, edge.first}), 1u) << "edge without a twin";
  }
  const int v = int(hull_vertices(triangles).size()), e = int(directed.size()) / 2;
  EXPECT_EQ(v - e + int(triangles.size()), 2);
}

// Every point lies on the inner side of every outward triangle, within tol.
void expect_contains_all(const std::vector<Vec3d>& points, const Triangles& triangles, double tol) {
  for (const auto& t : triangles) {
    Vec3d n = cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]);
    n = n / norm(n);
    double worst = -1e300;
    for (const Vec3d& p : points) worst = std::max(worst, dot(n, p - points[t[0]]));
    ASSERT_LE(worst, tol);
  }
}

std::vector<Vec3d> moved(const std::vector<Vec3d>& points, const Quatd& q, const Vec3d& shift) {
  std::vector<Vec3d> out;
  for (const Vec3d& p : points) out.push_back(rotate(q, p) + shift);
  return out;
}

TEST(ConvexHull, GridCubeKeepsOnlyTheCornersDespiteFacePointsEdgePointsAndDuplicates) {
  // A 5x5x5 grid: 98 of the 125 points lie inside, on a facet or on an edge of the cube; each
  // point also appears twice. Rotated so that no coordinate is exact, then shuffled.
  std::vector<Vec3d> grid;
  for (int rep = 0; rep < 2; ++rep)
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        for (int k = 0; k < 5; ++k) grid.push_back({i * 0.25, j * 0.25, k * 0.25});
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Vec3d> points = moved(grid, random_rotation(rng), {0.3, -2.0, 5.0});
    std::shuffle(points.begin(), points.end(), rng);
    const Triangles hull = convex_hull(points);
    expect_closed_surface(hull);
    EXPECT_EQ(hull.size(), 12u);  // 6 square facets, 2 triangles each
    const std::set<int> vertices = hull_vertices(hull);
    ASSERT_EQ(vertices.size(), 8u);
    // Each hull vertex is a cube corner: at distance sqrt(3)/2 from the centre.
    Vec3d centre;
    for (const Vec3d& p : points) centre += p / double(points.size());
    for (int v : vertices) EXPECT_NEAR(norm(points[v] - centre), std::sqrt(3.0) / 2, 1e-12);
    expect_contains_all(points, hull, 1e-12);
  }
}

TEST(ConvexHull, IcosahedronWithEdgeMidpointsAndFaceCentresHasTwelveVertices) {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3d> points;
  for (int i = 0; i < 4; ++i) {
    const double a = i & 1 ? 1.0 : -1.0, b = i & 2 ? phi : -phi;
    points.insert(points.end(), {{0, a, b}, {a, b, 0}, {b, 0, a}});
  }
  const Triangles base = convex_hull(points);
  ASSERT_EQ(base.size(), 20u);
  // Collinear (edge midpoints) and coplanar (face centres) extras first, so that the hull meets
  // them before some corners.
  std::vector<Vec3d> extras;
  for (const auto& t : base) {
    extras.push_back((points[t[0]] + points[t[1]]) / 2.0);
    extras.push_back((points[t[0]] + points[t[1]] + points[t[2]]) / 3.0);
  }
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Vec3d> all = extras;
    all.insert(all.end(), points.begin(), points.end());
    all = moved(all, random_rotation(rng), {1, 2, 3});
    std::shuffle(all.begin(), all.end(), rng);
    const Triangles hull = convex_hull(all);
    expect_closed_surface(hull);
    EXPECT_EQ(hull_vertices(hull).size(), 12u);
    EXPECT_EQ(hull.size(), 20u);
  }
}

TEST(ConvexHull, RandomCloudsMatchBruteForceSupportingPlanes) {
  for (int seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    const std::vector<Vec3d> points = random_convex_cloud(rng, 30, 1.0);
    const Triangles hull = convex_hull(points);
    expect_closed_surface(hull);
    // Points in general position: p is a hull vertex iff it is a corner of some triangle whose
    // plane has all points on one side (O(n^4) search). Tolerance 1e-12: far above round-off of
    // unit-size coordinates, far below the gaps of random points.
    std::set<int> brute;
    const int n = int(points.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        for (int k = j + 1; k < n; ++k) {
          const Vec3d normal = cross(points[j] - points[i], points[k] - points[i]);
          bool above = false, below = false;
          for (int m = 0; m < n; ++m) {
            const double d = dot(normal, points[m] - points[i]) / norm(normal);
            above = above || d > 1e-12;
            below = below || d < -1e-12;
          }
          if (!(above && below)) brute.insert({i, j, k});
        }
    EXPECT_EQ(hull_vertices(hull), brute) << "seed " << seed;
    expect_contains_all(points, hull, 1e-12);
  }
}

TEST(ConvexHull, ThreeThousandPointsOnASphereAreAllVertices) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> gauss;
  std::vector<Vec3d> points;
  for (int i = 0; i < 3000; ++i) {
    const Vec3d d{gauss(rng), gauss(rng), gauss(rng)};
    points.push_back(d / norm(d));
  }
  const Triangles hull = convex_hull(points);
  expect_closed_surface(hull);
  EXPECT_EQ(hull_vertices(hull).size(), 3000u);  // a strictly convex surface: every point a corner
  EXPECT_EQ(hull.size(), 2 * 3000u - 4);         // triangulated sphere: F = 2V - 4
  expect_contains_all(points, hull, 1e-12);
}

TEST(ConvexHull, ClustersAFewTolerancesWideRaiseTheToleranceInsteadOfFoldingTheSurface) {
  // Each of the 27 points of a 3x3x3 grid replaced by a cluster jittered by 1e-9..1e-7: planes
  // through points of one cluster are not resolvable in double precision at the default
  // tolerance (2e-10 of the extent here).
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> jitter(-1, 1);
  int raised = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const double amplitude = std::pow(10.0, -9 + trial % 3);
    std::vector<Vec3d> points;
    for (int i = 0; i < 150; ++i) {
      const Vec3d node{double(rng() % 3), double(rng() % 3), double(rng() % 3)};
      points.push_back(node + Vec3d{jitter(rng), jitter(rng), jitter(rng)} * amplitude);
    }
    points = moved(points, random_rotation(rng), {3, 4, 5});
    const Hull hull = convex_hull_with_tolerance(points);
    const double base = hull_tolerance(points, 1e-10);
    EXPECT_GE(hull.tolerance, base);
    EXPECT_LE(hull.tolerance, base * std::pow(10.0, kToleranceRaises) * 1.000001);
    if (hull.tolerance > base) ++raised;
    expect_closed_surface(hull.triangles);
    // Within the tolerance actually used once for the first hull and once for each rebuild from
    // its corners (convex_hull's contract), plus round-off of the plane of a 2 m face.
    expect_contains_all(points, hull.triangles, (1 + kCornerPasses) * hull.tolerance + 1e-14);
  }
  EXPECT_GT(raised, 0);  // the retry path is exercised by this data
}

TEST(ConvexHull, FlatOrTooFewPointsAreRejectedWithAReason) {
  const auto message = [](const std::vector<Vec3d>& points) {
    try {
      convex_hull(points);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).find("only 3 points"), std::string::npos);
  EXPECT_NE(message({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}).find("coincide"),
            std::string::npos);
  EXPECT_NE(message({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {-1, -1, -1}}).find("collinear"),
            std::string::npos);
  std::vector<Vec3d> plane;
  std::mt19937_64 rng(5);
  const Quatd q = random_rotation(rng);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) plane.push_back(rotate(q, Vec3d{double(i), double(j), 0}));
  const std::string flat = message(plane);
  EXPECT_NE(flat.find("coplanar"), std::string::npos) << flat;
  EXPECT_NE(flat.find("at least 4 non-coplanar points"), std::string::npos) << flat;
}

// R diag(values) R^T for a random rotation R.
Matrix3d rotated_diagonal(const Vec3d& values, const Quatd& q) {
  const Mat3<double> r = rotation_matrix(q);
  Matrix3d m{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) m[i][j] += r.m[i][k] * values[k] * r.m[j][k];
  return m;
}

void expect_right_handed_orthonormal(const SymmetricEigen& eigen) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      EXPECT_NEAR(dot(eigen.vectors[a], eigen.vectors[b]), a == b ? 1.0 : 0.0, 1e-14);
  EXPECT_NEAR(triple(eigen.vectors[0], eigen.vectors[1], eigen.vectors[2]), 1.0, 1e-14);
}

TEST(SymmetricEigen, RecoversEigenvaluesOfRotatedDiagonalMatricesToRoundOff) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> value(-3, 10);
  for (int trial = 0; trial < 200; ++trial) {
    Vec3d values{value(rng), value(rng), value(rng)};
    const Matrix3d m = rotated_diagonal(values, random_rotation(rng));
    std::sort(&values.x, &values.x + 3);
    const SymmetricEigen eigen = symmetric_eigen(m);
    // 1e-14 of the largest eigenvalue: a few round-offs of building and rotating m.
    const double scale = std::max(std::abs(values.x), std::abs(values.z));
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(eigen.values[k], values[k], 1e-14 * scale);
      // Residual |M v - lambda v|.
      Vec3d mv;
      for (int i = 0; i < 3; ++i)
        mv[i] = m[i][0] * eigen.vectors[k].x + m[i][1] * eigen.vectors[k].y +
                m[i][2] * eigen.vectors[k].z;
      EXPECT_LT(norm(mv - eigen.vectors[k] * eigen.values[k]), 1e-14 * scale);
    }
    expect_right_handed_orthonormal(eigen);
  }
}

TEST(SymmetricEigen, DegenerateSpectraStillGiveARightHandedFrame) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 50; ++trial) {
    const SymmetricEigen pair = symmetric_eigen(rotated_diagonal({2, 2, 5}, random_rotation(rng)));
    EXPECT_NEAR(pair.values.x, 2, 1e-14 * 5);
    EXPECT_NEAR(pair.values.y, 2, 1e-14 * 5);
    EXPECT_NEAR(pair.values.z, 5, 1e-14 * 5);
    expect_right_handed_orthonormal(pair);
    const SymmetricEigen triple_value =
        symmetric_eigen(rotated_diagonal({4, 4, 4}, random_rotation(rng)));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(triple_value.values[k], 4, 1e-14 * 4);
    expect_right_handed_orthonormal(triple_value);
  }
  // An exactly isotropic matrix keeps the input axes (a cube's body frame stays axis-aligned).
  const SymmetricEigen identity = symmetric_eigen({{{3, 0, 0}, {0, 3, 0}, {0, 0, 3}}});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(identity.vectors[k][k], 1.0);
}

TEST(QuaternionFromColumns, InvertsRotationMatrix) {
  std::mt19937_64 rng(19);
  for (int trial = 0; trial < 200; ++trial) {
    const Quatd q = random_rotation(rng);
    const Mat3<double> r = rotation_matrix(q);
    const std::array<Vec3d, 3> columns = {Vec3d{r.m[0][0], r.m[1][0], r.m[2][0]},
                                          Vec3d{r.m[0][1], r.m[1][1], r.m[2][1]},
                                          Vec3d{r.m[0][2], r.m[1][2], r.m[2][2]}};
    const Quatd back = quaternion_from_columns(columns);
    const double sign = back.w * q.w + back.x * q.x + back.y * q.y + back.z * q.z > 0 ? 1 : -1;
    EXPECT_NEAR(back.w, sign * q.w, 1e-14);
    EXPECT_NEAR(back.x, sign * q.x, 1e-14);
    EXPECT_NEAR(back.y, sign * q.y, 1e-14);
    EXPECT_NEAR(back.z, sign * q.z, 1e-14);
  }
}

}  // namespace
}  // namespace talus
