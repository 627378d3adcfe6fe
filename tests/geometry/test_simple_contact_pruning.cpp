// The pruned separating-axis search of the simple contact (Gauss-map test of Gregorius, GDC 2013,
// and the overlap bounds that skip axes, solver/geometry/separating_axes.hpp) against the full
// search over every face normal and edge pair, which runs when a view has no edge_faces; and the
// edge_faces that ShapeArrays derives from the face loops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "solver/geometry/simple_contact.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

const char* const kSpecs[] = {
    "dodecahedron:0.01",     "cube:0.009",        "mineral:0.01",     "corn:0.01",
    "cylinder:0.008,0.0053", "icosahedron:0.012", "tetrahedron:0.011"};
constexpr int kShapes = sizeof(kSpecs) / sizeof(kSpecs[0]);

template <class Real>
ConvexView<Real> without_edge_faces(ConvexView<Real> view) {
  view.edge_faces = nullptr;
  return view;
}

// Each edge's two faces: both loops hold the edge, the first runs edges[2e] -> edges[2e + 1], the
// second the other way.
TEST(SimpleContactPruning, EdgeFacesFollowTheLoops) {
  for (const char* spec : kSpecs) {
    const ShapeTemplate shape = make_builtin(spec);
    const ShapeArrays<double> arrays(shape);
    const ConvexView<double> view = arrays.view();
    ASSERT_NE(view.edge_faces, nullptr) << spec;
    for (int e = 0; e < view.n_edges; ++e) {
      for (int side = 0; side < 2; ++side) {
        const int face = view.edge_faces[2 * e + side];
        ASSERT_GE(face, 0) << spec;
        ASSERT_LT(face, view.n_faces) << spec;
        const std::vector<int>& loop = shape.faces[face].loop;
        const int from = view.edges[2 * e + side], to = view.edges[2 * e + 1 - side];
        bool runs = false;
        for (std::size_t k = 0; k < loop.size(); ++k) {
          runs = runs || (loop[k] == from && loop[(k + 1) % loop.size()] == to);
        }
        EXPECT_TRUE(runs) << spec << " edge " << e << " side " << side;
      }
    }
  }
  // A template whose loops do not close up around an edge gets no edge_faces (full search).
  ShapeTemplate broken = make_builtin("cube:1");
  broken.faces.pop_back();
  EXPECT_EQ(ShapeArrays<double>(broken).view().edge_faces, nullptr);
}

// Random pose pairs of every pair of built-ins, shallow to deep and some apart. The two searches
// take the minimum over axis sets that share every facet normal of A - B, from the same
// projections, so they pick the same axis, to the last bit in general position. Shapes with
// parallel edges (cube, corn, cylinder, and opposite edges of the regular solids) reach one
// direction through several edge pairs or a face, from differently rounded axes; either search
// may pick another of these ties, which the search itself treats as equal when within
// 16 eps (r_A + r_B) (and which differ by ~1e-16 in the normal). So: the depth to 1e-12 relative
// or the tie band, the normal to 1e-12.
TEST(SimpleContactPruning, SameDepthAndNormalAsTheFullSearch) {
  std::mt19937_64 rng(4242);
  std::vector<ShapeTemplate> templates;
  for (const char* spec : kSpecs) templates.push_back(make_builtin(spec));
  std::vector<ShapeArrays<double>> arrays;
  for (const ShapeTemplate& t : templates) arrays.emplace_back(t);
  int touching = 0, apart = 0, trials = 0;
  for (int a = 0; a < kShapes; ++a)
    for (int b = 0; b < kShapes; ++b)
      for (int k = 0; k < 50; ++k, ++trials) {
        // Centre distance (1 - f) (r_A + r_B): f in [0.1, 0.35] gives mostly shallow contacts,
        // [0.3, 0.7] deep ones, [-0.05, 0.1] mostly pairs apart.
        const double f_max = k % 5 == 0 ? 0.7 : k % 5 == 1 ? 0.1 : 0.35;
        const double f_min = k % 5 == 0 ? 0.3 : k % 5 == 1 ? -0.05 : 0.1;
        const PosePair poses = random_overlapping_pair(rng, templates[a].bounding_radius,
                                                       templates[b].bounding_radius, f_min, f_max);
        const ConvexView<double> va = arrays[a].view(), vb = arrays[b].view();
        const SimpleContact<double> pruned =
            polyhedron_polyhedron_contact(va, poses.a, vb, poses.b);
        const SimpleContact<double> full = polyhedron_polyhedron_contact(
            without_edge_faces(va), poses.a, without_edge_faces(vb), poses.b);
        const std::string what =
            std::string(kSpecs[a]) + " / " + kSpecs[b] + " trial " + std::to_string(k);
        ASSERT_EQ(pruned.touching, full.touching) << what;
        if (!full.touching) {
          ++apart;
          continue;
        }
        ++touching;
        const double tie_band =
            16 * Eps<double>::value * (templates[a].bounding_radius + templates[b].bounding_radius);
        EXPECT_NEAR(pruned.depth, full.depth, 1e-12 * full.depth + tie_band) << what;
        EXPECT_LE(norm(pruned.normal - full.normal), 1e-12) << what;
        EXPECT_LE(norm(pruned.point - full.point), 1e-12 * 0.01) << what;  // coordinates ~1 cm
      }
  EXPECT_GE(trials, 2000);
  EXPECT_GT(touching, trials / 3);  // contacts, where the pruning acts
  EXPECT_GT(apart, trials / 10);
}

// Aligned and right-angle placements of cubes, cylinders and dodecahedra: parallel edges,
// coincident face normals and Gauss-map arcs that meet at their ends, where the crossing test
// decides within its round-off band. The depth is the same; the normal may be either of two tied
// axes, so it is checked to realise the depth (the projections' overlap along it equals the depth).
TEST(SimpleContactPruning, DegeneratePlacementsSameDepth) {
  const double pi = 3.14159265358979323846;
  for (const char* spec : {"cube:0.01", "cylinder:0.008,0.0053", "dodecahedron:0.01"}) {
    const ShapeTemplate shape = make_builtin(spec);
    const ShapeArrays<double> arrays(shape);
    const ConvexView<double> view = arrays.view();
    const double r = shape.bounding_radius;
    int cases = 0;
    for (int turn = 0; turn < 4; ++turn)
      for (int dir = 0; dir < 3; ++dir)
        for (double f : {0.0, 0.02, 0.3}) {
          const Posed a{{0, 0, 0}, Quatd()};
          Vec3d d{0, 0, 0};
          d.x = dir == 0 ? 1 : 0;
          d.y = dir == 1 ? 1 : 0;
          d.z = dir == 2 ? 1 : 0;
          if (dir == 2) d = Vec3d{1, 1, 1} / std::sqrt(3.0);
          const Posed b{d * (2 * r * (1 - f) * 0.8),
                        Quatd::from_axis_angle({0, 0, 1}, turn * pi / 2)};
          const SimpleContact<double> pruned = polyhedron_polyhedron_contact(view, a, view, b);
          const SimpleContact<double> full = polyhedron_polyhedron_contact(
              without_edge_faces(view), a, without_edge_faces(view), b);
          ASSERT_EQ(pruned.touching, full.touching) << spec;
          if (!full.touching) continue;
          ++cases;
          // Ties are within 16 eps (r_A + r_B) ~ 1e-17 m; 1e-15 m leaves margin.
          EXPECT_NEAR(pruned.depth, full.depth, 1e-15) << spec << " turn " << turn;
          double lo_b = 1e300, hi_a = -1e300, lo_a = 1e300, hi_b = -1e300;
          for (const Vec3d& v : shape.vertices) {
            const double sa = dot(a.position + rotate(a.orientation, v), pruned.normal);
            const double sb = dot(b.position + rotate(b.orientation, v), pruned.normal);
            hi_a = std::max(hi_a, sa);
            lo_a = std::min(lo_a, sa);
            hi_b = std::max(hi_b, sb);
            lo_b = std::min(lo_b, sb);
          }
          EXPECT_NEAR(hi_a - lo_b, pruned.depth, 1e-15) << spec << " turn " << turn;
        }
    EXPECT_GT(cases, 12) << spec;
  }
}

// Float: the same agreement at float round-off (arcs accepted within 64 eps, ties within
// 16 eps (r_A + r_B)); 1e-5 relative is ~100 float eps.
TEST(SimpleContactPruning, FloatSameDepthAsTheFullSearch) {
  std::mt19937_64 rng(77);
  int touching = 0;
  for (int k = 0; k < 400; ++k) {
    const ShapeTemplate ta = make_builtin(kSpecs[k % kShapes]);
    const ShapeTemplate tb = make_builtin(kSpecs[(k / kShapes) % kShapes]);
    const ShapeArrays<float> sa(ta), sb(tb);
    const PosePair poses =
        random_overlapping_pair(rng, ta.bounding_radius, tb.bounding_radius, 0.1, 0.35);
    const Pose<float> pa{Vec3f(poses.a.position), Quat<float>(poses.a.orientation)};
    const Pose<float> pb{Vec3f(poses.b.position), Quat<float>(poses.b.orientation)};
    const SimpleContact<float> pruned = polyhedron_polyhedron_contact(sa.view(), pa, sb.view(), pb);
    const SimpleContact<float> full = polyhedron_polyhedron_contact(
        without_edge_faces(sa.view()), pa, without_edge_faces(sb.view()), pb);
    ASSERT_EQ(pruned.touching, full.touching) << k;
    if (!full.touching) continue;
    ++touching;
    EXPECT_NEAR(pruned.depth, full.depth, 1e-5f * full.depth) << k;
    EXPECT_LE(norm(pruned.normal - full.normal), 1e-5f) << k;
  }
  EXPECT_GT(touching, 120);
}

}  // namespace
}  // namespace talus
