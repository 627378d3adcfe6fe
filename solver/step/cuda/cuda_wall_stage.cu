// The CUDA step's wall contacts (cuda_wall_stage.cuh): the launches of its kernels
// (cuda_wall_kernels.cuh), the walls' upload and placement, the ordering of the touching records,
// the history store, and the graph steps' single pass.
#include "solver/step/cuda/cuda_wall_stage.cuh"

#include <cub/cub.cuh>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "solver/contact/contact_laws.hpp"
#include "solver/core/cub_call.cuh"
#include "solver/step/cuda/cuda_wall_kernels.cuh"
#include "solver/step/cuda/history_select.cuh"

namespace talus {

template <class Real>
DeviceWallStage<Real>::DeviceWallStage(DeviceStepShared<Real>& shared,
                                       std::unique_ptr<WallContactStage<Real>> host, double time)
    : shared_(shared), host_(std::move(host)) {
  if (shared.constant_region >= 0)
    fill_template_region(shared.device_bodies, shared.constant_region);
  motions_.upload(host_->motions());
  std::vector<int> materials;
  for (const auto& w : shared.scene.walls) materials.push_back(w.material);
  materials_.upload(materials);
  const std::size_t walls = shared.scene.walls.size();
  placements_.resize(walls);
  TALUS_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&placements_host_),
                                  std::max<std::size_t>(walls, 1) * sizeof(WallPlacement<Real>)));
  for (std::size_t w = 0; w < walls; ++w) placements_host_[w] = WallPlacement<Real>();
  if (host_->oscillates()) {  // their velocities change with the time: copied with the placements
    TALUS_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&motions_host_),
                                    walls * sizeof(WallMotionData<Real>)));
    std::copy(host_->motions().begin(), host_->motions().end(), motions_host_);
  }
  upload(time);
}

template <class Real>
DeviceWallStage<Real>::~DeviceWallStage() {
  if (placements_host_) cudaFreeHost(placements_host_);  // no throw from a destructor
  if (motions_host_) cudaFreeHost(motions_host_);
}

// Once, at construction: the grids and the static walls' corners (placed on the host at `time`
// by the host stage), and the moving walls' mesh-frame corners.
template <class Real>
void DeviceWallStage<Real>::upload(double time) {
  WallContactStage<Real>& hw = *host_;
  hw.place(time);
  const int walls = static_cast<int>(shared_.scene.walls.size());
  std::vector<Vec3<Real>> all;
  std::vector<Vec3d> moving;
  std::vector<int> cells, entries;
  std::vector<PlanarPatch<Real>> patches;
  std::vector<std::size_t> cell_at(walls), entry_at(walls), patch_at(walls);
  corner_at_.assign(walls, 0);
  mesh_corner_at_.assign(walls, -1);
  for (int w = 0; w < walls; ++w) {
    const TriangleMesh& mesh = hw.mesh(w);
    corner_at_[w] = static_cast<long long>(all.size());
    if (hw.moves(w)) {
      mesh_corner_at_[w] = static_cast<long long>(moving.size());
      for (const std::array<int, 3>& t : mesh.triangles) {
        for (const int k : t) moving.push_back(mesh.vertices[k]);
      }
      all.resize(all.size() + 3 * mesh.triangles.size());  // placed each step
    } else {
      all.insert(all.end(), hw.corners(w).begin(), hw.corners(w).end());
    }
    patch_at[w] = patches.size();
    patches.insert(patches.end(), hw.patches(w).begin(), hw.patches(w).end());
    cell_at[w] = cells.size();
    entry_at[w] = entries.size();
    if (const FacetGrid<Real>* g = hw.grid(w)) {
      cells.insert(cells.end(), g->cell_start().begin(), g->cell_start().end());
      entries.insert(entries.end(), g->cell_facets().begin(), g->cell_facets().end());
    }
  }
  corners_.upload(all);
  mesh_corners_.upload(moving);
  grid_cells_.upload(cells);
  grid_facets_.upload(entries);
  patches_.upload(patches);
  wall_views_.resize(walls);
  for (int w = 0; w < walls; ++w) {
    wall_views_[w] = hw.facets(w);
    wall_views_[w].corners = corners_.data() + corner_at_[w];
    wall_views_[w].patches =
        wall_views_[w].patch_count > 0 ? patches_.data() + patch_at[w] : nullptr;
    if (const FacetGrid<Real>* g = hw.grid(w)) {
      wall_views_[w].grid =
          g->view_of(grid_cells_.data() + cell_at[w], grid_facets_.data() + entry_at[w]);
    }
  }
  facets_.upload(wall_views_);
}

// The walls' placements at `time` into the pinned buffer (host work only): each wall's present
// facets and transform as the host stage locates them, and a moving wall's corner transform,
// computed here in double as on the host.
template <class Real>
void DeviceWallStage<Real>::stage_placement(double time) {
  host_->locate(time);
  for (std::size_t w = 0; w < wall_views_.size(); ++w) {
    const WallFacets<Real>& now = host_->facets(static_cast<int>(w));
    WallPlacement<Real>& to = placements_host_[w];
    to.count = now.count;
    to.rotation = now.rotation;
    to.translation = now.translation;
    if (mesh_corner_at_[w] >= 0) {
      const RigidTransform transform = wall_transform(shared_.scene.walls[w].motion, time);
      to.corner_rotation = transform.rotation;
      to.corner_translation = transform.translation;
    }
    wall_views_[w].count = now.count;
    wall_views_[w].rotation = now.rotation;
    wall_views_[w].translation = now.translation;
  }
  if (motions_host_)  // an oscillating wall's velocity at `time` (locate set it)
    std::copy(host_->motions().begin(), host_->motions().end(), motions_host_);
}

// The walls at `time` on the device: the placements copied over (one copy from pinned memory,
// which a graph launch repeats with the values the host has put there since), each moving
// wall's present corners placed by a kernel (one thread per corner, up to its facets' capacity),
// every wall's view set by one kernel.
template <class Real>
void DeviceWallStage<Real>::place(double time) {
  stage_placement(time);
  const cudaStream_t stream = shared_.stream;
  const int walls = static_cast<int>(wall_views_.size());
  TALUS_CUDA_CHECK(cudaMemcpyAsync(placements_.data(), placements_host_,
                                   walls * sizeof(WallPlacement<Real>), cudaMemcpyHostToDevice,
                                   stream));
  if (motions_host_) {
    TALUS_CUDA_CHECK(cudaMemcpyAsync(motions_.data(), motions_host_,
                                     walls * sizeof(WallMotionData<Real>), cudaMemcpyHostToDevice,
                                     stream));
  }
  for (int w = 0; w < walls; ++w) {
    if (mesh_corner_at_[w] < 0) continue;
    // All the mesh's corners: those of facets not present yet (a closed outlet) are placed too
    // and not read.
    const long long n = 3LL * static_cast<long long>(host_->mesh(w).triangles.size());
    if (n == 0) continue;
    place_wall_kernel<<<blocks_for(n), kBlock, 0, stream>>>(
        mesh_corners_.data() + mesh_corner_at_[w], static_cast<int>(n), placements_.data() + w,
        corners_.data() + corner_at_[w]);
    TALUS_CUDA_LAUNCH_CHECK();
  }
  set_wall_views_kernel<<<blocks_for(walls), kBlock, 0, stream>>>(facets_.data(),
                                                                  placements_.data(), walls);
  TALUS_CUDA_LAUNCH_CHECK();
}

// The three kernels once, with the room they have now (on the step's stream).
template <class Real>
void DeviceWallStage<Real>::launch_kernels(Real spring_dt, const HistoryIn& old) {
  const long long n = static_cast<long long>(shared_.count) * walls();
  const cudaStream_t stream = shared_.stream;
  WallArgs<Real> a;
  a.facets = facets_.data();
  a.motions = motions_.data();
  a.materials = materials_.data();
  a.walls = walls();
  const int capacity = static_cast<int>(touching_.size());
  const int clip_capacity = static_cast<int>(candidates_.size());
  if (n <= kWarpCandidatePairs) {
    wall_candidates_warp_kernel<<<blocks_for(32 * n), kBlock, 0, stream>>>(
        shared_.view, shared_.tables, a, run_first_.data(), run_count_.data(), candidates_.data(),
        clip_capacity, shared_.flags.data());
  } else {
    wall_candidates_kernel<<<blocks_for(n), kBlock, 0, stream>>>(
        shared_.view, shared_.tables, a, run_first_.data(), run_count_.data(), candidates_.data(),
        clip_capacity, shared_.flags.data());
  }
  TALUS_CUDA_LAUNCH_CHECK();
  wall_clip_kernel<<<blocks_for(clip_capacity), kBlock, 0, stream>>>(
      shared_.view, shared_.tables, candidates_.data(), clip_capacity, shared_.flags.data(),
      clipped_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  with_contact_law(*shared_.scene.effects.contact, [&](auto law) {
    wall_kernel<decltype(law)><<<blocks_for(n), kBlock, 0, stream>>>(
        shared_.view, shared_.tables, a, spring_dt, old, history_.values(), run_first_.data(),
        run_count_.data(), clipped_.data(), clip_capacity, touching_.data(), capacity,
        shared_.flags.data());
  });
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
void DeviceWallStage<Real>::compute(Real spring_dt, double time) {
  place(time);
  const int count = shared_.count;
  const long long n = static_cast<long long>(count) * walls();
  contact_count_ = 0;
  sums_ready_ = false;
  if (n == 0) return;
  const cudaStream_t stream = shared_.stream;
  wall_slot_.grow_to(n);
  TALUS_CUDA_CHECK(cudaMemsetAsync(wall_slot_.data(), 0xff, n * sizeof(int), stream));  // -1
  if (shared_.graph_mode) {
    compute_in_graph(spring_dt);
    return;
  }
  // Room for the touching records: what the last step needed (at first 64), doubled when the
  // counter says the kernel overflowed it, which runs it again (GpuStep tests with walls
  // overflow on their first evaluation).
  if (touching_.size() == 0) touching_.grow_to(std::min<long long>(n, 64));
  // Room for the facets to clip: likewise what the last step needed (at first 1024), doubled
  // past what the counter says when it overflowed.
  if (candidates_.size() == 0) candidates_.grow_to(1024), clipped_.grow_to(1024);
  run_first_.grow_to(n), run_count_.grow_to(n);
  for (;;) {
    const int capacity = static_cast<int>(touching_.size());
    const int clip_capacity = static_cast<int>(candidates_.size());
    launch_kernels(spring_dt, history_.in());
    const std::array<int, flags> all = shared_.flags.read_all();  // one wait for all three
    const int facets = all[wall_candidates];
    if (facets > clip_capacity) {
      grow_clip_room(facets);
      continue;
    }
    check_degenerate(all);
    contact_count_ = all[touching_walls];
    if (contact_count_ <= capacity) break;
    touching_.grow_to(std::min<long long>(n, 2LL * contact_count_));
    shared_.flags.clear(wall_candidates);
    shared_.flags.clear(touching_walls);
  }
  if (contact_count_ > 0) sort_records(n);
  if (tangential_history()) rebuild_history();
}

template <class Real>
void DeviceWallStage<Real>::grow_clip_room(int facets) {
  const long long room = std::max<long long>(2LL * facets, 1024);
  candidates_.grow_to(room), clipped_.grow_to(room);
  shared_.flags.clear(wall_candidates);
  shared_.flags.clear(touching_walls);
}

template <class Real>
void DeviceWallStage<Real>::check_degenerate(const std::array<int, flags>& all) const {
  const int bad = all[degenerate_wall];
  if (bad == INT_MAX) return;
  const int count = shared_.count;
  throw std::runtime_error(shared_.scene.file + ": particle " +
                           std::to_string(shared_.global_id(bad % count)) + " against wall '" +
                           shared_.scene.walls[bad / count].name +
                           "': a facet's clipping failed (section capacity)");
}

template <class Real>
bool DeviceWallStage<Real>::tangential_history() const {
  return with_contact_law(*shared_.scene.effects.contact,
                          [](auto law) { return decltype(law)::kTangentialHistory; });
}

// A graph step's records may be every (particle, wall) pair: capture only when room for all of
// them stays within this (a small scene's pairs are a few thousand records; a large scene runs
// stage by stage).
constexpr long long kGraphWallRecordBytes = 64LL << 20;

template <class Real>
bool DeviceWallStage<Real>::prepare_graph() {
  const long long n = static_cast<long long>(shared_.count) * walls();
  if (n == 0 || n * static_cast<long long>(sizeof(WallContactRecord<Real>)) > kGraphWallRecordBytes)
    return false;
  if (candidates_.size() == 0 || run_first_.size() < static_cast<std::size_t>(n)) return false;
  touching_.grow_to(n);
  keys_.grow_to(n), sorted_keys_.grow_to(n);
  index_.grow_to(n), sorted_index_.grow_to(n), contacts_.grow_to(n);
  // Both stores with room for every pair, the current one's entries kept; its count on the
  // device, where the graph reads it.
  const int current = history_.current, next = 1 - current;
  history_.keys[current].grow_keeping(touching_.size(), history_.count);
  history_.histories[current].grow_keeping(touching_.size(), history_.count);
  history_.keys[next].grow_to(touching_.size());
  history_.histories[next].grow_to(touching_.size());
  history_.device_count.grow_to(1);
  TALUS_CUDA_CHECK(cudaMemcpy(history_.device_count.data(), &history_.count, sizeof(int),
                              cudaMemcpyHostToDevice));
  // CUB's scratch for the graph's sorts of the whole buffers (nothing may be allocated while
  // the graph is captured).
  const int capacity = static_cast<int>(n);
  std::size_t bytes = 0;
  TALUS_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys_.data(),
                                                   sorted_keys_.data(), index_.data(),
                                                   sorted_index_.data(), capacity, 0, 63));
  temp_.grow_to(bytes);
  if (tangential_history()) {
    bytes = 0;
    TALUS_CUDA_CHECK(cub::DeviceMergeSort::SortPairs(nullptr, bytes, history_.keys[next].data(),
                                                     history_.histories[next].data(), capacity,
                                                     KeyLess()));
    temp_.grow_to(bytes);
  }
  return true;
}

// One pass of the three kernels with the room prepare_graph made: the touching records cannot
// overrun it (room for every pair); the facets to clip can, which `abort` tells the kernels
// after this stage and the step (which then runs this stage again with more room). The records
// sorted over the whole buffer (those past the count last), the history store rebuilt likewise
// and copied back into the buffers the graph reads, with its count.
template <class Real>
void DeviceWallStage<Real>::compute_in_graph(Real spring_dt) {
  const int count = shared_.count;
  const long long n = static_cast<long long>(count) * walls();
  const cudaStream_t stream = shared_.stream;
  const int capacity = static_cast<int>(n);
  HistoryIn old = history_.in();
  old.count_at = history_.device_count.data();
  shared_.abort =
      AbortCheck{shared_.flags.at(wall_candidates), static_cast<int>(candidates_.size())};
  launch_kernels(spring_dt, old);
  const int* touching = shared_.flags.at(touching_walls);
  int bits = 1;
  while (bits < 63 && (1LL << bits) <= n) ++bits;  // room for the key n past the real ones
  wall_contact_keys_all<<<blocks_for(capacity), kBlock, 0, stream>>>(
      touching_.data(), capacity, touching, count, n, keys_.data(), index_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  cub_call(temp_, [&](void* t, std::size_t& b) {
    return cub::DeviceRadixSort::SortPairs(t, b, keys_.data(), sorted_keys_.data(), index_.data(),
                                           sorted_index_.data(), capacity, 0, bits, stream);
  });
  order_wall_contacts<<<blocks_for(capacity), kBlock, 0, stream>>>(
      touching_.data(), sorted_keys_.data(), sorted_index_.data(), capacity, touching,
      contacts_.data(), wall_slot_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  if (!tangential_history()) return;
  const int current = history_.current, next = 1 - current;
  PairKey* next_keys = history_.keys[next].data();
  ContactHistoryData<Real>* next_histories = history_.histories[next].data();
  copy_histories_all<<<blocks_for(capacity), kBlock, 0, stream>>>(
      contacts_.data(), capacity, touching, next_keys, next_histories);
  TALUS_CUDA_LAUNCH_CHECK();
  cub_call(temp_, [&](void* t, std::size_t& b) {
    return cub::DeviceMergeSort::SortPairs(t, b, next_keys, next_histories, capacity, KeyLess(),
                                           stream);
  });
  keep_history_kernel<<<blocks_for(capacity), kBlock, 0, stream>>>(
      next_keys, next_histories, capacity, touching, shared_.abort, history_.keys[current].data(),
      history_.histories[current].data(), history_.device_count.data());
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
void DeviceWallStage<Real>::after_graph(const std::array<int, flags>& all) {
  check_degenerate(all);
  contact_count_ = all[touching_walls];
  if (tangential_history()) history_.count = contact_count_;  // the graph kept it in `current`
  sums_ready_ = false;
}

template <class Real>
void DeviceWallStage<Real>::recover(Real spring_dt, double time, int facets) {
  grow_clip_room(facets);
  shared_.abort = AbortCheck{};
  compute(spring_dt, time);
}

// The touching records into wall-major order (as the host's), each pair's slot recorded.
template <class Real>
void DeviceWallStage<Real>::sort_records(long long pairs) {
  const int m = contact_count_;
  const cudaStream_t stream = shared_.stream;
  keys_.grow_to(m), sorted_keys_.grow_to(m);
  index_.grow_to(m), sorted_index_.grow_to(m), contacts_.grow_to(m);
  wall_contact_keys<<<blocks_for(m), kBlock, 0, stream>>>(touching_.data(), m, shared_.count,
                                                          keys_.data(), index_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  int bits = 1;
  while (bits < 63 && (1LL << bits) < pairs) ++bits;
  cub_call(temp_, [&](void* t, std::size_t& b) {
    return cub::DeviceRadixSort::SortPairs(t, b, keys_.data(), sorted_keys_.data(), index_.data(),
                                           sorted_index_.data(), m, 0, bits, stream);
  });
  order_wall_contacts<<<blocks_for(m), kBlock, 0, stream>>>(touching_.data(), sorted_keys_.data(),
                                                            sorted_index_.data(), m, nullptr,
                                                            contacts_.data(), wall_slot_.data());
  TALUS_CUDA_LAUNCH_CHECK();
}

// The next history store: the touching contacts' keys and histories, sorted by key.
template <class Real>
void DeviceWallStage<Real>::rebuild_history() {
  const int n = contact_count_;
  const cudaStream_t stream = shared_.stream;
  PairKey* keys = history_.next_keys(n);
  ContactHistoryData<Real>* histories = history_.next_histories(n);
  if (n > 0) {
    copy_histories<<<blocks_for(n), kBlock, 0, stream>>>(contacts_.data(), n, keys, histories);
    TALUS_CUDA_LAUNCH_CHECK();
    cub_call(temp_, [&](void* t, std::size_t& b) {
      return cub::DeviceMergeSort::SortPairs(t, b, keys, histories, n, KeyLess(), stream);
    });
  }
  history_.flip(n);
}

template <class Real>
void DeviceWallStage<Real>::sum() const {
  if (sums_ready_) return;
  const std::size_t walls = shared_.scene.walls.size();
  force_.assign(walls, Vec3d());
  torque_.assign(walls, Vec3d());
  // As WallContactStage::accumulate: in order, in double.
  for (const WallContactRecord<Real>& c : download(contacts_.data(), contact_count_)) {
    force_[c.wall] -= Vec3d(c.force);
    torque_[c.wall] -= cross(Vec3d(c.point), Vec3d(c.force)) + Vec3d(c.couple);
  }
  sums_ready_ = true;
}

// In a graph step for every record the buffer holds, the count read on the device.
template <class Real>
void DeviceWallStage<Real>::add_energy_sums(double* sums) const {
  const bool graph = shared_.graph_mode;
  const int n =
      graph ? static_cast<int>(static_cast<long long>(shared_.count) * walls()) : contact_count_;
  if (n == 0) return;
  wall_energy_kernel<<<blocks_for(n), kBlock, 0, shared_.stream>>>(
      contacts_.data(), n, graph ? shared_.flags.at(touching_walls) : nullptr, shared_.abort, sums);
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
Vec3d DeviceWallStage<Real>::force(int w) const {
  sum();
  return force_.at(w);
}

template <class Real>
Vec3d DeviceWallStage<Real>::torque(int w) const {
  sum();
  return torque_.at(w);
}

template <class Real>
std::size_t DeviceWallStage<Real>::bytes() const {
  return corners_.size() * sizeof(Vec3<Real>) + mesh_corners_.size() * sizeof(Vec3d) +
         (grid_cells_.size() + grid_facets_.size() + materials_.size()) * sizeof(int) +
         facets_.size() * sizeof(WallFacets<Real>) + patches_.size() * sizeof(PlanarPatch<Real>) +
         motions_.size() * sizeof(WallMotionData<Real>) + history_.bytes() + selection_.bytes() +
         (touching_.size() + contacts_.size()) * sizeof(WallContactRecord<Real>) +
         (keys_.size() + sorted_keys_.size()) * sizeof(long long) +
         (index_.size() + sorted_index_.size() + wall_slot_.size() + run_first_.size() +
          run_count_.size()) *
             sizeof(int) +
         candidates_.size() * sizeof(WallCandidate<Real>) +
         clipped_.size() * sizeof(WallContact<Real>);
}

template <class Real>
void DeviceWallStage<Real>::export_histories(
    std::vector<PairKey>& keys, std::vector<ContactHistoryData<Real>>& histories) const {
  keys = download(history_.keys[history_.current].data(), history_.count);
  histories = download(history_.values(), history_.count);
}

template <class Real>
void DeviceWallStage<Real>::import_histories(
    const std::vector<PairKey>& keys, const std::vector<ContactHistoryData<Real>>& histories) {
  const int n = static_cast<int>(keys.size());
  PairKey* next_keys = history_.next_keys(n);
  ContactHistoryData<Real>* next = history_.next_histories(n);
  if (n > 0) {
    TALUS_CUDA_CHECK(
        cudaMemcpy(next_keys, keys.data(), n * sizeof(PairKey), cudaMemcpyHostToDevice));
    TALUS_CUDA_CHECK(cudaMemcpy(next, histories.data(), n * sizeof(ContactHistoryData<Real>),
                                cudaMemcpyHostToDevice));
  }
  history_.flip(n);
}

template <class Real>
void DeviceWallStage<Real>::histories_with(const std::vector<long long>& ids,
                                           std::vector<PairKey>& keys,
                                           std::vector<ContactHistoryData<Real>>& histories) {
  select_histories_with<false>(history_.keys[history_.current].data(), history_.values(),
                               history_.count, ids, selection_, temp_, keys, histories);
}

template <class Real>
void DeviceWallStage<Real>::add_histories(const std::vector<PairKey>& keys,
                                          const std::vector<ContactHistoryData<Real>>& histories) {
  const int added = static_cast<int>(keys.size());
  if (added == 0) return;
  // The store and the arrivals into the next buffers; sorted there, stably (the store's entry
  // before an arrival of the same key); the unique keys back into the current buffers.
  const int stored = history_.count, n = stored + added;
  PairKey* next_keys = history_.next_keys(n);
  ContactHistoryData<Real>* next = history_.next_histories(n);
  PairKey* current_keys = history_.keys[history_.current].data();
  ContactHistoryData<Real>* current = history_.histories[history_.current].data();
  if (stored > 0) {
    TALUS_CUDA_CHECK(
        cudaMemcpy(next_keys, current_keys, stored * sizeof(PairKey), cudaMemcpyDeviceToDevice));
    TALUS_CUDA_CHECK(cudaMemcpy(next, current, stored * sizeof(ContactHistoryData<Real>),
                                cudaMemcpyDeviceToDevice));
  }
  TALUS_CUDA_CHECK(
      cudaMemcpy(next_keys + stored, keys.data(), added * sizeof(PairKey), cudaMemcpyHostToDevice));
  TALUS_CUDA_CHECK(cudaMemcpy(next + stored, histories.data(),
                              added * sizeof(ContactHistoryData<Real>), cudaMemcpyHostToDevice));
  cub_call(temp_, [&](void* t, std::size_t& b) {
    return cub::DeviceMergeSort::StableSortPairs(t, b, next_keys, next, n, KeyLess());
  });
  history_.keys[history_.current].grow_to(n);
  history_.histories[history_.current].grow_to(n);
  selection_.count.grow_to(1);
  cub_call(temp_, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::UniqueByKey(
        t, b, next_keys, next, history_.keys[history_.current].data(),
        history_.histories[history_.current].data(), selection_.count.data(), n, KeyEqual());
  });
  history_.count = download(selection_.count.data(), 1).at(0);
}

template class DeviceWallStage<double>;
template class DeviceWallStage<float>;

}  // namespace talus
