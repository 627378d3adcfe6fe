// The bin grid over a wall's facets (solver/walls/facet_grid.hpp, facet_grid_build.hpp) against
// brute force: for random meshes (a soup of triangles of every size, slivers and degenerate ones
// among them; a generated drum of long strips and fans) and random spheres (inside and outside
// the grid's box, smaller and much larger than a cell, with the wall moved rigidly), the query
// returns every facet the sphere reaches, in strictly ascending order (so no duplicates), none
// at or above the present count, and only facets near the sphere (it prunes).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "solver/scene/wall_meshes.hpp"
#include "solver/walls/facet_grid_build.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using Triangles = std::vector<std::array<int, 3>>;
using LongVec = Vec3<long double>;

// The distance from p to triangle (a, b, c), in long double, written independently of
// closest_point_on_triangle: the foot on the plane when it lies inside, else the nearest of the
// three edges (a degenerate triangle has only its edges).
long double segment_distance(const LongVec& p, const LongVec& a, const LongVec& b) {
  const LongVec ab = b - a;
  const long double len2 = dot(ab, ab);
  long double s = len2 > 0 ? dot(p - a, ab) / len2 : 0;
  s = std::clamp(s, 0.0L, 1.0L);
  return norm(p - (a + ab * s));
}
long double triangle_distance(const Vec3d& pd, const Vec3d& ad, const Vec3d& bd, const Vec3d& cd) {
  const LongVec p(pd), a(ad), b(bd), c(cd);
  const LongVec n = cross(b - a, c - a);
  const long double n2 = dot(n, n);
  if (n2 > 0) {
    const LongVec foot = p - n * (dot(p - a, n) / n2);
    // Inside when the foot is on the inner side of all three edges.
    const long double u = dot(cross(b - a, foot - a), n), v = dot(cross(c - b, foot - b), n),
                      w = dot(cross(a - c, foot - c), n);
    if (u >= 0 && v >= 0 && w >= 0) return norm(p - foot);
  }
  return std::min(
      {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

struct Mesh {
  std::vector<Vec3d> vertices;
  Triangles triangles;
};

// `n` triangles in [-1, 1]^3: most of a random size from 0.01 to 1.5, some slivers (a corner
// almost on the opposite edge), some degenerate (a repeated corner, three collinear corners).
Mesh triangle_soup(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> unit(-1, 1), log_size(std::log(0.01), std::log(1.5));
  Mesh m;
  for (int t = 0; t < n; ++t) {
    const Vec3d centre(unit(rng), unit(rng), unit(rng));
    const double size = std::exp(log_size(rng));
    const Vec3d a = centre + random_direction(rng) * size;
    const Vec3d b = centre + random_direction(rng) * size;
    Vec3d c = centre + random_direction(rng) * size;
    if (t % 10 == 3) c = a + (b - a) * 0.3 + random_direction(rng) * (1e-9 * size);  // sliver
    if (t % 29 == 5) c = a;                                                          // repeated
    if (t % 31 == 7) c = a + (b - a) * 2.0;                                          // collinear
    const int first = static_cast<int>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({first, first + 1, first + 2});
  }
  return m;
}

// A generated drum (WallMesh) of `segments` sides, tilted: long strips and thin fan triangles.
Mesh drum(int segments) {
  WallSpec spec;
  spec.kind = WallKind::drum;
  DrumWall d;
  d.center = Vec3d(0.01, -0.02, 0.03);
  d.axis = Vec3d(0.3, 1, 0.2) / norm(Vec3d(0.3, 1, 0.2));
  d.radius = 0.1;
  d.length = 0.08;
  d.segments = segments;
  spec.shape = d;
  const WallMesh w = make_wall_mesh(spec);
  return {w.mesh.vertices, w.mesh.triangles};
}

struct QueryCheck {
  int returned = 0, missing = 0, unordered = 0, beyond_count = 0, far = 0;
};

// One query against brute force. The wall is moved by (rotation, translation) as the wall stage
// places it: corners in double, the distance in long double. `far_bound`: the largest distance a
// returned facet may lie at (negative: not checked).
template <class Real>
QueryCheck check_query(const Mesh& mesh, const FacetGridView<Real>& grid, int count,
                       const Quatd& rotation, const Vec3d& translation, const Vec3d& centre,
                       double radius, double far_bound) {
  FacetCursor<Real> cursor(grid, count, Quat<Real>(rotation), Vec3<Real>(translation),
                           Vec3<Real>(centre), Real(radius));
  std::vector<int> got;
  for (int t = cursor.next(); t >= 0; t = cursor.next()) got.push_back(t);
  QueryCheck c;
  c.returned = static_cast<int>(got.size());
  for (std::size_t k = 1; k < got.size(); ++k) c.unordered += got[k] <= got[k - 1] ? 1 : 0;
  for (const int t : got) c.beyond_count += t >= count ? 1 : 0;
  const Vec3<Real> c_real(centre);  // the centre as the step holds it
  // The step's exact test runs in Real on rounded corners: it may keep a facet up to a few units
  // of Real's round-off of the coordinates beyond the radius, so the grid must return those too.
  double scale = norm(centre) + norm(translation) + radius;
  for (const Vec3d& v : mesh.vertices) scale = std::max(scale, norm(centre) + norm(v) + radius);
  const double reach = radius + 64 * double(Eps<Real>::value) * scale;
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    Vec3d p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = rotate(rotation, mesh.vertices[mesh.triangles[t][k]]) + translation;
    }
    const long double d = triangle_distance(Vec3d(c_real), p[0], p[1], p[2]);
    const bool listed = std::binary_search(got.begin(), got.end(), t);
    if (t < count && d <= reach && !listed) ++c.missing;
    if (listed && far_bound >= 0 && d > far_bound) ++c.far;
  }
  return c;
}

template <class Real>
class FacetGridTest : public ::testing::Test {};
using Reals = ::testing::Types<double, float>;
TYPED_TEST_SUITE(FacetGridTest, Reals);

// Random spheres against a soup and a drum, the wall still or moved: nothing missing, ascending,
// nothing at or above the present count, and only facets near the sphere for spheres inside the
// grid's box (within sqrt 3 (radius + cell) of the centre: the query's cells reach one cell
// beyond its box; the margin, at most 1.2e-4 of the scale, is below the 10% slack).
TYPED_TEST(FacetGridTest, QueryReturnsEveryReachableFacetAscendingOnce) {
  using Real = TypeParam;
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(0, 1);
  int total_returned = 0, total_missing = 0, many_cells = 0;
  for (int mesh_kind = 0; mesh_kind < 2; ++mesh_kind) {
    const Mesh mesh = mesh_kind == 0 ? triangle_soup(rng, 400) : drum(160);
    const double max_radius = mesh_kind == 0 ? 0.03 : 0.006;
    const FacetGrid<Real> grid(mesh.vertices, mesh.triangles, max_radius);
    const FacetGridView<Real> view = grid.view();
    const double cell = double(view.cell_size);
    ASSERT_GE(cell, 2 * max_radius);
    Vec3d lo(1e9, 1e9, 1e9), hi(-1e9, -1e9, -1e9);
    for (const Vec3d& v : mesh.vertices) {
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    }
    const int facets = static_cast<int>(mesh.triangles.size());
    for (int q = 0; q < 3000; ++q) {
      const bool moved = q % 2 == 1;
      const Quatd rotation = moved ? random_rotation(rng) : Quatd();
      const Vec3d translation = moved ? random_direction(rng) * 0.3 : Vec3d();
      // A centre in the mesh frame, in the box grown by 20% on each side (some outside it).
      Vec3d local;
      for (int a = 0; a < 3; ++a) {
        const double pad = 0.2 * (hi[a] - lo[a]) + max_radius;
        local[a] = lo[a] - pad + (hi[a] - lo[a] + 2 * pad) * unit(rng);
      }
      // Most spheres up to the largest radius; every 5th one up to 4 cells (the search path).
      const double radius = q % 5 == 0 ? 4 * cell * unit(rng) : max_radius * unit(rng);
      many_cells += radius > cell ? 1 : 0;
      const int count = q % 3 == 0 ? facets - static_cast<int>(unit(rng) * facets / 4) : facets;
      bool inside = true;
      for (int a = 0; a < 3; ++a) inside = inside && local[a] >= lo[a] && local[a] <= hi[a];
      const double far = inside ? 1.1 * std::sqrt(3.0) * (radius + cell) : -1;
      const Vec3d centre = rotate(rotation, local) + translation;
      const QueryCheck c =
          check_query(mesh, view, count, rotation, translation, centre, radius, far);
      EXPECT_EQ(c.missing, 0) << "mesh " << mesh_kind << " query " << q;
      EXPECT_EQ(c.unordered, 0) << "mesh " << mesh_kind << " query " << q;
      EXPECT_EQ(c.beyond_count, 0) << "mesh " << mesh_kind << " query " << q;
      EXPECT_EQ(c.far, 0) << "mesh " << mesh_kind << " query " << q;
      total_returned += c.returned;
      total_missing += c.missing;
    }
  }
  EXPECT_EQ(total_missing, 0);
  EXPECT_GT(total_returned, 1000);  // the queries did reach facets
  EXPECT_GT(many_cells, 300);       // and many spanned more than 8 cells
}

// The check above catches a grid that drops a facet: the same grid with one facet taken out of
// every cell misses it for a small sphere at the facet's centroid.
TEST(FacetGrid, CheckCatchesADroppedFacet) {
  std::mt19937_64 rng(7);
  const Mesh mesh = triangle_soup(rng, 200);
  const FacetGrid<double> grid(mesh.vertices, mesh.triangles, 0.03);
  const int dropped = 117;
  std::vector<int> start = {0}, entries;
  for (std::size_t cell = 0; cell + 1 < grid.cell_start().size(); ++cell) {
    for (int e = grid.cell_start()[cell]; e < grid.cell_start()[cell + 1]; ++e) {
      if (grid.cell_facets()[e] != dropped) entries.push_back(grid.cell_facets()[e]);
    }
    start.push_back(static_cast<int>(entries.size()));
  }
  const std::array<int, 3>& t = mesh.triangles[dropped];
  const Vec3d centroid =
      (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) * (1.0 / 3);
  const int facets = static_cast<int>(mesh.triangles.size());
  const QueryCheck whole =
      check_query(mesh, grid.view(), facets, Quatd(), Vec3d(), centroid, 0.01, -1);
  EXPECT_EQ(whole.missing, 0);
  const QueryCheck broken = check_query(mesh, grid.view_of(start.data(), entries.data()), facets,
                                        Quatd(), Vec3d(), centroid, 0.01, -1);
  EXPECT_EQ(broken.missing, 1);
}

// Without a grid the cursor yields every facet below the count; with one, a non-finite centre
// too (the exact test cannot skip any facet for it, so neither may the grid).
TEST(FacetGrid, NoGridOrNonFiniteCentreYieldsEveryFacet) {
  FacetCursor<double> all(5);
  for (int t = 0; t < 5; ++t) EXPECT_EQ(all.next(), t);
  EXPECT_EQ(all.next(), -1);
  std::mt19937_64 rng(3);
  const Mesh mesh = triangle_soup(rng, 50);
  const FacetGrid<double> grid(mesh.vertices, mesh.triangles, 0.03);
  FacetCursor<double> nan(grid.view(), 40, Quatd(), Vec3d(), Vec3d(std::nan(""), 0, 0), 0.01);
  for (int t = 0; t < 40; ++t) EXPECT_EQ(nan.next(), t);
  EXPECT_EQ(nan.next(), -1);
}

// The cell size: at least a particle's diameter (a particle's box then spans at most 2 x 2 x 2
// cells), and within the cell budget however small the particles are against the wall.
TEST(FacetGrid, CellSizeFollowsTheParticlesWithinTheBudget) {
  Mesh box;
  for (int k = 0; k < 8; ++k) box.vertices.push_back(Vec3d(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  box.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 7, 5}, {4, 6, 7}, {0, 4, 5}, {0, 5, 1},
                   {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  const FacetGrid<double> fine(box.vertices, box.triangles, 1e-4);  // 0.2 mm grains in 1 m
  const FacetGridView<double> f = fine.view();
  EXPECT_LE(double(f.dims[0]) * f.dims[1] * f.dims[2], FacetGrid<double>::kMinCells);
  EXPECT_GT(double(f.dims[0]) * f.dims[1] * f.dims[2], FacetGrid<double>::kMinCells / 2);
  const FacetGrid<double> coarse(box.vertices, box.triangles, 0.1);
  EXPECT_GE(coarse.view().cell_size, 0.2);
  EXPECT_LT(coarse.view().cell_size, 0.2 * (1 + 1e-9));
  // Each facet is listed only in the cells its triangle meets: of a face's 5 x 5 cells, the 15
  // on and beside the diagonal's side and the 4 that touch the diagonal at a corner, 19 per
  // triangle, 228 in all; listing by bounding box would give 25 per triangle, 300.
  EXPECT_EQ(coarse.view().dims[0], 5);
  EXPECT_EQ(coarse.cell_facets().size(), 228u);
}

}  // namespace
}  // namespace talus
