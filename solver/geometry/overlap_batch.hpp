// The overlap of many pose pairs of two templates on the GPU, one thread per pair (§2.3: "one
// thread is assigned to deal with one contact pair"), each with its own fixed workspace sized
// from the two templates. Host-facing: no CUDA types, so host code can include it; the
// implementation is in overlap_batch.cu and overlap_batch_kernels.cuh and exists only in CUDA
// builds (talus_cuda_overlap).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "solver/geometry/convex.hpp"
#include "solver/geometry/overlap.hpp"

namespace talus {

// How the batch kernel runs (one thread per pair in all three). Each builds the same polytope
// with the same arithmetic, so the results are identical; they differ only in where the data
// lives, and are kept selectable so that the benchmark shows what each step gains.
enum class OverlapBatchKernel : int {
  global_templates = 0,  // templates read from global memory; one workspace for all faces
  shared_templates = 1,  // templates staged in each block's shared memory
  small_workspace = 2,   // staged, and a workspace of 3/8 of the planes first
  // small_workspace without the second copy of the overlap: the pairs the small workspace cannot
  // hold are deferred to a second launch with the full one.
  deferred_overflow = 3,
  // Two phases: a culling kernel (a mask of kept planes per pair), then a kernel that builds the
  // polytope from the mask with the small workspace, in pair order; deferred overflow.
  phased = 4,
  // phased, with the pairs sorted by their number of kept planes (CUB radix sort) between the
  // phases, and one polytope kernel per workspace size (8, 16, ... planes) over its range of
  // the sorted pairs, so that a warp's pairs have the same number of planes (the default).
  phased_sorted = 5,
};

template <class Real>
class OverlapBatchGpu {
 public:
  // Copies both templates (views of host arrays) to device memory.
  OverlapBatchGpu(const ConvexView<Real>& a, const ConvexView<Real>& b);
  ~OverlapBatchGpu();
  OverlapBatchGpu(const OverlapBatchGpu&) = delete;
  OverlapBatchGpu& operator=(const OverlapBatchGpu&) = delete;

  // Copies the pose pairs to the device, where they stay for repeated runs.
  void set_poses(const std::vector<Pose<Real>>& poses_a, const std::vector<Pose<Real>>& poses_b);
  // Computes every pair; returns the kernel time in milliseconds (CUDA events).
  double run(OverlapOptions options = OverlapOptions(),
             OverlapBatchKernel kernel = OverlapBatchKernel::phased_sorted);
  // The results of the last run, in pair order.
  std::vector<OverlapResult<Real>> results() const;

  int workspace_capacity() const;       // planes per pair the workspace holds
  std::size_t workspace_bytes() const;  // per pair (per thread, in local memory)
  // The workspace the small_workspace kernel tries first (3/8 of the full one).
  int small_workspace_capacity() const;
  std::size_t small_workspace_bytes() const;
  std::size_t pair_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace talus
