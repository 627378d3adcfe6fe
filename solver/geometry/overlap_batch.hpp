// The overlap of many pose pairs of two templates on the GPU, one thread per pair (§2.3: "one
// thread is assigned to deal with one contact pair"), each with its own fixed workspace sized
// from the two templates. Host-facing: no CUDA types, so host code can include it; the
// implementation is in overlap_batch.cu and exists only in CUDA builds (talus_cuda).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "solver/geometry/convex.hpp"
#include "solver/geometry/overlap.hpp"

namespace talus {

// True when a CUDA device can be used; otherwise `reason` (if given) says why not.
bool cuda_device_available(std::string* reason = nullptr);

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
  double run(OverlapOptions options = OverlapOptions());
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
