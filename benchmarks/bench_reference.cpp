// Cost per contact of the serial reference solver (reference/, CGAL exact arithmetic): one
// dodecahedron-dodecahedron contact force (exact overlap + volume law), face first and corner
// first; one particle-triangle wall contact (exact section and volume below + law); and one
// RefWorld::step of a small bed, reported per contact.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include "reference/contact/contact_geometry.hpp"
#include "reference/contact/force_law.hpp"
#include "reference/geometry/wall_area.hpp"
#include "reference/world/world.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus::bench {
namespace {

using reference::RefPose;

Eigen::Vector3d e3(const Vec3d& v) {
  return {v.x, v.y, v.z};
}

// A's face (or corner) turned to -z, B its mirror above: overlapping by 50 um along z.
void pair_poses(const ShapeTemplate& t, bool corner, RefPose& a, RefPose& b) {
  const Eigen::Vector3d axis = corner ? e3(t.vertices[0]).normalized() : e3(t.faces[0].normal);
  const double reach = corner ? e3(t.vertices[0]).norm() : t.faces[0].offset;
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(axis, Eigen::Vector3d::UnitZ());
  a.orientation = q, b.orientation = q;
  a.position = Eigen::Vector3d(0, 0, -reach + 25e-6);
  b.position = Eigen::Vector3d(0, 0, reach - 25e-6);
}

void pair_contact(benchmark::State& state, bool corner) {
  const ShapeTemplate t = make_shape("dodecahedron:0.01");
  RefPose a, b;
  pair_poses(t, corner, a, b);
  reference::VolumeLawParameters law;
  law.effective_mass = 1e-3, law.restitution = 0.5, law.time_step = 1e-7;
  for (auto _ : state) {
    const reference::PairGeometry g = reference::volume_geometry(t, a, t, b);
    reference::NormalContact nc;
    nc.normal = g.normal, nc.point = g.point, nc.area = g.area;
    nc.normal_stiffness = 1e9 * g.area;
    nc.elastic = nc.normal_stiffness * std::cbrt(g.volume);
    reference::ContactHistory h;
    const reference::ContactForce f =
        reference::volume_contact_force(nc, law, Eigen::Vector3d(0, 0, 1), 1e-7, h);
    benchmark::DoNotOptimize(f.normal_force);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_ReferencePairContactFace(benchmark::State& state) {
  pair_contact(state, false);
}
void BM_ReferencePairContactCorner(benchmark::State& state) {
  pair_contact(state, true);
}

// A dodecahedron 50 um into one triangle (a face down), the wall-contact geometry and the law.
void BM_ReferenceWallFacetContact(benchmark::State& state) {
  const ShapeTemplate t = make_shape("dodecahedron:0.01");
  RefPose a, b;
  pair_poses(t, false, a, b);
  b.position.z() -= t.faces[0].offset;  // B's lower face 25 um below z = 0
  const Eigen::Vector3d p0(-0.05, -0.05, 0), p1(0.05, -0.05, 0), p2(0, 0.05, 0);
  reference::VolumeLawParameters law;
  law.effective_mass = 1e-3, law.restitution = 0.5, law.time_step = 1e-7;
  for (auto _ : state) {
    const reference::RefWallContact wc = reference::wall_contact(t, b, p0, p1, p2);
    reference::NormalContact nc;
    nc.normal = -wc.normal, nc.point = wc.overlap_centroid, nc.area = wc.section_area;
    nc.normal_stiffness = 1e9 * wc.section_area;
    nc.elastic = nc.normal_stiffness * std::cbrt(wc.volume_below);
    reference::ContactHistory h;
    const reference::ContactForce f =
        reference::volume_contact_force(nc, law, Eigen::Vector3d(0, 0, -1), 1e-7, h);
    benchmark::DoNotOptimize(f.normal_force);
  }
  state.SetItemsProcessed(state.iterations());
}

// A bed: 3 x 3 dodecahedra in a layer, 9.9 mm apart (side neighbours overlap), 1 um into a floor
// of two triangles, gravity on. Time per step divided by the contacts of the step.
void BM_ReferenceWorldStepPerContact(benchmark::State& state) {
  reference::RefWorldSetup s;
  s.templates = {make_shape("dodecahedron:0.01")};
  reference::RefMaterial m;
  m.name = "m", m.density = 2500, m.youngs_modulus = 1e7, m.poisson_ratio = 0.3;
  m.restitution = 0.5, m.friction = 0.3;
  s.materials = {m};
  s.effects.gravity = Eigen::Vector3d(0, 0, -9.81);
  s.effects.friction = true;
  s.time_step = 1e-7;
  const ShapeTemplate& t = s.templates[0];
  const Eigen::Quaterniond q =
      Eigen::Quaterniond::FromTwoVectors(e3(t.faces[0].normal), -Eigen::Vector3d::UnitZ());
  long long id = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      reference::RefBodySpec b;
      b.shape = 0, b.material = 0, b.id = ++id;
      b.position = Eigen::Vector3d(0.0099 * i, 0.0099 * j, t.faces[0].offset - 1e-6);
      b.orientation = q;
      s.bodies.push_back(b);
    }
  }
  reference::RefWall floor;
  floor.name = "floor", floor.material = 0;
  floor.triangles = {
      {Eigen::Vector3d(-0.1, -0.1, 0), Eigen::Vector3d(0.2, -0.1, 0), Eigen::Vector3d(0.2, 0.2, 0)},
      {Eigen::Vector3d(-0.1, -0.1, 0), Eigen::Vector3d(0.2, 0.2, 0),
       Eigen::Vector3d(-0.1, 0.2, 0)}};
  s.walls = {floor};
  reference::RefWorld world(s);
  world.step();
  const double contacts = static_cast<double>(world.contacts().size());
  for (auto _ : state) world.step();
  state.counters["contacts"] = contacts;
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * contacts));
}

BENCHMARK(BM_ReferencePairContactFace)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReferencePairContactCorner)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReferenceWallFacetContact)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReferenceWorldStepPerContact)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace talus::bench

BENCHMARK_MAIN();
