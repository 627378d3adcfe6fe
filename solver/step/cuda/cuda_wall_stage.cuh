// The CUDA step's wall contacts (stage wall_contacts). The host stage (WallContactStage) keeps
// locating the walls (present facets, transforms, opening outlets); the device holds each wall's
// facet grid and corners, uploaded once: a static wall's corners never change, a moving wall's
// are placed each step by a kernel from its mesh-frame corners. One thread per (particle, wall)
// keeps only the touching records (appended, then sorted into the host's wall-major order, with
// an index per particle and wall for the accumulation), and the touching contacts' histories
// become the next step's store. Included only from .cu files.
#pragma once

#include <memory>
#include <vector>

#include "solver/step/cuda/cuda_step_common.cuh"
#include "solver/step/host/wall_stage.hpp"

namespace talus {

// A facet to clip: its corners and the (particle, wall) thread k = w * count + i it belongs to
// (cuda_wall_stage.cu).
template <class Real>
struct WallCandidate {
  Vec3<Real> a, b, c;
  int owner;
};

// A wall's placement for one evaluation, as the host locates it: its present facets and the
// transform of its view, and a moving wall's corner transform (wall_transform, in double). The
// host writes them into pinned memory and one copy takes them to the device, so that a graph
// launch (cuda_step_impl.cuh, "Graph steps") repeats the copy with each step's values.
template <class Real>
struct WallPlacement {
  int count = 0;
  Quat<Real> rotation;
  Vec3<Real> translation;
  Quatd corner_rotation;
  Vec3d corner_translation;
};

template <class Real>
class DeviceWallStage {
 public:
  // `host` has made the scene's checks; its walls are placed at `time` and uploaded.
  DeviceWallStage(DeviceStepShared<Real>& shared, std::unique_ptr<WallContactStage<Real>> host,
                  double time);
  ~DeviceWallStage();
  DeviceWallStage(const DeviceWallStage&) = delete;
  DeviceWallStage& operator=(const DeviceWallStage&) = delete;

  void open_outlets(double time) { host_->open_outlets(time); }
  // The walls at `time`, then every (particle, wall). Throws std::runtime_error naming the
  // particle and the wall when a facet's clipping fails. While the step is captured
  // (DeviceStepShared::graph_mode): one pass that reads nothing back (compute_in_graph).
  void compute(Real spring_dt, double time);

  // Graph steps. Before a capture: room for a record per (particle, wall) and the history store
  // ready for the graph; false when the scene is too large for that room (it then runs stage by
  // stage). stage_placement: the walls' placements at `time` into pinned memory, before each
  // launch of the graph. after_graph: the counts from the step's flags (throws as compute for a
  // failed clipping). recover: after a launch whose facets overran their room (the flag
  // wall_candidates past it), the stage again stage by stage with room for `facets`.
  bool prepare_graph();
  void stage_placement(double time);
  void after_graph(const std::array<int, flags>& all);
  void recover(Real spring_dt, double time, int facets);
  // The room for facets to clip (a graph step's abort test compares with it).
  int clip_capacity() const { return static_cast<int>(candidates_.size()); }

  int contact_count() const { return contact_count_; }
  int walls() const { return static_cast<int>(wall_views_.size()); }
  // The touching records in wall-major order, and each (particle, wall)'s place among them
  // (index w * particles + i; -1: apart).
  const WallContactRecord<Real>* contacts() const { return contacts_.data(); }
  const int* slots() const { return wall_slot_.data(); }
  // Wall w's force and torque about the origin at the last evaluation (downloaded and summed in
  // double, in order, on the first call after it).
  // Adds the last evaluation's wall contacts to the energy sums (cuda_step_common.cuh).
  void add_energy_sums(double* sums) const;
  Vec3d force(int w) const;
  Vec3d torque(int w) const;
  std::size_t bytes() const;
  // The history store (the touching contacts of the last evaluation, sorted by key), and setting
  // it (a restart).
  void export_histories(std::vector<PairKey>& keys,
                        std::vector<ContactHistoryData<Real>>& histories) const;
  void import_histories(const std::vector<PairKey>& keys,
                        const std::vector<ContactHistoryData<Real>>& histories);
  // Decomposed (docs/parallel.md), at a rebuild: the store's entries of the particles among
  // `ids` (sorted global ids: those leaving for other ranks), chosen on the device; and the
  // arriving particles' entries merged into the store there, in key order, an entry whose key
  // the store holds already dropped (as sorted_store does). Neither moves the whole store
  // through the host: at a million particles on a floor it holds tens of thousands of entries.
  void histories_with(const std::vector<long long>& ids, std::vector<PairKey>& keys,
                      std::vector<ContactHistoryData<Real>>& histories);
  void add_histories(const std::vector<PairKey>& keys,
                     const std::vector<ContactHistoryData<Real>>& histories);

 private:
  void upload(double time);
  void place(double time);
  void launch_kernels(Real spring_dt, const HistoryIn& old);
  void compute_in_graph(Real spring_dt);
  void grow_clip_room(int facets);
  void check_degenerate(const std::array<int, flags>& all) const;
  bool tangential_history() const;
  void sort_records(long long pairs);
  void rebuild_history();
  void sum() const;

  DeviceStepShared<Real>& shared_;
  std::unique_ptr<WallContactStage<Real>> host_;
  DeviceBuffer<Vec3<Real>> corners_;            // all walls', wall after wall, 3 per triangle
  DeviceBuffer<Vec3d> mesh_corners_;            // the moving walls' corners in their mesh frames
  DeviceBuffer<int> grid_cells_, grid_facets_;  // all walls' grids (CSR), wall after wall
  DeviceBuffer<PlanarPatch<Real>> patches_;     // all walls' planar patches, wall after wall
  std::vector<long long> corner_at_, mesh_corner_at_;  // per wall, offsets into those
  std::vector<WallFacets<Real>> wall_views_;  // per wall, device pointers: a copy of `facets_`
  DeviceBuffer<WallFacets<Real>> facets_;
  DeviceBuffer<WallMotionData<Real>> motions_;
  DeviceBuffer<WallPlacement<Real>> placements_;    // per wall, copied from placements_host_
  WallPlacement<Real>* placements_host_ = nullptr;  // pinned
  // An oscillating wall's velocity changes with the time: the motions copied from this pinned
  // copy with the placements at each place() (null when no wall oscillates: uploaded once).
  WallMotionData<Real>* motions_host_ = nullptr;
  DeviceBuffer<int> materials_;
  // The touching (particle, wall) records (appended, then in wall-major order) and each pair's
  // place among them (-1: apart): a record per touching pair, not per particle and wall.
  DeviceBuffer<WallContactRecord<Real>> touching_, contacts_;
  DeviceBuffer<long long> keys_, sorted_keys_;
  DeviceBuffer<int> index_, sorted_index_, wall_slot_;
  // The facets to clip (WallCandidate, cuda_wall_stage.cu) and their clippings, with each
  // (particle, wall)'s run of them.
  DeviceBuffer<WallCandidate<Real>> candidates_;
  DeviceBuffer<WallContact<Real>> clipped_;
  DeviceBuffer<int> run_first_, run_count_;
  int contact_count_ = 0;
  DeviceHistory<Real> history_;
  HistorySelection<Real> selection_;  // histories_with's buffers
  // CUB's scratch for this stage's sorts, its own: the stage may run beside the pair stage
  // (CudaStep's walls beside the pairs), whose sorts use DeviceStepShared::temp.
  DeviceBuffer<unsigned char> temp_;
  mutable bool sums_ready_ = false;
  mutable std::vector<Vec3d> force_, torque_;
};

}  // namespace talus
