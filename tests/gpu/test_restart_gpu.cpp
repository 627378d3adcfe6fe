// Restart on the CUDA step (CudaStep::export_state/import_state, the runner's checkpoints): the
// host tests of tests/step/test_restart.cpp on the device. The scene (tests/step/restart_scene.hpp)
// has friction, rotation, pair contacts, a turning drum and a moving lid, and no feed (feeding
// runs: tests/gpu/test_feed_gpu.cpp). A resumed step or run equals the uninterrupted one on
// the same backend bit for bit in deterministic mode: the pair list a resumed step builds at its
// first step holds other candidates than the uninterrupted one's kept list, but the forces are
// computed per candidate and summed per particle in pair order, so the list's age does not
// change them; and a state exported by one backend is taken by the other.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/run/production_run.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/support/gpu_skip.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the system's temporary directory, removed at the end.
struct TempDir {
  std::string path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "talus_gpu_restart_XXXXXX").string();
    path = mkdtemp(pattern.data()) ? pattern : "";
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

// A step of `scene` that resumes `first`'s state through a checkpoint file in `dir`.
template <class Real>
std::unique_ptr<CudaStep<Real>> resumed(const CudaStep<Real>& first, const Scene& scene,
                                        const std::string& dir) {
  Checkpoint written;
  put_step_state(written, first.export_state());
  write_checkpoint(dir + "/state.bin", written);
  auto second = std::make_unique<CudaStep<Real>>(scene);
  second->import_state(get_step_state<Real>(read_checkpoint(dir + "/state.bin")));
  return second;
}

template <class Real>
void check_cuda_round_trip(const std::string& precision) {
  TempDir dir;
  const Scene scene = talus_test::write_restart_scene(dir.path, precision);
  CudaStep<Real> whole(scene), first(scene);
  for (int k = 0; k < 70; ++k) whole.step();
  for (int k = 0; k < 30; ++k) first.step();
  const std::unique_ptr<CudaStep<Real>> second = resumed(first, scene, dir.path);
  for (int k = 0; k < 40; ++k) second->step();
  const StepState<Real> a = whole.export_state(), b = second->export_state();
  EXPECT_GT(a.pair_keys.size(), 0u);
  EXPECT_GT(a.wall_keys.size(), 0u);
  talus_test::expect_same_state(a, b);
}

TEST(RestartGpu, CudaStepStateRoundTripIsExactDouble) {
  SKIP_WITHOUT_GPU();
  check_cuda_round_trip<double>("double");
}

TEST(RestartGpu, CudaStepStateRoundTripIsExactFloat) {
  SKIP_WITHOUT_GPU();
  check_cuda_round_trip<float>("float");
}

// A bed at rest resumed: nine stacks of two cubes on a floor under gravity, every cube touching
// the floor or the cube below it (a pair and a wall contact with friction history each), and
// no particle moving more than a few micrometres. The resumed step's pair list mirrors the
// checkpoint's reference for the whole run (nothing moves far enough to rebuild: one build, the
// import's), and its steps still run as graphs (DevicePairList::steady; predict_move bounds the
// move from both references), to the uninterrupted run's bits. Before, a mirroring list kept
// every step of such a run stage by stage: the fixed bed's resumed sittings took no graph step.
std::string bed_at_rest_yaml() {
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "time: {step: 2.0e-5, end: 1.0}\nprecision: double\nmaterials:\n"
          "  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,\n"
          "          restitution: 0.5}\n"
          "templates:\n  box: {shape: \"cuboid:0.01,0.01,0.01\", material: glass}\n"
          "particles:\n  - explicit:\n";
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      // Each cube 1 um into the floor or the cube below: touching from the first step.
      for (const double z : {0.005 - 1e-6, 0.015 - 2e-6})
        yaml << "      - {template: box, position: [" << 0.0102 * i << ", " << 0.0102 * j << ", "
             << z << "]}\n";
    }
  }
  yaml << "walls:\n  - plane: {name: floor, point: [0, 0, 0], normal: [0, 0, 1], size: 0.1,\n"
          "              material: glass}\n"
          "effects:\n  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n"
          "  rotation: true\n";
  return yaml.str();
}

TEST(RestartGpu, ResumedBedAtRestTakesGraphStepsWithTheSameBits) {
  SKIP_WITHOUT_GPU();
  TempDir dir;
  const std::string path = dir.path + "/scene.yaml";
  std::ofstream(path) << bed_at_rest_yaml();
  const Scene scene = load_scene(path);
  CudaStep<double> whole(scene), first(scene);
  for (int k = 0; k < 160; ++k) whole.step();
  for (int k = 0; k < 60; ++k) first.step();
  const std::unique_ptr<CudaStep<double>> second = resumed(first, scene, dir.path);
  for (int k = 0; k < 100; ++k) second->step();
  // 18 cubes: 9 wall contacts and 9 pair contacts while the stacks stand.
  EXPECT_EQ(second->pair_contact_count(), 9u);
  EXPECT_EQ(second->wall_contact_count(), 9u);
  EXPECT_EQ(second->pair_list_builds(), 1);  // the import's: the mirror held to the end
  // The first resumed step builds the list (not a graph step) and predicts the second's move;
  // every later step is a graph step unless the prediction came within 0.9 of the rebuild
  // distance, which micrometres of motion against a skin of a millimetre never do.
  EXPECT_EQ(second->graph_counts().steps, 99);
  talus_test::expect_same_state(whole.export_state(), second->export_state());
}

// A host checkpoint goes on on the device and the other way round: the same arrays and stores,
// so each step continues (within the backends' round-off agreement, not bit for bit).
TEST(RestartGpu, StateMovesBetweenBackends) {
  SKIP_WITHOUT_GPU();
  TempDir dir;
  const Scene scene = talus_test::write_restart_scene(dir.path);
  HostStep<double> host(scene, 1);
  for (int k = 0; k < 30; ++k) host.step();
  CudaStep<double> device(scene);
  device.import_state(host.export_state());
  const StepState<double> back = device.export_state();
  EXPECT_EQ(back.pair_keys.size(), host.export_state().pair_keys.size());
  talus_test::expect_same_state(host.export_state(), back);
  for (int k = 0; k < 10; ++k) host.step(), device.step();
  const std::vector<TrajectoryRow> a = host.trajectory_rows(), b = device.trajectory_rows();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    // As tests/gpu/test_step_gpu.cpp: the backends agree to round-off, 1e-10 relative.
    EXPECT_NEAR(a[i].position.x, b[i].position.x, 1e-10 * (1 + std::abs(a[i].position.x)));
    EXPECT_NEAR(a[i].position.z, b[i].position.z, 1e-10 * (1 + std::abs(a[i].position.z)));
  }
}

// The runner on the CUDA step: stopped at step 57, resumed from its checkpoint, every frame and
// probe row equal to the uninterrupted run's.
TEST(RestartGpu, InterruptedCudaRunResumesExactly) {
  SKIP_WITHOUT_GPU();
  TempDir dir;
  const std::string whole = dir.path + "/whole", cut = dir.path + "/cut";
  const auto run = [](const Scene& scene, const std::string& root,
                      std::shared_ptr<const Checkpoint> resume, std::function<bool()> stop) {
    ProductionSettings settings;
    settings.output_root = root;
    settings.make_step = make_cuda_step;
    settings.resume = std::move(resume);
    settings.stop_requested = std::move(stop);
    return run_production(scene, settings);
  };
  run(talus_test::write_restart_scene(whole), whole, nullptr, nullptr);
  const Scene scene = talus_test::write_restart_scene(cut);
  int asked = 0;
  const ProductionReport stopped = run(scene, cut, nullptr, [&] { return ++asked > 57; });
  ASSERT_TRUE(stopped.interrupted);
  const ResumePoint point = read_resume_point(cut + "/checkpoints");
  EXPECT_EQ(point.step, 57);
  EXPECT_EQ(point.backend, "cuda");
  run(scene, point.output_root, point.checkpoint, nullptr);
  for (int step = 0; step <= 120; ++step) {
    const std::string name = "/frames/" + trajectory_file_name(step);
    std::ifstream a(whole + name), b(cut + name);
    const std::string x((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
    const std::string y((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
    EXPECT_FALSE(x.empty()) << name;
    EXPECT_TRUE(x == y) << name;
  }
  std::ifstream a(whole + "/probes.csv"), b(cut + "/probes.csv");
  const std::string x((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
  const std::string y((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(x == y);
}

}  // namespace
}  // namespace talus
