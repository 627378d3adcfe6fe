// Feeds on the CUDA step (solver/step/cuda/cuda_step.hpp): before a step's integrate_begin the
// scene's feed entries insert particles through the same Feeder calls, with the same inputs, as on
// the host step (host_step.hpp, itself compared with the reference solver in
// tests/reference/test_production_vs_reference.cpp, FeedIntoABoxLinear). In double and
// deterministic mode, stepped side by side with the host step: the same particle count after
// every step (and the count the feeds have due), the same contact counts, positions and
// velocities within a round-off tolerance. A feeding CUDA run interrupted in the middle of its
// feed and resumed from its exported state (or the runner's checkpoint) ends equal to the
// uninterrupted one bit for bit. Float runs insert the same particles as the host's. Skipped
// with the reason where no GPU is usable.
//
// TALUS_GPU_TEST_MAX_STEPS caps the steps (compute-sanitizer runs the kernels tens of times
// slower): the polyhedron scene inserts a particle every 10 steps from its first step, so the
// capped runs still append particles, grow the device arrays and rebuild the pair list.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"  // expect_same_state
#include "tests/support/feed_scenes.hpp"
#include "tests/support/gpu_skip.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;

long long max_steps() {
  const char* cap = std::getenv("TALUS_GPU_TEST_MAX_STEPS");
  return cap ? std::atoll(cap) : -1;
}

long long capped(long long steps) {
  return max_steps() > 0 ? std::min(steps, max_steps()) : steps;
}

// A fresh directory under the system's temporary directory, removed at the end.
struct TempDir {
  std::string path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "talus_gpu_feed_XXXXXX").string();
    path = mkdtemp(pattern.data()) ? pattern : "";
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

const char* const kGlass = R"(
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
)";

// ProductionVsReference.FeedIntoABoxLinear's scene (same text, same seed): one ball, then 2000
// balls per second for 10 ms (20, one every 100 steps) thrown down at 0.5 m/s into a box, the
// linear model with friction and rotation; 30 ms (6000 steps), through the landing's contacts.
std::string ball_feed_yaml() {
  return std::string("time: {step: 5.0e-6, end: 0.03}\n") + kGlass + testing::kBallFeedScene;
}

// Two feeds into one box, polyhedra under the volume model with friction and rotation: 20 cubes
// (one every 10 steps, from the first step) thrown right and down, and 15 icosahedra (one every
// 13 to 14 steps) thrown left and down, both for 1 ms, so that some steps insert from both
// feeds (the second feeder keeps off the first's new particles) and the device arrays grow
// several times; the two streams meet each other, the floor and the side walls within the
// 10 ms (2000 steps), with pair and wall histories carried over every rebuild the insertions
// force. The region is large enough (the bounding spheres fill a quarter of it at most) that no
// particle is deferred: the count after each step is what the feeds have due.
std::string polyhedron_feed_yaml(const std::string& precision = "double",
                                 const std::string& end = "0.01") {
  return "time: {step: 5.0e-6, end: " + end + "}\nprecision: " + precision + "\n" + kGlass + R"(
templates:
  cube: {shape: "cube:0.005", material: glass}
  ico: {shape: "icosahedron:0.006", material: glass}
walls:
  - box: {min: [-0.025, -0.025, 0], max: [0.025, 0.025, 0.05], material: glass}
particles:
  - explicit:
      - {template: cube, position: [0, 0, 0.0026]}
  - feed:
      template: cube
      region: {box: {min: [-0.022, -0.022, 0.005], max: [0.022, 0.022, 0.035]}}
      rate: 20000
      stop: 0.001
      velocity: [1.0, 0, -1.5]
      seed: 3
  - feed:
      template: ico
      region: {box: {min: [-0.022, -0.022, 0.005], max: [0.022, 0.022, 0.035]}}
      rate: 15000
      stop: 0.001
      velocity: [-1.0, 0.5, -1.5]
      seed: 4
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)";
}

Scene scene_from(const std::string& yaml) {
  return parse_scene(yaml, "feed.yaml", ".");
}

// The count after a step that started at `time`: the initial particles and what every feed had
// due then (no feed of these scenes defers a particle).
struct DueCount {
  long long initial = 0;
  std::vector<Feeder> feeds;
  explicit DueCount(const Scene& scene)
      : initial(static_cast<long long>(initial_particles(scene).size())) {
    for (std::size_t f = 0; f < scene.feeds.size(); ++f)
      feeds.emplace_back(scene, static_cast<int>(f));
  }
  long long at(double time) const {
    long long count = initial;
    for (const Feeder& feed : feeds) count += feed.due(time);
    return count;
  }
};

struct FeedAgreement {
  long long steps = 0;
  long long count_mismatches = 0;  // the GPU's count differs from the host's or from the due
  long long contact_mismatches = 0;
  long long pair_contact_steps = 0, wall_contact_steps = 0;
  long long list_builds = 0;
  long long insertion_steps = 0, unbuilt_insertions = 0;  // the list not rebuilt after inserting
  int final_count = 0;
  double position_error = 0;  // max |x_gpu - x_host| / max(|x_host|, length)
  double velocity_error = 0;  // max |v_gpu - v_host| / (|v_host| + speed)
  bool same_ids = true, finite = true;
};

// Both steps side by side over the scene (capped), every particle compared after every step.
// `length`, `speed`: the particles' size and the feed's speed, the scales of the errors of a
// particle near the origin or at rest.
template <class Real>
FeedAgreement compare_feeding(const Scene& scene, double length, double speed) {
  HostStep<Real> host(scene, 1);
  CudaStep<Real> gpu(scene);
  const long long total = capped(std::llround(scene.end_time / scene.time_step));
  const DueCount due(scene);
  FeedAgreement a;
  for (long long k = 0; k < total; ++k) {
    const double start = host.time();
    const int count_before = gpu.particle_count();
    const long long builds_before = gpu.pair_list_builds();
    host.step();
    gpu.step();
    ++a.steps;
    const int count = gpu.particle_count();
    a.count_mismatches += count != host.particle_count() || count != due.at(start) ? 1 : 0;
    if (count > count_before && scene.effects.contact) {
      ++a.insertion_steps;
      a.unbuilt_insertions += gpu.pair_list_builds() > builds_before ? 0 : 1;
    }
    a.contact_mismatches += host.pair_contact_count() != gpu.pair_contact_count() ||
                                    host.wall_contact_count() != gpu.wall_contact_count()
                                ? 1
                                : 0;
    a.pair_contact_steps += host.pair_contact_count() > 0 ? 1 : 0;
    a.wall_contact_steps += host.wall_contact_count() > 0 ? 1 : 0;
    const std::vector<TrajectoryRow> h = host.trajectory_rows(), g = gpu.trajectory_rows();
    if (h.size() != g.size()) continue;  // counted above
    for (std::size_t i = 0; i < h.size(); ++i) {
      a.same_ids = a.same_ids && g[i].id == h[i].id && g[i].template_index == h[i].template_index;
      a.finite = a.finite && std::isfinite(g[i].position.x) && std::isfinite(g[i].position.y) &&
                 std::isfinite(g[i].position.z);
      a.position_error = std::max(a.position_error, norm(g[i].position - h[i].position) /
                                                        std::max(norm(h[i].position), length));
      a.velocity_error = std::max(
          a.velocity_error, norm(g[i].velocity - h[i].velocity) / (norm(h[i].velocity) + speed));
    }
  }
  a.final_count = gpu.particle_count();
  a.list_builds = gpu.pair_list_builds();
  std::printf(
      "steps %lld  particles %d  count mismatches %lld  contact mismatches %lld  pair contact "
      "steps %lld  wall contact steps %lld  list builds %lld  insertion steps %lld  position "
      "error %.3g  velocity error %.3g\n",
      a.steps, a.final_count, a.count_mismatches, a.contact_mismatches, a.pair_contact_steps,
      a.wall_contact_steps, a.list_builds, a.insertion_steps, a.position_error, a.velocity_error);
  return a;
}

// Double, as tests/gpu/test_step_gpu.cpp: the GPU runs the host's functions with the host's
// summation order, and the feeders get the same positions (the host's and the GPU's agree to
// ~1e-14, far from deciding whether a random place is free); what differs is nvcc's fused
// multiply-adds, ~1e-16 relative per operation, which contacts amplify by far less than 1e5
// over these horizons (on the host, a 1e-16 relative shift of one particle grows to 1e-13 in
// the positions and 1.3e-12 in the velocities of the ball scene, 3e-15 and 3e-14 in the
// polyhedron scene; the reference solver agrees with the host step on the ball scene to 2e-14
// and 3e-13): 1e-10 keeps a margin of 1000. Velocities carry the stiff contact force (an error dx
// in x gives about dx sqrt(k / m), ~6e3 / s, in v), so they get 100 times more, as the reference
// comparison does. A fed particle without its body forces at once is off by g dt / 2 =
// 2.5e-5 m/s from its first step, 5e-5 of the speed scale: caught.
constexpr double kPositionTolerance = 1e-10;
constexpr double kVelocityTolerance = 1e-8;

void expect_double_agreement(const FeedAgreement& a) {
  EXPECT_EQ(a.count_mismatches, 0);
  // Every step that inserted rebuilt the pair list (the new particles had no candidates).
  EXPECT_EQ(a.unbuilt_insertions, 0);
  EXPECT_EQ(a.contact_mismatches, 0);
  EXPECT_TRUE(a.same_ids);
  EXPECT_TRUE(a.finite);
  EXPECT_LT(a.position_error, kPositionTolerance);
  EXPECT_LT(a.velocity_error, kVelocityTolerance);
}

TEST(FeedGpu, FeedIntoABoxLinearMatchesHost) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(ball_feed_yaml());
  const FeedAgreement a = compare_feeding<double>(scene, 0.003, 0.5);
  expect_double_agreement(a);
  if (max_steps() <= 0) {
    EXPECT_EQ(a.final_count, 21);  // the initial ball and floor(2000 * 0.01) fed
    // The landing: wall contacts, and pair contacts among the fed balls on the floor (the host
    // step sees them in 1248 and 915 of the 6000 steps; the GPU's counts were compared above).
    EXPECT_GE(a.wall_contact_steps, 500);
    EXPECT_GE(a.pair_contact_steps, 500);
  }
}

TEST(FeedGpu, TwoPolyhedronFeedsVolumeModelMatchHost) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(polyhedron_feed_yaml());
  const FeedAgreement a = compare_feeding<double>(scene, 0.005, 1.0);
  expect_double_agreement(a);
  // Cubes are due at steps 10, 20, ..., icosahedra at 14, 27, 40, ...: insertions even within
  // the first 60 steps (the sanitizer's cap).
  EXPECT_GE(a.insertion_steps, std::min<long long>(a.steps / 10, 20));
  if (max_steps() <= 0) {
    EXPECT_EQ(a.final_count, 1 + 20 + 15);
    // The host step sees wall contacts in 1099 and pair contacts in 1351 of the 2000 steps.
    EXPECT_GE(a.wall_contact_steps, 500);
    EXPECT_GE(a.pair_contact_steps, 500);
  }
}

// Float: the same particles inserted at the same steps as the host's float step (a place is
// accepted when the bounding spheres keep apart; the two backends' positions differ by round-off,
// ~1e-7 relative, which decides nothing unless a random place grazes a sphere to that precision),
// finite, and close: as GpuStep.FloatRunIsFiniteAndClose, rounding of ~6e-8 per operation
// amplified by contacts by up to ~1e4 stays within 1e-3 of the particle size.
TEST(FeedGpu, FloatFeedingInsertsTheSameParticles) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(polyhedron_feed_yaml("float"));
  const FeedAgreement a = compare_feeding<float>(scene, 0.005, 1.0);
  EXPECT_EQ(a.count_mismatches, 0);
  EXPECT_TRUE(a.same_ids);
  EXPECT_TRUE(a.finite);
  EXPECT_LT(a.position_error, 1e-3);
  if (max_steps() <= 0) EXPECT_EQ(a.final_count, 1 + 20 + 15);
}

// The step's state in the middle of the feed (some particles inserted, more due) through a
// checkpoint file: the resumed step inserts the same particles at the same steps (the feeders'
// states travel in feed_states) and ends equal to the uninterrupted one, bit for bit. The
// resumed step builds its pair list at its first step where the uninterrupted one may keep an
// older one; forces are computed per candidate and summed per particle in pair order, so that
// does not change a bit (tests/gpu/test_restart_gpu.cpp).
template <class Real>
void check_feeding_round_trip(const std::string& precision) {
  TempDir dir;
  const Scene scene = scene_from(polyhedron_feed_yaml(precision));
  const long long total = capped(2000), cut = std::min<long long>(total / 2, 150);
  CudaStep<Real> whole(scene), first(scene);
  for (long long k = 0; k < total; ++k) whole.step();
  for (long long k = 0; k < cut; ++k) first.step();
  // Mid-feed: more than the initial particle, fewer than the feeds will insert.
  EXPECT_GT(first.particle_count(), 1);
  EXPECT_LT(first.particle_count(), 36);
  Checkpoint written;
  put_step_state(written, first.export_state());
  write_checkpoint(dir.path + "/state.bin", written);
  const StepState<Real> state = get_step_state<Real>(read_checkpoint(dir.path + "/state.bin"));
  EXPECT_EQ(state.feed_states.size(), 2u);
  CudaStep<Real> second(scene);
  second.import_state(state);
  EXPECT_EQ(second.particle_count(), first.particle_count());
  for (long long k = cut; k < total; ++k) second.step();
  EXPECT_EQ(second.particle_count(), whole.particle_count());
  const StepState<Real> a = whole.export_state(), b = second.export_state();
  talus_test::expect_same_state(a, b);
  EXPECT_EQ(a.feed_states, b.feed_states);
  if (max_steps() <= 0) {
    EXPECT_EQ(a.count, 36);
    EXPECT_GT(a.pair_keys.size() + a.wall_keys.size(), 0u);  // histories went through the cut
  }

  // A state without the feeds' (another scene's) does not fit.
  StepState<Real> lacking = first.export_state();
  lacking.feed_states.clear();
  CudaStep<Real> third(scene);
  EXPECT_THROW(third.import_state(lacking), CheckpointError);
}

TEST(FeedGpu, FeedingStateRoundTripIsExactDouble) {
  SKIP_WITHOUT_GPU();
  check_feeding_round_trip<double>("double");
}

TEST(FeedGpu, FeedingStateRoundTripIsExactFloat) {
  SKIP_WITHOUT_GPU();
  check_feeding_round_trip<float>("float");
}

// A host state taken in the middle of the feed goes on on the device: the same particles are
// inserted afterwards, and the backends agree to round-off (as tests/gpu/test_restart_gpu.cpp's
// StateMovesBetweenBackends).
TEST(FeedGpu, FeedingStateMovesFromHostToDevice) {
  SKIP_WITHOUT_GPU();
  const Scene scene = scene_from(polyhedron_feed_yaml());
  const long long cut = capped(100), more = capped(200);
  HostStep<double> host(scene, 1);
  for (long long k = 0; k < cut; ++k) host.step();
  CudaStep<double> device(scene);
  device.import_state(host.export_state());
  EXPECT_EQ(device.particle_count(), host.particle_count());
  talus_test::expect_same_state(host.export_state(), device.export_state());
  for (long long k = 0; k < more; ++k) {
    host.step();
    device.step();
    ASSERT_EQ(device.particle_count(), host.particle_count()) << "step " << host.steps();
  }
  // The feed changes the graph's nodes between captures: such a capture is made into a new
  // executable graph, never offered to the driver as an update it refuses (an API error under
  // compute-sanitizer: 2 in this test at 66a818d, on an H200).
  EXPECT_EQ(device.graph_counts().refused_updates, 0);
  EXPECT_GE(device.graph_counts().instantiations, 1);
  const std::vector<TrajectoryRow> a = host.trajectory_rows(), b = device.trajectory_rows();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_LT(norm(a[i].position - b[i].position) / std::max(norm(a[i].position), 0.005),
              kPositionTolerance);
  }
}

// The runner on the CUDA step with feeds: stopped in the middle of the feed, resumed from its
// checkpoint (feeds.states), every frame and probe row equal to the uninterrupted run's.
TEST(FeedGpu, InterruptedCudaFeedingRunResumesExactly) {
  SKIP_WITHOUT_GPU();
  TempDir dir;
  const long long steps = capped(400), stop_at = std::min<long long>(steps / 2, 150);
  char end[32];
  std::snprintf(end, sizeof(end), "%.17g", steps * 5.0e-6);
  const auto write_scene = [&](const std::string& root) {
    fs::create_directories(root);
    std::ofstream(root + "/scene.yaml")
        << polyhedron_feed_yaml("double", end)
        << "outputs:\n  trajectories: {every: 10, directory: frames}\n"
           "  probes: {every: 5, file: probes.csv, quantities: [kinetic_energy, contact_count, "
           "wall_forces]}\n  checkpoint: {every: 1000, keep: 2}\n";
    return load_scene(root + "/scene.yaml");
  };
  const auto run = [](const Scene& scene, const std::string& root,
                      std::shared_ptr<const Checkpoint> resume, std::function<bool()> stop) {
    ProductionSettings settings;
    settings.output_root = root;
    settings.make_step = make_cuda_step;
    settings.resume = std::move(resume);
    settings.stop_requested = std::move(stop);
    return run_production(scene, settings);
  };
  const std::string whole = dir.path + "/whole", cut = dir.path + "/cut";
  const ProductionReport full = run(write_scene(whole), whole, nullptr, nullptr);
  EXPECT_EQ(full.backend, "cuda");
  EXPECT_EQ(full.steps, steps);
  const Scene scene = write_scene(cut);
  int asked = 0;
  const ProductionReport stopped = run(scene, cut, nullptr, [&] { return ++asked > stop_at; });
  ASSERT_TRUE(stopped.interrupted);
  const ResumePoint point = read_resume_point(cut + "/checkpoints");
  EXPECT_EQ(point.step, stop_at);
  EXPECT_EQ(point.backend, "cuda");
  EXPECT_NE(point.checkpoint->text("feeds.states"), "");
  const ProductionReport resumed = run(scene, point.output_root, point.checkpoint, nullptr);
  EXPECT_EQ(resumed.particles, full.particles);
  const auto bytes_of = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  for (long long step = 0; step <= steps; step += 10) {
    const std::string name = "/frames/" + trajectory_file_name(step);
    const std::string x = bytes_of(whole + name), y = bytes_of(cut + name);
    EXPECT_FALSE(x.empty()) << name;
    EXPECT_TRUE(x == y) << name;
  }
  const std::string x = bytes_of(whole + "/probes.csv"), y = bytes_of(cut + "/probes.csv");
  EXPECT_FALSE(x.empty());
  EXPECT_TRUE(x == y);
}

}  // namespace
}  // namespace talus
