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
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/run/production_run.hpp"
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

template <class Real>
void check_cuda_round_trip(const std::string& precision) {
  TempDir dir;
  const Scene scene = talus_test::write_restart_scene(dir.path, precision);
  CudaStep<Real> whole(scene), first(scene);
  for (int k = 0; k < 70; ++k) whole.step();
  for (int k = 0; k < 30; ++k) first.step();
  Checkpoint written;
  put_step_state(written, first.export_state());
  write_checkpoint(dir.path + "/state.bin", written);
  CudaStep<Real> second(scene);
  second.import_state(get_step_state<Real>(read_checkpoint(dir.path + "/state.bin")));
  for (int k = 0; k < 40; ++k) second.step();
  const StepState<Real> a = whole.export_state(), b = second.export_state();
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
