// The host step with the facet grid (WallSearch::grid) against the same step with brute force
// (WallSearch::brute_force): the same bits at every step — positions, velocities, orientations,
// angular velocities, forces, torques, wall forces and contact counts — since the grid only
// prunes facets the exact test skips and visits the others in ascending order. The scene has a
// drum of 600 facets turning at 3000 rpm about its axis, which is off the origin (over the 200
// steps it turns 0.63 rad, 25 mm at its rim, several cells: a query in the wrong frame, without
// the rotation or the translation, misses facets and this test fails), with particles on its
// side and caps (near the caps' fan centres too); a translating plate; a hopper whose closed
// outlet opens at step 50 (a query that kept its plate's facets fails too). Many particles'
// bounding boxes straddle cell boundaries (the test counts them).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "solver/scene/wall_meshes.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/walls/facet_grid_build.hpp"
#include "tests/support/walled_scene.hpp"

namespace talus {
namespace {

using talus_test::kDrumCentre;
using talus_test::walled_scene;

template <class Real>
bool same_bits(const Real* a, const Real* b, int n) {
  return (a == nullptr) == (b == nullptr) &&
         (a == nullptr || std::memcmp(a, b, n * sizeof(Real)) == 0);
}
template <class Real>
bool same_bits(const Soa3<Real>& a, const Soa3<Real>& b, int n) {
  return same_bits(a.x, b.x, n) && same_bits(a.y, b.y, n) && same_bits(a.z, b.z, n);
}

struct Run {
  long long steps = 0, differing_steps = 0, wall_contact_steps = 0;
  std::vector<bool> wall_touched;          // per wall: a non-zero force at some step
  std::vector<std::size_t> wall_contacts;  // per step
};

// Both searches side by side over the scene's horizon.
template <class Real>
Run compare_searches(const Scene& scene) {
  HostStep<Real> grid(scene, 0, WallSearch::grid), brute(scene, 0, WallSearch::brute_force);
  const int n = grid.particle_count();
  Run run;
  run.wall_touched.assign(scene.walls.size(), false);
  const long long total = std::llround(scene.end_time / scene.time_step);
  for (long long k = 0; k < total; ++k) {
    grid.step();
    brute.step();
    ++run.steps;
    const ParticleView<Real>& g = grid.particles();
    const ParticleView<Real>& b = brute.particles();
    bool same = same_bits(g.position, b.position, n) && same_bits(g.velocity, b.velocity, n) &&
                same_bits(g.orientation.w, b.orientation.w, n) &&
                same_bits(g.orientation.x, b.orientation.x, n) &&
                same_bits(g.orientation.y, b.orientation.y, n) &&
                same_bits(g.orientation.z, b.orientation.z, n) &&
                same_bits(g.angular_velocity, b.angular_velocity, n) &&
                same_bits(g.force, b.force, n) && same_bits(g.torque, b.torque, n) &&
                grid.wall_contact_count() == brute.wall_contact_count() &&
                grid.pair_contact_count() == brute.pair_contact_count();
    for (int w = 0; w < static_cast<int>(scene.walls.size()); ++w) {
      const Vec3d fg = grid.wall_force(w), fb = brute.wall_force(w);
      const Vec3d tg = grid.wall_torque(w), tb = brute.wall_torque(w);
      same = same && std::memcmp(&fg, &fb, sizeof(Vec3d)) == 0 &&
             std::memcmp(&tg, &tb, sizeof(Vec3d)) == 0;
      if (norm(fg) > 0) run.wall_touched[w] = true;
    }
    run.wall_contacts.push_back(grid.wall_contact_count());
    run.differing_steps += same ? 0 : 1;
    run.wall_contact_steps += grid.wall_contact_count() > 0 ? 1 : 0;
  }
  return run;
}

void expect_identical(const Run& run) {
  EXPECT_EQ(run.steps, 200);
  EXPECT_EQ(run.differing_steps, 0);
  EXPECT_EQ(run.wall_contact_steps, run.steps);
  for (std::size_t w = 0; w < run.wall_touched.size(); ++w) {
    EXPECT_TRUE(run.wall_touched[w]) << "wall " << w << " never touched";
  }
  // Two particles sit on the outlet's plate until it opens at step 50 (or 51, as the sum of the
  // steps rounds): their contacts end there (both spheres'; one polyhedron's, the other's corner
  // has left the plate by then).
  ASSERT_EQ(run.wall_contacts.size(), 200u);
  EXPECT_GT(run.wall_contacts[48], run.wall_contacts[52]);
}

// The scene's particles whose bounding box crosses a cell boundary of the drum's grid (built as
// the wall stage builds it: the same mesh, the largest bounding radius), at t = 0.
int straddling(const Scene& scene, double max_radius) {
  const WallMesh drum = make_wall_meshes(scene).at(0);
  const FacetGrid<double> grid(drum.mesh.vertices, drum.mesh.triangles, max_radius);
  const FacetGridView<double> v = grid.view();
  int count = 0;
  for (const ParticleState& p : scene.particles) {
    if (norm(p.position - kDrumCentre) > 0.05) continue;  // not in the drum
    bool crosses = false;
    for (int a = 0; a < 3; ++a) {
      const double lo = (p.position[a] - max_radius - v.origin[a]) / v.cell_size;
      const double hi = (p.position[a] + max_radius - v.origin[a]) / v.cell_size;
      crosses = crosses || std::floor(lo) != std::floor(hi);
    }
    count += crosses ? 1 : 0;
  }
  return count;
}

TEST(WallGridStep, VolumeModelGridIsBitIdenticalToBruteForce) {
  const Scene scene = walled_scene("double", "volume", {"cube", "ico"});
  EXPECT_GE(scene.particles.size(), 25u);
  EXPECT_GE(straddling(scene, 0.0045), 8);
  expect_identical(compare_searches<double>(scene));
}

TEST(WallGridStep, VolumeModelGridIsBitIdenticalToBruteForceInFloat) {
  const Scene scene = walled_scene("float", "volume", {"cube", "ico"});
  expect_identical(compare_searches<float>(scene));
}

// Spheres use the nearest-facet rule over the facets within reach; a cube among them the
// linear model's clipping.
TEST(WallGridStep, LinearModelSpheresGridIsBitIdenticalToBruteForce) {
  const Scene scene = walled_scene(
      "double", "{model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}",
      {"ball", "ball", "cube"});
  EXPECT_GE(straddling(scene, 0.004), 8);
  expect_identical(compare_searches<double>(scene));
}

}  // namespace
}  // namespace talus
