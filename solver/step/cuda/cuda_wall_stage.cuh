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

template <class Real>
class DeviceWallStage {
 public:
  // `host` has made the scene's checks; its walls are placed at `time` and uploaded.
  DeviceWallStage(DeviceStepShared<Real>& shared, std::unique_ptr<WallContactStage<Real>> host,
                  double time);

  void open_outlets(double time) { host_->open_outlets(time); }
  // The walls at `time`, then every (particle, wall). Throws std::runtime_error naming the
  // particle and the wall when a facet's clipping fails.
  void compute(Real spring_dt, double time);

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

 private:
  void upload(double time);
  void place(double time);
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
  mutable bool sums_ready_ = false;
  mutable std::vector<Vec3d> force_, torque_;
};

}  // namespace talus
