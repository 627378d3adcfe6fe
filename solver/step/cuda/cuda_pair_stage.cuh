// The CUDA step's pair contacts (stage pair_contacts): every slot of the pair list through its
// contact geometry, the force law with the slot's history, and the force (kept in the slot for
// the deterministic accumulation, or added to both particles by atomics). Polyhedron pairs of
// the volume model with at most 64 faces together go through the phased path: a culling kernel
// (GJK, then the kept planes as a 64-bit mask), the slots sorted by their number of kept planes,
// and one polytope kernel per workspace size (8, 16, 32, 64 planes), so that a warp's pairs do
// similar work in little local memory; the few pairs whose hull overruns the small workspace are
// deferred to the whole-pair kernel. Other pairs (spheres, the linear model, larger templates)
// run whole in one thread with the workspace of their templates' capacity, one launch per
// capacity the scene has. Included only from .cu files.
#pragma once

#include <array>
#include <vector>

#include "solver/geometry/phased_overlap.cuh"
#include "solver/step/cuda/cuda_pair_list.cuh"

namespace talus {

template <class Real>
class DevicePairStage {
 public:
  // The workspace capacities come from the scene's templates (host views, for their counts of
  // faces) under the scene's contact law.
  DevicePairStage(DeviceStepShared<Real>& shared, DevicePairList<Real>& list,
                  const std::vector<BodyProperties<Real>>& host_bodies);
  ~DevicePairStage();
  DevicePairStage(const DevicePairStage&) = delete;
  DevicePairStage& operator=(const DevicePairStage&) = delete;

  // Every slot of the list. spring_dt: 0 in the evaluation at t = 0, else the step. A pair whose
  // geometry is degenerate raises flag degenerate_pair, which the step reads at its end
  // (check_flags).
  void compute(Real spring_dt) { compute(spring_dt, 0, list_.candidates(), true); }
  // The slots first .. first + count only (a decomposed step: the inner slots while the ghosts'
  // states travel, then the rest, DevicePairList::inner_candidates). `wait`: false when nothing
  // may make the host wait for the device (the phased path's ranges and deferred pairs then
  // read on the device, as in a graph step). The first range of a step starts at slot 0.
  void compute(Real spring_dt, int first, int count, bool wait);
  // The flags read at the end of the step (DeviceFlags::read_all): throws std::runtime_error
  // naming the two particles when a pair's geometry was degenerate; keeps the touching count.
  void check_flags(const std::array<int, flags>& all);

  // Pairs touching at the last evaluation (read from the device on the first call after it, if
  // check_flags has not given it).
  long long touching_count() const;
  // Device bytes of the phased path's masks, keys, orders and deferral list.
  std::size_t bytes() const;

 private:
  // Templated on the scene's contact law (contact/laws/), which compute picks once per call.
  template <class Law>
  void launch_all(int candidates, bool wait);
  template <class Law>
  void launch_pairs(int capacity, const int* slots, int n, const int* count_at);
  template <class Law, int Capacity>
  void launch_pairs(const int* slots, int n, const int* count_at);
  template <class Law, int Cap>
  void launch_polytopes(const PhasedBuckets* buckets, int slots, cudaStream_t stream);
  template <class Law>
  void compute_phased(int n, bool wait);

  DeviceStepShared<Real>& shared_;
  DevicePairList<Real>& list_;
  std::vector<int> capacities_;  // the workspace capacities of the scene's template pairs
  bool phased_ = false;
  Real spring_dt_ = 0;
  int first_ = 0;  // the range's first slot (compute)
  mutable long long contact_count_ = 0;
  mutable bool contact_count_ready_ = true;
  // The phased path's per-slot masks, keys, orders and deferral list (phased_overlap.cuh).
  PhasedOverlapScratch scratch_;
  // One stream per polytope workspace size (8, 16, 32, 64 planes), so the sizes run together.
  std::array<cudaStream_t, kPhasedSizes> streams_{};
  // Their start after the sort on the step's stream, and the step's stream waiting for them.
  cudaEvent_t fork_ = nullptr;
  std::array<cudaEvent_t, kPhasedSizes> joins_{};
};

}  // namespace talus
