// The production step on the CUDA backend: the host step's stages (host_step.hpp) as kernels
// over device arrays, one thread per particle, per candidate pair or per (particle, wall), each
// calling the same TALUS_HD functions (particle_kernels.hpp, pair_kernels.hpp,
// wall_kernels.hpp). The broad phase is ContactPairsGpu on the step's own position arrays; the
// volume model's overlap runs with the workspace of each template pair's capacity (one launch
// per capacity the scene has); the tangential history lives on the device keyed by global ids
// (sorted keys, binary search, rebuilt from the touching pairs as on the host). Accumulation is
// deterministic, with no atomics: each contact is written to its own slot, then one thread per
// particle sums its contacts in pair order (a CSR of the sorted list), then its wall contacts
// in wall order, as the host does, so both backends agree to round-off.
//
// Host-facing: no CUDA types; the implementation (cuda_step.cu) exists only in CUDA builds
// (talus_cuda), where TALUS_HAVE_CUDA is defined.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solver/io/trajectory.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/any_step.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/walls/facet_grid.hpp"

namespace talus {

template <class Real>
class CudaStep {
 public:
  // As HostStep: the scene's initial particles (global id = index), copied to the device.
  // Throws StepNotSupported for what the step cannot simulate, std::runtime_error from CUDA.
  // `wall_search`: the facet grid, or brute force (the same results; for the benchmarks).
  explicit CudaStep(const Scene& scene, WallSearch wall_search = WallSearch::grid);
  ~CudaStep();
  CudaStep(const CudaStep&) = delete;
  CudaStep& operator=(const CudaStep&) = delete;

  // As HostStep::step and HostStep::evaluate_forces (the same errors, the same messages).
  void step();
  void evaluate_forces();

  double time() const;
  long long steps() const;
  const StepPlan& plan() const;
  int particle_count() const;

  // The device arrays that exist (names as HostStep's) and the device bytes the step holds.
  std::vector<std::string> allocated_arrays() const;
  std::size_t allocated_bytes() const;
  // Wall-clock seconds per stage (each stage synchronised at its end), indexed by Stage.
  const std::array<double, 9>& stage_seconds() const;
  std::size_t pair_contact_count() const;
  std::size_t wall_contact_count() const;
  // Wall w's force and torque about the origin at the last evaluation (the wall contacts are
  // downloaded and summed in double, in order, on the first call after an evaluation).
  Vec3d wall_force(int w) const;
  Vec3d wall_torque(int w) const;

  // Downloaded and computed as HostStep's (particle_rows etc.).
  std::vector<TrajectoryRow> trajectory_rows() const;
  double kinetic_energy() const;
  double bed_height(const Vec3d& gravity) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The CUDA step in the scene's precision, for ProductionSettings::make_step.
std::unique_ptr<AnyStep> make_cuda_step(const Scene& scene);

}  // namespace talus
