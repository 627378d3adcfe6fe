// The production step on the GPU (solver/step/cuda/cuda_step.hpp) against the host step
// (host_step.hpp, itself tested against the reference solver in
// tests/reference/test_production_vs_reference.cpp) on that file's 2- and 20-particle scenes,
// stepped side by side over the same horizons: the same number of pair and wall contacts at every
// step, and positions within 1e-10 relative. Skipped with the reason where no GPU is usable.
//
// TALUS_GPU_TEST_MAX_STEPS caps the steps of every comparison (compute-sanitizer runs the kernels
// tens of times slower): the capped runs then check agreement only, not that contacts formed;
// GpuStep.CrowdInABoxVolumeMatchesHost has pair and wall contacts from its first step and 300
// steps in all, so the capped runs still exercise every contact kernel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/step/template_table.hpp"
#include "tests/support/gpu_skip.hpp"
#include "tests/support/walled_scene.hpp"

namespace talus {
namespace {

Scene scene_from(const std::string& yaml) {
  return parse_scene(yaml, "test.yaml", ".");
}

long long max_steps() {
  const char* cap = std::getenv("TALUS_GPU_TEST_MAX_STEPS");
  return cap ? std::atoll(cap) : -1;
}

// The scenes of test_production_vs_reference.cpp (same text, same seeds).
const char* const kGlass = R"(
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
)";

std::string cloud(int n, double spacing, double speed, const std::vector<std::string>& templates,
                  std::uint64_t seed, int side = 3) {
  std::mt19937_64 random(seed);
  const auto uniform = [&] { return double(random() >> 11) * 0x1.0p-53 - 0.5; };
  std::ostringstream out;
  out.precision(17);
  out << "particles:\n  - explicit:\n";
  for (int k = 0; k < n; ++k) {
    const double mid = 0.5 * (side - 1);
    const double x = spacing * (k % side - mid + 0.1 * uniform());
    const double y = spacing * ((k / side) % side - mid + 0.1 * uniform());
    const double z = spacing * (k / (side * side) - mid + 0.1 * uniform());
    out << "      - {template: " << templates[k % templates.size()] << ", position: [" << x << ", "
        << y << ", " << z << "], velocity: [" << -speed * x / spacing + speed * uniform() << ", "
        << -speed * y / spacing << ", " << -speed * z / spacing << "], orientation: {axis: ["
        << uniform() << ", 1, " << uniform() << "], degrees: " << 90 * uniform()
        << "}, angular_velocity: [" << 10 * uniform() << ", " << 10 * uniform() << ", "
        << 10 * uniform() << "]}\n";
  }
  return out.str();
}

Scene two_cubes_volume() {
  return scene_from(std::string("time: {step: 1.0e-6, end: 3.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
  octa: {shape: "octahedron:0.012", material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.0062, 0.001, 0.0005], velocity: [1.0, 0, 0],
         orientation: {axis: [1, 1, 0], degrees: 30}, angular_velocity: [0, 5, 20]}
      - {template: octa, position: [0.0062, -0.001, 0], velocity: [-1.0, 0.2, 0],
         orientation: {axis: [0, 1, 1], degrees: 20}}
effects:
  contact: volume
  friction: true
  rotation: true
)");
}

Scene two_spheres_volume() {
  return scene_from(std::string("time: {step: 1.0e-6, end: 2.0e-3}\n") + kGlass + R"(
templates:
  ball: {sphere: 0.005, material: glass}
  small: {sphere: 0.003, material: glass}
particles:
  - explicit:
      - {template: ball, position: [-0.0051, 0.001, 0], velocity: [1.0, 0, 0],
         angular_velocity: [0, 10, 30]}
      - {template: small, position: [0.0032, -0.001, 0], velocity: [-1.0, 0.2, 0]}
effects:
  contact: volume
  friction: true
  rotation: true
)");
}

Scene sphere_and_cube_linear() {
  return scene_from(std::string("time: {step: 1.0e-6, end: 2.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
  ball: {sphere: 0.004, material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.0052, 0.001, 0.0005], velocity: [1.0, 0, 0],
         orientation: {axis: [1, 1, 0], degrees: 30}, angular_velocity: [0, 5, 20]}
      - {template: ball, position: [0.0052, -0.001, 0], velocity: [-1.0, 0.2, 0]}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
}

Scene twenty_polyhedra_volume(const std::string& precision = "double") {
  return scene_from(std::string("time: {step: 2.0e-6, end: 3.0e-3}\nprecision: ") + precision +
                    "\n" + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  octa: {shape: "octahedron:0.011", material: glass}
)" + cloud(20, 0.011, 1.0, {"cube", "octa"}, 11) +
                    R"(
effects:
  contact: volume
  friction: true
  rotation: true
)");
}

Scene twenty_mixed_in_a_box_linear() {
  std::vector<std::string> names;
  for (int k = 0; k < 20; ++k)
    names.push_back(k == 0 || k == 19 ? "cube" : k % 2 ? "ball" : "small");
  return scene_from(std::string("time: {step: 2.0e-6, end: 6.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  ball: {sphere: 0.005, material: glass}
  small: {sphere: 0.004, material: glass}
walls:
  - box: {min: [-0.019, -0.019, -0.019], max: [0.019, 0.019, 0.019], material: glass}
)" + cloud(20, 0.012, 1.0, names, 5) +
                    R"(
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)");
}

struct Agreement {
  long long steps = 0, contact_steps = 0, mismatches = 0;
  long long list_builds = 0;  // the GPU step's pair-list builds (evaluate_forces' included)
  double position_error = 0;  // max |x_gpu - x_host| / max(|x_host|, length)
  bool finite = true;
};

// Both steps side by side. `length`: the particles' size (the error of a particle near the origin
// is measured against it rather than against 0).
template <class Real>
Agreement compare_steps(const Scene& scene, double length) {
  HostStep<Real> host(scene);
  CudaStep<Real> gpu(scene);
  long long total = std::llround(scene.end_time / scene.time_step);
  if (max_steps() > 0) total = std::min(total, max_steps());
  Agreement a;
  for (long long k = 0; k < total; ++k) {
    host.step();
    gpu.step();
    ++a.steps;
    a.contact_steps += host.pair_contact_count() + host.wall_contact_count() > 0 ? 1 : 0;
    a.mismatches += host.pair_contact_count() != gpu.pair_contact_count() ||
                            host.wall_contact_count() != gpu.wall_contact_count()
                        ? 1
                        : 0;
    const std::vector<TrajectoryRow> h = host.trajectory_rows(), g = gpu.trajectory_rows();
    EXPECT_EQ(h.size(), g.size());
    for (std::size_t i = 0; i < std::min(h.size(), g.size()); ++i) {
      a.finite = a.finite && std::isfinite(g[i].position.x) && std::isfinite(g[i].position.y) &&
                 std::isfinite(g[i].position.z);
      a.position_error = std::max(a.position_error, norm(g[i].position - h[i].position) /
                                                        std::max(norm(h[i].position), length));
    }
  }
  a.list_builds = gpu.pair_list_builds();
  std::printf(
      "steps %lld  contact steps %lld  mismatches %lld  position error %.3g  list builds %lld\n",
      a.steps, a.contact_steps, a.mismatches, a.position_error, a.list_builds);
  return a;
}

// Double: the GPU runs the host's functions with the host's summation order; what differs is
// nvcc's fused multiply-adds (and libm's cbrt/sqrt), ~1e-16 relative per operation. A contact
// amplifies that by far less than 1e5 over these horizons (the reference comparison, whose
// implementations differ far more, stays below 1e-8), so 1e-10 leaves a margin of 100 above
// 1e-16 x 1e4 and still catches any wrong term (a force or torque term off is ~1e-3 and more).
constexpr double kDoubleTolerance = 1e-10;

void expect_agreement(const Agreement& a, long long min_contact_steps) {
  EXPECT_TRUE(a.finite);
  EXPECT_EQ(a.mismatches, 0);
  if (max_steps() <= 0) EXPECT_GE(a.contact_steps, min_contact_steps);
  EXPECT_LT(a.position_error, kDoubleTolerance);
}

TEST(GpuStep, TwoCubesVolumeMatchesHost) {
  SKIP_WITHOUT_GPU();
  expect_agreement(compare_steps<double>(two_cubes_volume(), 0.01), 100);
}

TEST(GpuStep, TwoSpheresVolumeMatchesHost) {
  SKIP_WITHOUT_GPU();
  expect_agreement(compare_steps<double>(two_spheres_volume(), 0.005), 100);
}

TEST(GpuStep, SphereAndCubeLinearMatchesHost) {
  SKIP_WITHOUT_GPU();
  expect_agreement(compare_steps<double>(sphere_and_cube_linear(), 0.01), 100);
}

TEST(GpuStep, TwentyPolyhedraVolumeMatchesHost) {
  SKIP_WITHOUT_GPU();
  expect_agreement(compare_steps<double>(twenty_polyhedra_volume(), 0.01), 100);
}

TEST(GpuStep, TwentyMixedParticlesInABoxLinearMatchesHost) {
  SKIP_WITHOUT_GPU();
  expect_agreement(compare_steps<double>(twenty_mixed_in_a_box_linear(), 0.01), 100);
}

std::string mixed_capacity_scene() {
  return std::string("time: {step: 2.0e-6, end: 3.0e-3}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  ico: {shape: "icosahedron:0.012", material: glass}
)" + cloud(12, 0.011, 2.0, {"cube", "ico"}, 3) +
         R"(
effects:
  contact: volume
  friction: true
  rotation: true
)";
}

// Mixed workspace capacities in one scene: cubes and icosahedra (6 + 6 and 6 + 20 faces: the
// 32-plane workspace; 20 + 20: the 64-plane one), so two pair launches each step.
TEST(GpuStep, MixedWorkspaceCapacitiesMatchHost) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(mixed_capacity_scene());
  expect_agreement(compare_steps<double>(scene, 0.01), 50);
}

// 20 cubes and icosahedra crowded in a box, volume model, gravity, friction, rotation: 2 to 35
// touching pairs and 7 wall contacts at the start (the host step says so), both workspace
// capacities, histories for pairs and walls; 300 steps. `settings`: top-level keys (skin,
// deterministic).
Scene crowd_in_a_box(const std::string& settings = "") {
  return scene_from(std::string("time: {step: 2.0e-6, end: 6.0e-4}\n") + settings + kGlass + R"(
templates:
  cube: {shape: "cube:0.008", material: glass}
  ico: {shape: "icosahedron:0.009", material: glass}
walls:
  - box: {min: [-0.0115, -0.0115, -0.0115], max: [0.0115, 0.0115, 0.0115], material: glass}
)" + cloud(20, 0.0075, 3.0, {"cube", "ico"}, 9) +
                    R"(
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)");
}

// The default skin (a tenth of the largest bounding diameter, 0.9 mm here): particles move at
// most 3 m/s x 6e-4 s = 1.8 mm, so the list is kept for many steps, yet the contacts and
// positions are the host's (which builds its list every step with no skin).
TEST(GpuStep, CrowdInABoxVolumeMatchesHost) {
  SKIP_WITHOUT_GPU();
  const Agreement a = compare_steps<double>(crowd_in_a_box(), 0.01);
  expect_agreement(a, 300);
  // Under TALUS_GPU_TEST_MAX_STEPS (the sanitizer runs) fewer steps are compared.
  EXPECT_EQ(a.steps, max_steps() > 0 ? std::min(max_steps(), 300LL) : 300);
  // Kept while no particle has moved 0.45 skin = 0.41 mm: about 1.8 / 0.41 + 1 builds at most
  // (speeds fall in the box); 1 + 300 would mean the skin is ignored.
  if (max_steps() <= 0) EXPECT_LE(a.list_builds, 10);
  EXPECT_GE(a.list_builds, 1);
}

// No skin: the list is built at every evaluation (301: evaluate_forces and 300 steps), with the
// same results.
TEST(GpuStep, NoSkinBuildsTheListEveryStep) {
  SKIP_WITHOUT_GPU();
  const Agreement a = compare_steps<double>(crowd_in_a_box("skin: 0\n"), 0.01);
  expect_agreement(a, 300);
  EXPECT_EQ(a.list_builds, a.steps + 1);
}

// A skin as wide as the particles: many more candidates that never touch, the same contacts.
TEST(GpuStep, WideSkinMatchesHost) {
  SKIP_WITHOUT_GPU();
  const Agreement a = compare_steps<double>(crowd_in_a_box("skin: 0.008\n"), 0.01);
  expect_agreement(a, 300);
  EXPECT_EQ(a.list_builds, 1);  // nothing moves 3.6 mm within 6e-4 s at <= 3 m/s
}

// deterministic: false adds the pair forces by atomics, in whatever order threads arrive: the
// sums round differently (~1e-16 relative per addition), which stays within the tolerance of
// the comparison above.
TEST(GpuStep, AtomicAccumulationMatchesHost) {
  SKIP_WITHOUT_GPU();
  const Agreement a = compare_steps<double>(crowd_in_a_box("deterministic: false\n"), 0.01);
  expect_agreement(a, 300);
}

// Deterministic mode repeats bit for bit: two runs of the crowd give the same positions and
// velocities exactly.
TEST(GpuStep, DeterministicRunsRepeatExactly) {
  SKIP_WITHOUT_GPU();
  const Scene scene = crowd_in_a_box();
  CudaStep<double> first(scene), second(scene);
  const long long steps = max_steps() > 0 ? std::min(max_steps(), 300LL) : 300;
  for (long long k = 0; k < steps; ++k) first.step(), second.step();
  const std::vector<TrajectoryRow> a = first.trajectory_rows(), b = second.trajectory_rows();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position.x, b[i].position.x);
    EXPECT_EQ(a[i].position.y, b[i].position.y);
    EXPECT_EQ(a[i].position.z, b[i].position.z);
    EXPECT_EQ(a[i].velocity.x, b[i].velocity.x);
    EXPECT_EQ(a[i].velocity.z, b[i].velocity.z);
  }
  EXPECT_GT(first.pair_contact_count(), 0u);
}

double max_position_error(const std::vector<TrajectoryRow>& gpu,
                          const std::vector<TrajectoryRow>& host, double length) {
  double error = gpu.size() == host.size() ? 0 : HUGE_VAL;
  for (std::size_t i = 0; i < std::min(gpu.size(), host.size()); ++i) {
    error = std::max(
        error, norm(gpu[i].position - host[i].position) / std::max(norm(host[i].position), length));
  }
  return error;
}

// Templates in constant memory (template_table.hpp): each step alive holds its own region.
// Two scenes whose second templates differ (icosahedra, octahedra) stepped in turn, each
// against its host run: had two steps shared a region, one would collide with the other's
// shapes and masses. One step more than there are regions reads global memory instead, with
// the same results; the regions come back when their steps go.
TEST(GpuStep, StepsAliveTogetherReadTheirOwnTemplates) {
  SKIP_WITHOUT_GPU();
  const Scene crowd = crowd_in_a_box(), twenty = twenty_polyhedra_volume();
  HostStep<double> host_crowd(crowd), host_twenty(twenty);
  {
    std::vector<std::unique_ptr<CudaStep<double>>> gpu;
    for (int k = 0; k <= kTemplateRegions; ++k)
      gpu.push_back(std::make_unique<CudaStep<double>>(k % 2 ? twenty : crowd));
    for (int k = 0; k < kTemplateRegions; ++k) EXPECT_TRUE(gpu[k]->templates_in_constant_memory());
    EXPECT_FALSE(gpu.back()->templates_in_constant_memory());
    const long long steps = max_steps() > 0 ? std::min(max_steps(), 200LL) : 200;
    for (long long n = 0; n < steps; ++n) {
      host_crowd.step();
      host_twenty.step();
      for (auto& step : gpu) step->step();
    }
    EXPECT_GT(host_crowd.pair_contact_count(), 0u);
    for (int k = 0; k <= kTemplateRegions; ++k) {
      SCOPED_TRACE(k);
      const HostStep<double>& host = k % 2 ? host_twenty : host_crowd;
      EXPECT_EQ(gpu[k]->pair_contact_count(), host.pair_contact_count());
      EXPECT_LT(max_position_error(gpu[k]->trajectory_rows(), host.trajectory_rows(), 0.01),
                kDoubleTolerance);
    }
  }
  const CudaStep<double> again(crowd);
  EXPECT_TRUE(again.templates_in_constant_memory());
  CudaStepOptions global;
  global.constant_templates = false;
  EXPECT_FALSE(CudaStep<double>(crowd, global).templates_in_constant_memory());
}

// The scene of the host's grid test (tests/support/walled_scene.hpp) with a drum of 400 segments
// (1600 facets) turning at 3000 rpm about an axis off the origin, so that the device places its
// corners each step and maps particles back through a rotation and a translation; a translating
// plate; a hopper (a static wall, 180 facets, uploaded once) whose outlet opens at step 50, when
// its present count drops; cubes and icosahedra resting on all of them; volume model, gravity,
// friction, rotation; 200 steps. The facet grid on both sides.
Scene drum_and_hopper_volume() {
  return talus_test::walled_scene("double", "volume", {"cube", "ico"}, 400);
}

TEST(GpuStep, ManyFacetDrumAndOpeningOutletMatchHost) {
  SKIP_WITHOUT_GPU();
  const Agreement a = compare_steps<double>(drum_and_hopper_volume(), 0.01);
  expect_agreement(a, 200);
  EXPECT_EQ(a.steps, max_steps() > 0 ? std::min(max_steps(), 200LL) : 200);
}

// On the device, the facet grid against brute force (WallSearch::brute_force): the same kernel
// arithmetic over the same facets in the same order, so the same bits, as on the host
// (tests/step/test_wall_grid_step.cpp).
TEST(GpuStep, WallGridMatchesBruteForceOnDevice) {
  SKIP_WITHOUT_GPU();
  const Scene scene = drum_and_hopper_volume();
  CudaStepOptions grid_search, brute_search;
  brute_search.wall_search = WallSearch::brute_force;
  CudaStep<double> grid(scene, grid_search), brute(scene, brute_search);
  long long total = std::llround(scene.end_time / scene.time_step);
  if (max_steps() > 0) total = std::min(total, max_steps());
  long long differing = 0, wall_contact_steps = 0;
  for (long long k = 0; k < total; ++k) {
    grid.step();
    brute.step();
    const std::vector<TrajectoryRow> g = grid.trajectory_rows(), b = brute.trajectory_rows();
    bool same = g.size() == b.size() && grid.wall_contact_count() == brute.wall_contact_count();
    for (std::size_t i = 0; same && i < g.size(); ++i) {
      same = std::memcmp(&g[i].position, &b[i].position, sizeof(Vec3d)) == 0 &&
             std::memcmp(&g[i].velocity, &b[i].velocity, sizeof(Vec3d)) == 0 &&
             std::memcmp(&g[i].orientation, &b[i].orientation, sizeof(Quatd)) == 0 &&
             std::memcmp(&g[i].angular_velocity, &b[i].angular_velocity, sizeof(Vec3d)) == 0;
    }
    differing += same ? 0 : 1;
    wall_contact_steps += grid.wall_contact_count() > 0 ? 1 : 0;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(wall_contact_steps, total);
}

// Float: finite, and close to the host's float run. The two round differently (fused
// multiply-adds, ~6e-8 relative per operation) and contacts amplify it by up to ~1e4 over the
// horizon: 1e-3 of the particle size is ~100x that and still far below a wrong force.
TEST(GpuStep, FloatRunIsFiniteAndClose) {
  SKIP_WITHOUT_GPU();
  const Agreement a = compare_steps<float>(twenty_polyhedra_volume("float"), 0.01);
  EXPECT_TRUE(a.finite);
  if (max_steps() <= 0) EXPECT_GE(a.contact_steps, 100);
  EXPECT_LT(a.position_error, 1e-3);
}

// Only the stages of the scene's effects allocate: no contacts, no rotation: no force-law arrays,
// no torque, no bounding radius (as the host step's plan).
TEST(GpuStep, AllocatesOnlyThePlansArrays) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(std::string("time: {step: 1.0e-3, end: 1.0e-2}\n") + kGlass + R"(
templates:
  ball: {sphere: 0.005, material: glass}
particles:
  - explicit:
      - {template: ball, position: [0, 0, 1], velocity: [1, 0, 0]}
effects:
  gravity: [0, 0, -9.81]
)");
  HostStep<double> host(scene);
  CudaStep<double> gpu(scene);
  EXPECT_EQ(gpu.allocated_arrays(), host.allocated_arrays());
  for (int k = 0; k < 10; ++k) host.step(), gpu.step();
  // Free fall: z = 1 - g t^2 / 2 exactly for the Verlet step; both within round-off.
  const double z = gpu.trajectory_rows()[0].position.z;
  EXPECT_NEAR(z, 1 - 0.5 * 9.81 * 0.01 * 0.01, 1e-12);
  EXPECT_NEAR(z, host.trajectory_rows()[0].position.z, 1e-15);
}

// Particles in a box shaken up and down (an oscillating wall, `motion: oscillation`: 1 mm at
// 50 Hz, 10 g), volume law with friction and rotation: the device reads the wall's velocity of
// each step's time (copied up with the placements) as the host's stage does, so the positions
// agree as in the other comparisons and the walls' work agrees to round-off (the same powers
// summed by the same trapezoid rule; 1e-9 relative leaves the margin of the positions').
TEST(GpuStep, ShakenBoxVolumeMatchesHost) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(std::string("time: {step: 2.0e-6, end: 2.0e-2}\n") + kGlass + R"(
templates:
  cube: {shape: "cube:0.01", material: glass}
  dodeca: {shape: "dodecahedron:0.012", material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.006, 0.001, 0.0065], velocity: [-0.3, 0, -0.2],
         orientation: {axis: [1, 0.3, 0], degrees: 25}}
      - {template: dodeca, position: [0.007, -0.002, 0.007], velocity: [0.1, 0.2, -0.3],
         orientation: {axis: [0, 1, 1], degrees: 40}}
      - {template: cube, position: [0.0, 0.009, 0.006], velocity: [0.2, -0.3, 0]}
walls:
  - box:
      min: [-0.015, -0.015, 0]
      max: [0.015, 0.015, 0.03]
      open_top: true
      material: glass
      motion:
        oscillation: {direction: [0, 0.6, 0.8], amplitude: 0.001, frequency: 50, start: 0.002,
                      cycles: 1}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)");
  expect_agreement(compare_steps<double>(scene, 0.01), 100);
  HostStep<double> host(scene);
  CudaStep<double> gpu(scene);
  long long steps = std::llround(scene.end_time / scene.time_step);
  if (max_steps() > 0) steps = std::min(steps, max_steps());
  for (long long k = 0; k < steps; ++k) host.step(), gpu.step();
  const double work = host.energy().ledger.wall_work;
  if (max_steps() <= 0) EXPECT_GT(std::abs(work), 0);
  EXPECT_NEAR(gpu.energy().ledger.wall_work, work, 1e-9 * std::abs(work) + 1e-15);
}

}  // namespace
}  // namespace talus
