// The overlap of many pose pairs of two templates on the GPU, one thread per pair (§2.3: "one
// thread is assigned to deal with one contact pair"), each with its own fixed workspace sized
// from the two templates: what the overlap benchmark (bench_overlap_gpu) times and the GPU
// geometry tests compare with the host. The step has its own kernels over its pair list
// (solver/step/cuda/), built from the same device functions. Host-facing: no CUDA types, so host
// code can include it; the implementation is in overlap_batch.cu and overlap_batch_kernels.cuh.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "solver/geometry/convex.hpp"
#include "solver/geometry/overlap.hpp"

namespace talus {

// How run() computes. phased (the default): a culling kernel (a mask of kept planes a pair), the
// pairs sorted by their number of kept planes, one polytope kernel per workspace size (8, 16,
// ... planes) over its range of the sorted pairs and the vertex enumeration alone for the
// fewest, the pairs a workspace cannot hold deferred to a last launch; templates with more than
// 64 faces together (or too large for shared memory) go whole. whole: each pair's whole overlap
// in one kernel (overlap_polyhedra), as the deferred pairs go. Both give the same results, bit for
// bit (the GPU tests assert it).
enum class OverlapBatchPath : int { phased = 0, whole = 1 };

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
             OverlapBatchPath path = OverlapBatchPath::phased);
  // The results of the last run, in pair order.
  std::vector<OverlapResult<Real>> results() const;

  int workspace_capacity() const;       // planes per pair the workspace holds
  std::size_t workspace_bytes() const;  // per pair (per thread, in local memory)
  std::size_t pair_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace talus
