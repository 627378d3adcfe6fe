// The production step on the CUDA backend (see cuda_step.hpp): the device state, the stages as
// launches of the kernels in cuda_step_kernels.cuh, and the set-up from a scene.
#include "solver/step/cuda_step.hpp"

#include <cub/cub.cuh>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/core/cub_call.cuh"
#include "solver/core/device_buffer.hpp"
#include "solver/geometry/device_shape.cuh"
#include "solver/neighbor/contact_pairs_gpu.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/step/contact_stage.hpp"
#include "solver/step/cuda_step_kernels.cuh"
#include "solver/step/host_step.hpp"
#include "solver/step/wall_stage.hpp"

namespace talus {

namespace {

// Which regions of the constant bank's template share (template_table.hpp) CudaStep instances
// hold, so that two steps alive at once never read each other's templates.
std::mutex region_mutex;
std::array<bool, kTemplateRegions> region_in_use{};

int claim_template_region() {
  const std::lock_guard<std::mutex> lock(region_mutex);
  for (int r = 0; r < kTemplateRegions; ++r) {
    if (!region_in_use[r]) {
      region_in_use[r] = true;
      return r;
    }
  }
  return -1;
}

void release_template_region(int r) {
  if (r < 0) return;
  const std::lock_guard<std::mutex> lock(region_mutex);
  region_in_use[r] = false;
}

}  // namespace

template <class Real>
struct CudaStep<Real>::Impl {
  const Scene& scene;
  StepPlan plan;
  Real dt;
  int count = 0;
  std::vector<std::unique_ptr<ShapeArrays<Real>>> host_shapes;  // per template (polyhedra)
  std::vector<BodyProperties<Real>> host_bodies;                // host shape views
  std::vector<std::unique_ptr<DeviceShape<Real>>> device_shapes;
  DeviceBuffer<BodyProperties<Real>> bodies;  // device shape views
  std::vector<std::pair<std::string, DeviceBuffer<Real>>> storage;
  DeviceBuffer<int> template_ids, material_ids;
  DeviceBuffer<long long> global_ids;
  ParticleView<Real> view;  // device pointers
  DeviceBuffer<int> flag;
  DeviceBuffer<unsigned char> temp;  // CUB's temporary storage

  // Pair contacts.
  std::unique_ptr<PairContactStage<Real>> host_tables;  // the scene's checks and law tables
  DeviceBuffer<Real> table_values;
  PairLawTables<Real> tables;   // device pointers
  std::vector<int> capacities;  // the workspace capacities of the scene's template pairs
  // The pair list (a Verlet list) and its slots: kept until some particle has moved skin / 2.
  std::unique_ptr<ContactPairsGpu<Real>> broad_phase;
  Real skin = 0;
  long long list_builds = 0;
  int candidates = 0;
  DeviceBuffer<Real> built_x, built_y, built_z;   // positions when the list was built
  DeviceBuffer<unsigned long long> largest_move;  // squared, as double bits
  DeviceBuffer<unsigned char> slot_state;
  DeviceBuffer<ContactHistoryData<Real>> slot_history;  // volume model
  DeviceBuffer<SlotForce<Real>> slot_forces;            // deterministic mode
  DeviceBuffer<KeyedHistory<Real>> keyed, store;        // carried over at a rebuild
  mutable long long contact_count = 0;
  mutable bool contact_count_ready = true;
  // The phased pair stage (capacities 32 and 64): per slot a mask of kept planes and a key.
  bool phased = false;
  DeviceBuffer<unsigned long long> masks;
  DeviceBuffer<unsigned char> keys, sorted_keys;
  DeviceBuffer<int> order, sorted_order, deferred, histogram;
  // Deterministic mode: each particle's slots (CSR over the list, built with it).
  DeviceBuffer<int> entry_particle, entry_slot, sorted_particle, sorted_slot;
  DeviceBuffer<int> entry_begin, entry_end;

  // Wall contacts. The host stage locates the walls (present facets, transforms); the device
  // holds each wall's grid and corners, uploaded once: a static wall's corners never change, a
  // moving wall's are placed each step by a kernel from its mesh-frame corners (place_walls).
  std::unique_ptr<WallContactStage<Real>> host_walls;
  DeviceBuffer<Vec3<Real>> corners;           // all walls', wall after wall, 3 per triangle
  DeviceBuffer<Vec3d> mesh_corners;           // the moving walls' corners in their mesh frames
  DeviceBuffer<int> grid_cells, grid_facets;  // all walls' grids (CSR), wall after wall
  std::vector<long long> corner_at, mesh_corner_at;  // per wall, offsets into those
  std::vector<WallFacets<Real>> wall_views;  // per wall, device pointers: a copy of `facets`
  DeviceBuffer<WallFacets<Real>> facets;
  DeviceBuffer<WallMotionData<Real>> motions;
  DeviceBuffer<int> wall_materials;
  // The touching (particle, wall) records (appended, then in wall-major order) and each pair's
  // place among them (-1: apart): a record per touching pair, not per particle and wall.
  DeviceBuffer<WallContactRecord<Real>> wall_touching, wall_contacts;
  DeviceBuffer<long long> wall_keys, sorted_wall_keys;
  DeviceBuffer<int> wall_index, sorted_wall_index, wall_slot;
  int wall_contact_count = 0;
  DeviceHistory<Real> wall_history;
  mutable bool wall_sums_ready = false;
  mutable std::vector<Vec3d> wall_force, wall_torque;

  std::array<double, 9> stage_seconds{};
  double time = 0;
  long long steps = 0;
  bool forces_ready = false;

  int constant_region = -1;  // the templates' region of constant memory; -1: global memory

  explicit Impl(const Scene& s) : scene(s), plan(plan_step(s)), dt(Real(s.time_step)) {}
  ~Impl() { release_template_region(constant_region); }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  Real* allocate(const std::string& name) {
    storage.emplace_back(name, DeviceBuffer<Real>(count));
    Real* data = storage.back().second.data();
    if (count > 0) TALUS_CUDA_CHECK(cudaMemset(data, 0, count * sizeof(Real)));
    return data;
  }

  void reset_flags() {
    const int none[flags] = {INT_MAX, INT_MAX, INT_MAX, 0, 0, 0, 0};
    TALUS_CUDA_CHECK(cudaMemcpy(flag.data(), none, sizeof(none), cudaMemcpyHostToDevice));
  }
  int read_flag(Flag which) const {
    int value = 0;
    TALUS_CUDA_CHECK(cudaMemcpy(&value, flag.data() + which, sizeof(int), cudaMemcpyDeviceToHost));
    return value;
  }

  template <class Body>
  void timed(Stage stage, Body&& body) {
    const double start = clock_seconds();
    body();
    TALUS_CUDA_CHECK(cudaDeviceSynchronize());
    stage_seconds[static_cast<int>(stage)] += clock_seconds() - start;
  }

  // The next history store: the touching contacts' keys and histories, sorted by key.
  template <class Record>
  void rebuild_history(DeviceHistory<Real>& h, const DeviceBuffer<Record>& touching, int n) {
    const int next = 1 - h.current;
    h.keys[next].grow_to(n);
    h.histories[next].grow_to(n);
    if (n > 0) {
      copy_histories<<<blocks_for(n), kBlock>>>(touching.data(), n, h.keys[next].data(),
                                                h.histories[next].data());
      TALUS_CUDA_LAUNCH_CHECK();
      cub_call(temp, [&](void* t, std::size_t& b) {
        return cub::DeviceMergeSort::SortPairs(t, b, h.keys[next].data(), h.histories[next].data(),
                                               n, KeyLess());
      });
    }
    h.current = next;
    h.count = n;
  }

  // True when some particle has moved more than (a little less than) skin / 2 since the list
  // was built: a pair outside the list (centres beyond r_a + r_b + skin then) could now touch.
  // The 10% margin covers the round-off of the distances the broad phase compared.
  bool list_expired() {
    if (list_builds == 0 || !(skin > 0)) return true;
    TALUS_CUDA_CHECK(cudaMemset(largest_move.data(), 0, sizeof(unsigned long long)));
    max_displacement_kernel<<<blocks_for(count), kBlock>>>(view, built_x.data(), built_y.data(),
                                                           built_z.data(), largest_move.data());
    TALUS_CUDA_LAUNCH_CHECK();
    unsigned long long bits = 0;
    TALUS_CUDA_CHECK(cudaMemcpy(&bits, largest_move.data(), sizeof(bits), cudaMemcpyDeviceToHost));
    double moved2 = 0;
    std::memcpy(&moved2, &bits, sizeof(moved2));
    const double limit = 0.45 * double(skin);
    return moved2 > limit * limit;
  }

  // Stage candidate_pairs: rebuilds the list when it has expired, carrying the touching slots'
  // histories over to the new slots of the same pairs (by global ids).
  void find_candidates() {
    if (!list_expired()) return;
    const int old = list_builds > 0 ? candidates : 0;
    int stored = 0;
    if (tables.volume_model && old > 0) {
      keyed.grow_to(old), store.grow_to(old);
      key_histories<<<blocks_for(old), kBlock>>>(global_ids.data(), broad_phase->device_pairs(),
                                                 old, slot_state.data(), slot_history.data(),
                                                 keyed.data());
      TALUS_CUDA_LAUNCH_CHECK();
      int* selected_count = flag.data() + selected;
      cub_call(temp, [&](void* t, std::size_t& b) {
        return cub::DeviceSelect::If(t, b, keyed.data(), store.data(), selected_count, old,
                                     Touching());
      });
      stored = read_flag(selected);
      if (stored > 0) {
        cub_call(temp, [&](void* t, std::size_t& b) {
          return cub::DeviceMergeSort::SortKeys(t, b, store.data(), stored, KeyLess());
        });
      }
    }
    broad_phase->build();
    candidates = static_cast<int>(broad_phase->pair_count());
    ++list_builds;
    const ContactPair* pairs = broad_phase->device_pairs();
    slot_state.grow_to(candidates);
    if (tables.volume_model) slot_history.grow_to(candidates);
    if (candidates > 0) {
      carry_histories<<<blocks_for(candidates), kBlock>>>(
          global_ids.data(), pairs, candidates, store.data(), stored,
          tables.volume_model ? slot_history.data() : nullptr, slot_state.data());
      TALUS_CUDA_LAUNCH_CHECK();
    }
    if (scene.deterministic && candidates > 0) {
      // Each particle's slots, in ascending slot (pair) order: the radix sort is stable.
      const int entries = 2 * candidates;
      slot_forces.grow_to(candidates);
      entry_particle.grow_to(entries), entry_slot.grow_to(entries);
      sorted_particle.grow_to(entries), sorted_slot.grow_to(entries);
      emit_entries<<<blocks_for(candidates), kBlock>>>(pairs, candidates, entry_particle.data(),
                                                       entry_slot.data());
      TALUS_CUDA_LAUNCH_CHECK();
      int bits = 1;
      while (bits < 31 && (1 << bits) < count) ++bits;
      cub_call(temp, [&](void* t, std::size_t& b) {
        return cub::DeviceRadixSort::SortPairs(t, b, entry_particle.data(), sorted_particle.data(),
                                               entry_slot.data(), sorted_slot.data(), entries, 0,
                                               bits);
      });
      TALUS_CUDA_CHECK(cudaMemset(entry_begin.data(), 0, count * sizeof(int)));
      TALUS_CUDA_CHECK(cudaMemset(entry_end.data(), 0, count * sizeof(int)));
      entry_ranges<<<blocks_for(entries), kBlock>>>(sorted_particle.data(), entries,
                                                    entry_begin.data(), entry_end.data());
      TALUS_CUDA_LAUNCH_CHECK();
    }
    if (skin > 0) {  // the positions the next steps' displacements are measured from
      const std::size_t bytes = count * sizeof(Real);
      TALUS_CUDA_CHECK(
          cudaMemcpy(built_x.data(), view.position.x, bytes, cudaMemcpyDeviceToDevice));
      TALUS_CUDA_CHECK(
          cudaMemcpy(built_y.data(), view.position.y, bytes, cudaMemcpyDeviceToDevice));
      TALUS_CUDA_CHECK(
          cudaMemcpy(built_z.data(), view.position.z, bytes, cudaMemcpyDeviceToDevice));
    }
  }

  SlotArgs<Real> slot_args(Real spring_dt) {
    SlotArgs<Real> a;
    a.pairs = broad_phase->device_pairs();
    a.spring_dt = spring_dt;
    a.histories = tables.volume_model ? slot_history.data() : nullptr;
    a.forces = scene.deterministic ? slot_forces.data() : nullptr;
    a.slot_state = slot_state.data();
    a.flag = flag.data();
    a.touching = flag.data() + touching_pairs;
    return a;
  }

  // pair_kernel for the pairs of capacity Capacity among `slots` (all slots when null).
  template <int Capacity>
  void launch_pairs(const SlotArgs<Real>& args, const int* slots, int n) {
    if (n <= 0) return;
    if (scene.deterministic) {
      pair_kernel<Real, Capacity, false><<<blocks_for(n), kBlock>>>(view, tables, args, slots, n);
    } else {
      pair_kernel<Real, Capacity, true><<<blocks_for(n), kBlock>>>(view, tables, args, slots, n);
    }
    TALUS_CUDA_LAUNCH_CHECK();
  }

  void launch_pairs(int capacity, const SlotArgs<Real>& args, const int* slots, int n) {
    switch (capacity) {
      case 0:
        return launch_pairs<0>(args, slots, n);
      case 32:
        return launch_pairs<32>(args, slots, n);
      case 64:
        return launch_pairs<64>(args, slots, n);
      case 128:
        return launch_pairs<128>(args, slots, n);
      default:
        return launch_pairs<256>(args, slots, n);
    }
  }

  // Phase 2 for the workspace sizes Cap, 2 Cap, ... up to 64: each over the sorted slots whose
  // kept planes fit it and not the size before (keys below + 2 .. Cap + 1).
  template <int Cap>
  void launch_polytopes(const SlotArgs<Real>& args, const std::vector<int>& counts, int begin,
                        int below) {
    int end = begin;
    for (int m = below + 1; m <= Cap; ++m) end += counts[m + 1];
    const int n = end - begin;
    if (n > 0) {
      const auto launch = [&](auto kernel) {
        kernel<<<blocks_for(n), kBlock>>>(view, tables, args, sorted_order.data(), begin, n,
                                          masks.data(), deferred.data(),
                                          flag.data() + deferred_pairs);
        TALUS_CUDA_LAUNCH_CHECK();
      };
      if (scene.deterministic) {
        launch(polytope_pair_kernel<Real, Cap, false>);
      } else {
        launch(polytope_pair_kernel<Real, Cap, true>);
      }
    }
    if constexpr (Cap < kMaxMaskPlanes) launch_polytopes<Cap * 2>(args, counts, end, Cap);
  }

  // The phased stage over every slot: cull, sort by kept planes, polytopes, deferred pairs.
  void compute_phased(const SlotArgs<Real>& args) {
    const int n = candidates;
    masks.grow_to(n), keys.grow_to(n), sorted_keys.grow_to(n);
    order.grow_to(n), sorted_order.grow_to(n);
    histogram.grow_to(kMaxMaskPlanes + 2);
    TALUS_CUDA_CHECK(cudaMemset(histogram.data(), 0, histogram.size() * sizeof(int)));
    cull_pair_kernel<<<blocks_for(n), kBlock>>>(view, tables, args, n, masks.data(), keys.data(),
                                                order.data(), histogram.data());
    TALUS_CUDA_LAUNCH_CHECK();
    // Stable: slots of one key stay in slot order. kOtherPath (255) sorts last.
    cub_call(temp, [&](void* t, std::size_t& b) {
      return cub::DeviceRadixSort::SortPairs(t, b, keys.data(), sorted_keys.data(), order.data(),
                                             sorted_order.data(), n, 0, 8);
    });
    const std::vector<int> counts = download(histogram.data(), kMaxMaskPlanes + 2);
    deferred.grow_to(n);
    launch_polytopes<8>(args, counts, counts[0], -1);
    const int late = read_flag(deferred_pairs);
    for (const int capacity : capacities) {
      if (capacity > 0 && capacity <= kMaxMaskPlanes)
        launch_pairs(capacity, args, deferred.data(), late);
    }
  }

  // Stage pair_contacts: every slot of the list.
  void compute_pairs(Real spring_dt) {
    contact_count = 0;
    contact_count_ready = true;
    if (candidates == 0) return;
    const SlotArgs<Real> args = slot_args(spring_dt);
    if (phased) compute_phased(args);
    for (const int capacity : capacities) {
      if (!phased || capacity == 0 || capacity > kMaxMaskPlanes)
        launch_pairs(capacity, args, nullptr, candidates);
    }
    const int bad = read_flag(degenerate_pair);
    if (bad != INT_MAX) {
      const ContactPair pair = download(broad_phase->device_pairs() + bad, 1)[0];
      const std::vector<long long> ids = download(global_ids.data(), count);
      throw std::runtime_error(
          scene.file + ": particles " + std::to_string(ids[pair.a]) + " and " +
          std::to_string(ids[pair.b]) +
          ": the contact geometry is degenerate (a sphere inside another, or an overlap the "
          "workspace cannot hold)");
    }
    contact_count_ready = false;  // flag[touching_pairs], read when asked
  }

  // Once, at construction: the grids and the static walls' corners (placed on the host at t = 0
  // by the host stage), and the moving walls' mesh-frame corners.
  void upload_walls() {
    WallContactStage<Real>& hw = *host_walls;
    hw.place(time);
    const int walls = static_cast<int>(scene.walls.size());
    std::vector<Vec3<Real>> all;
    std::vector<Vec3d> moving;
    std::vector<int> cells, entries;
    std::vector<std::size_t> cell_at(walls), entry_at(walls);
    corner_at.assign(walls, 0);
    mesh_corner_at.assign(walls, -1);
    for (int w = 0; w < walls; ++w) {
      const TriangleMesh& mesh = hw.mesh(w);
      corner_at[w] = static_cast<long long>(all.size());
      if (hw.moves(w)) {
        mesh_corner_at[w] = static_cast<long long>(moving.size());
        for (const std::array<int, 3>& t : mesh.triangles) {
          for (const int k : t) moving.push_back(mesh.vertices[k]);
        }
        all.resize(all.size() + 3 * mesh.triangles.size());  // placed each step
      } else {
        all.insert(all.end(), hw.corners(w).begin(), hw.corners(w).end());
      }
      cell_at[w] = cells.size();
      entry_at[w] = entries.size();
      if (const FacetGrid<Real>* g = hw.grid(w)) {
        cells.insert(cells.end(), g->cell_start().begin(), g->cell_start().end());
        entries.insert(entries.end(), g->cell_facets().begin(), g->cell_facets().end());
      }
    }
    corners.upload(all);
    mesh_corners.upload(moving);
    grid_cells.upload(cells);
    grid_facets.upload(entries);
    wall_views.resize(walls);
    for (int w = 0; w < walls; ++w) {
      wall_views[w] = hw.facets(w);
      wall_views[w].corners = corners.data() + corner_at[w];
      if (const FacetGrid<Real>* g = hw.grid(w)) {
        wall_views[w].grid =
            g->view_of(grid_cells.data() + cell_at[w], grid_facets.data() + entry_at[w]);
      }
    }
    facets.upload(wall_views);
  }

  // The walls at the current time: each moving wall's present corners placed by a kernel (one
  // thread per corner) with the transform computed here, in double as on the host; the per-wall
  // views uploaded again only when a count or a transform changed (a few hundred bytes).
  void place_walls() {
    host_walls->locate(time);
    bool changed = false;
    for (std::size_t w = 0; w < wall_views.size(); ++w) {
      const WallFacets<Real>& now = host_walls->facets(static_cast<int>(w));
      WallFacets<Real>& view = wall_views[w];
      if (mesh_corner_at[w] >= 0) {
        const RigidTransform transform = wall_transform(scene.walls[w].motion, time);
        const int n = 3 * now.count;
        if (n > 0) {
          place_wall_kernel<<<blocks_for(n), kBlock>>>(mesh_corners.data() + mesh_corner_at[w], n,
                                                       transform.rotation, transform.translation,
                                                       corners.data() + corner_at[w]);
          TALUS_CUDA_LAUNCH_CHECK();
        }
        view.rotation = now.rotation;
        view.translation = now.translation;
        changed = true;
      }
      if (view.count != now.count) {
        view.count = now.count;
        changed = true;
      }
    }
    if (changed) facets.upload(wall_views);
  }

  void compute_walls(Real spring_dt) {
    place_walls();
    const int walls = static_cast<int>(wall_views.size());
    WallArgs<Real> args;
    args.facets = facets.data();
    args.motions = motions.data();
    args.materials = wall_materials.data();
    args.walls = walls;
    const long long n = static_cast<long long>(count) * walls;
    wall_contact_count = 0;
    if (n > 0) {
      wall_slot.grow_to(n);
      TALUS_CUDA_CHECK(cudaMemset(wall_slot.data(), 0xff, n * sizeof(int)));  // -1
      // Room for the touching records: what the last step needed (at first 64), doubled when the
      // counter says the kernel overflowed it, which runs it again (GpuStep tests with walls
      // overflow on their first evaluation).
      if (wall_touching.size() == 0) wall_touching.grow_to(std::min<long long>(n, 64));
      for (;;) {
        const int capacity = static_cast<int>(wall_touching.size());
        wall_kernel<<<blocks_for(n), kBlock>>>(view, tables, args, spring_dt, wall_history.in(),
                                               wall_history.values(), wall_touching.data(),
                                               capacity, flag.data());
        TALUS_CUDA_LAUNCH_CHECK();
        const int bad = read_flag(degenerate_wall);
        if (bad != INT_MAX) {
          const std::vector<long long> ids = download(global_ids.data(), count);
          throw std::runtime_error(scene.file + ": particle " + std::to_string(ids[bad % count]) +
                                   " against wall '" + scene.walls[bad / count].name +
                                   "': a facet's clipping failed (section capacity)");
        }
        wall_contact_count = read_flag(touching_walls);
        if (wall_contact_count <= capacity) break;
        wall_touching.grow_to(std::min<long long>(n, 2LL * wall_contact_count));
        TALUS_CUDA_CHECK(cudaMemset(flag.data() + touching_walls, 0, sizeof(int)));
      }
    }
    const int m = wall_contact_count;
    if (m > 0) {
      wall_keys.grow_to(m), sorted_wall_keys.grow_to(m);
      wall_index.grow_to(m), sorted_wall_index.grow_to(m), wall_contacts.grow_to(m);
      wall_contact_keys<<<blocks_for(m), kBlock>>>(wall_touching.data(), m, count, wall_keys.data(),
                                                   wall_index.data());
      TALUS_CUDA_LAUNCH_CHECK();
      int bits = 1;
      while (bits < 63 && (1LL << bits) < n) ++bits;
      cub_call(temp, [&](void* t, std::size_t& b) {
        return cub::DeviceRadixSort::SortPairs(t, b, wall_keys.data(), sorted_wall_keys.data(),
                                               wall_index.data(), sorted_wall_index.data(), m, 0,
                                               bits);
      });
      order_wall_contacts<<<blocks_for(m), kBlock>>>(wall_touching.data(), sorted_wall_keys.data(),
                                                     sorted_wall_index.data(), m,
                                                     wall_contacts.data(), wall_slot.data());
      TALUS_CUDA_LAUNCH_CHECK();
    }
    if (tables.volume_model) rebuild_history(wall_history, wall_contacts, wall_contact_count);
    wall_sums_ready = false;
  }

  void accumulate() {
    const int walls = host_walls ? static_cast<int>(scene.walls.size()) : 0;
    const bool slots = scene.deterministic && candidates > 0;
    accumulate_kernel<<<blocks_for(count), kBlock>>>(
        view, slots ? broad_phase->device_pairs() : nullptr, slot_state.data(),
        slots ? slot_forces.data() : nullptr, sorted_slot.data(), entry_begin.data(),
        entry_end.data(), wall_contacts.data(), wall_slot.data(), walls);
    TALUS_CUDA_LAUNCH_CHECK();
  }

  long long touching_count() const {
    if (!contact_count_ready) {
      contact_count = read_flag(touching_pairs);
      contact_count_ready = true;
    }
    return contact_count;
  }

  void run_force_stages(Real spring_dt) {
    if (count == 0) return;
    const BodyProperties<Real>* b = bodies.data();
    for (const Stage stage : plan.stages) {
      switch (stage) {
        case Stage::clear_forces:
          timed(stage, [&] {
            clear_forces_kernel<<<blocks_for(count), kBlock>>>(view);
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::gravity:
          timed(stage, [&] {
            const Vec3<Real> g(*scene.effects.gravity);
            gravity_kernel<<<blocks_for(count), kBlock>>>(view, b, g);
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::drag:
          timed(stage, [&] {
            drag_kernel<<<blocks_for(count), kBlock>>>(view, Real(*scene.effects.drag_alpha));
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::candidate_pairs:
          timed(stage, [&] { find_candidates(); });
          break;
        case Stage::pair_contacts:
          timed(stage, [&] { compute_pairs(spring_dt); });
          break;
        case Stage::wall_contacts:
          timed(stage, [&] { compute_walls(spring_dt); });
          break;
        case Stage::accumulate:
          timed(stage, [&] { accumulate(); });
          break;
        case Stage::integrate_begin:
        case Stage::integrate_end:
          break;
      }
    }
  }

  // The particle arrays in host memory, as a host ParticleView over `keep`'s vectors.
  struct HostCopy {
    std::vector<std::vector<Real>> arrays;
    std::vector<int> template_ids;
    std::vector<long long> global_ids;
    ParticleView<Real> view;
  };
  HostCopy host_copy() const {
    HostCopy c;
    c.view.count = count;
    c.template_ids = download(template_ids.data(), count);
    c.global_ids = download(global_ids.data(), count);
    c.view.template_id = c.template_ids.data();
    c.view.global_id = c.global_ids.data();
    c.arrays.reserve(13);
    const auto get = [&](const Real* device) {
      c.arrays.push_back(download(device, count));
      return c.arrays.back().data();
    };
    const auto get3 = [&](const Soa3<Real>& s) {
      Soa3<Real> h;
      if (s.present()) h.x = get(s.x), h.y = get(s.y), h.z = get(s.z);
      return h;
    };
    c.view.position = get3(view.position);
    c.view.velocity = get3(view.velocity);
    c.view.angular_velocity = get3(view.angular_velocity);
    c.view.orientation.w = get(view.orientation.w);
    c.view.orientation.x = get(view.orientation.x);
    c.view.orientation.y = get(view.orientation.y);
    c.view.orientation.z = get(view.orientation.z);
    return c;
  }

  std::size_t wall_bytes() const {
    return corners.size() * sizeof(Vec3<Real>) + mesh_corners.size() * sizeof(Vec3d) +
           (grid_cells.size() + grid_facets.size()) * sizeof(int) +
           facets.size() * sizeof(WallFacets<Real>);
  }

  void sum_walls() const {
    if (wall_sums_ready) return;
    wall_force.assign(scene.walls.size(), Vec3d());
    wall_torque.assign(scene.walls.size(), Vec3d());
    if (host_walls) {
      // As WallContactStage::accumulate: in order, in double.
      for (const WallContactRecord<Real>& c : download(wall_contacts.data(), wall_contact_count)) {
        wall_force[c.wall] -= Vec3d(c.force);
        wall_torque[c.wall] -= cross(Vec3d(c.point), Vec3d(c.force));
      }
    }
    wall_sums_ready = true;
  }
};

template <class Real>
CudaStep<Real>::CudaStep(const Scene& scene, CudaStepOptions options)
    : impl_(std::make_unique<Impl>(scene)) {
  Impl& m = *impl_;
  for (const ParticleTemplate& t : scene.templates) {
    m.host_shapes.push_back(t.kind == ParticleShapeKind::polyhedron
                                ? std::make_unique<ShapeArrays<Real>>(t.shape)
                                : nullptr);
    m.host_bodies.push_back(body_properties(scene, t, m.host_shapes.back().get()));
  }
  // The scene's checks first (StepNotSupported), as the host step makes them.
  if (m.plan.contacts)
    m.host_tables = std::make_unique<PairContactStage<Real>>(scene, m.host_bodies);
  if (m.plan.walls) {
    m.host_walls =
        std::make_unique<WallContactStage<Real>>(scene, m.host_bodies, 1, options.wall_search);
  }

  std::vector<BodyProperties<Real>> device_bodies = m.host_bodies;
  for (std::size_t k = 0; k < device_bodies.size(); ++k) {
    m.device_shapes.push_back(nullptr);
    if (m.host_shapes[k]) {
      m.device_shapes.back() = std::make_unique<DeviceShape<Real>>(m.host_bodies[k].shape);
      device_bodies[k].shape = m.device_shapes.back()->view;
    }
  }
  m.bodies.upload(device_bodies);
  if (options.constant_templates &&
      device_bodies.size() <= static_cast<std::size_t>(templates_per_region<Real>())) {
    m.constant_region = claim_template_region();
    if (m.constant_region >= 0) {
      TALUS_CUDA_CHECK(
          cudaMemcpyToSymbol(template_table_detail::constant_templates, device_bodies.data(),
                             device_bodies.size() * sizeof(BodyProperties<Real>),
                             static_cast<std::size_t>(m.constant_region) * kTemplateRegionBytes));
    }
  }
  m.flag.resize(flags);

  const std::vector<ParticleState> initial = initial_particles(scene);
  m.count = static_cast<int>(initial.size());
  const int n = m.count;
  ParticleView<Real>& v = m.view;
  v.count = n;
  const auto soa3 = [&](const std::string& name) {
    Soa3<Real> s;
    s.x = m.allocate(name + ".x"), s.y = m.allocate(name + ".y"), s.z = m.allocate(name + ".z");
    return s;
  };
  v.position = soa3("position");
  v.velocity = soa3("velocity");
  v.orientation.w = m.allocate("orientation.w");
  v.orientation.x = m.allocate("orientation.x");
  v.orientation.y = m.allocate("orientation.y");
  v.orientation.z = m.allocate("orientation.z");
  if (m.plan.arrays.force) {
    v.force = soa3("force");
    v.step_start_acceleration = soa3("step_start_acceleration");
  }
  if (m.plan.arrays.angular_velocity) v.angular_velocity = soa3("angular_velocity");
  if (m.plan.arrays.torque) {
    v.torque = soa3("torque");
    v.step_start_torque = soa3("step_start_torque");
  }
  if (m.plan.arrays.bounding_radius) v.bounding_radius = m.allocate("bounding_radius");

  // The initial state, made on the host as HostStep makes it, then uploaded array by array.
  std::vector<int> template_ids(n), material_ids(n);
  std::vector<long long> global_ids(n);
  std::vector<std::vector<Real>> columns(14, std::vector<Real>(n));
  for (int i = 0; i < n; ++i) {
    const ParticleState& p = initial[i];
    const BodyProperties<Real>& body = m.host_bodies.at(p.template_index);
    template_ids[i] = p.template_index;
    material_ids[i] = body.material;
    global_ids[i] = i;
    const Quatd q = p.orientation.normalized();
    const Vec3<Real> x(p.position), u(p.velocity);
    const Quat<Real> qr(q);
    // The scene gives the angular velocity in the world frame; Euler's equations want the body's.
    const Vec3<Real> w(rotate_inverse(q, p.angular_velocity));
    const Real values[14] = {x.x,  x.y,  x.z,  u.x, u.y, u.z, qr.w,
                             qr.x, qr.y, qr.z, w.x, w.y, w.z, body.bounding_radius};
    for (int c = 0; c < 14; ++c) columns[c][i] = values[c];
  }
  Real* const targets[14] = {v.position.x,         v.position.y,         v.position.z,
                             v.velocity.x,         v.velocity.y,         v.velocity.z,
                             v.orientation.w,      v.orientation.x,      v.orientation.y,
                             v.orientation.z,      v.angular_velocity.x, v.angular_velocity.y,
                             v.angular_velocity.z, v.bounding_radius};
  for (int c = 0; c < 14; ++c) {
    if (targets[c] && n > 0) {
      TALUS_CUDA_CHECK(
          cudaMemcpy(targets[c], columns[c].data(), n * sizeof(Real), cudaMemcpyHostToDevice));
    }
  }
  m.template_ids.upload(template_ids);
  m.material_ids.upload(material_ids);
  m.global_ids.upload(global_ids);
  v.template_id = m.template_ids.data();
  v.material_id = m.material_ids.data();
  v.global_id = m.global_ids.data();

  if (m.plan.contacts) {
    const PairLawTables<Real>& h = m.host_tables->tables();
    m.tables = upload_law_tables(h, m.bodies.data(), m.table_values);
    m.tables.bodies.constant_region = m.constant_region;
    // One pair launch per workspace capacity among the scene's template pairs.
    for (const BodyProperties<Real>& a : m.host_bodies) {
      for (const BodyProperties<Real>& b : m.host_bodies) {
        const int capacity = pair_capacity(a, b, h.volume_model);
        if (std::find(m.capacities.begin(), m.capacities.end(), capacity) == m.capacities.end()) {
          m.capacities.push_back(capacity);
        }
      }
    }
    std::sort(m.capacities.begin(), m.capacities.end());
    // The phased stage when some template pair has at most 64 planes: its capacity is then 32
    // or 64 (a pair with more goes to pair_kernel with its own capacity).
    for (const int capacity : m.capacities)
      m.phased = m.phased || (capacity > 0 && capacity <= kMaxMaskPlanes);
    m.broad_phase = std::make_unique<ContactPairsGpu<Real>>();
    double largest_radius = 0;
    for (const BodyProperties<Real>& b : m.host_bodies)
      largest_radius = std::max(largest_radius, double(b.bounding_radius));
    m.skin = Real(scene.skin ? *scene.skin : 0.2 * largest_radius);  // default: 0.1 diameter
    NeighborInput<Real> in;
    in.x = v.position.x, in.y = v.position.y, in.z = v.position.z;
    in.radius = v.bounding_radius;
    in.count = n;
    in.skin = m.skin;
    m.broad_phase->set_device_particles(in);
    if (scene.deterministic) m.entry_begin.resize(n), m.entry_end.resize(n);
    if (m.skin > 0) m.built_x.resize(n), m.built_y.resize(n), m.built_z.resize(n);
    m.largest_move.resize(1);
  }
  if (m.host_walls) {
    m.motions.upload(m.host_walls->motions());
    std::vector<int> materials;
    for (const auto& w : scene.walls) materials.push_back(w.material);
    m.wall_materials.upload(materials);
    m.upload_walls();
  }
}

template <class Real>
CudaStep<Real>::~CudaStep() = default;

template <class Real>
void CudaStep<Real>::evaluate_forces() {
  Impl& m = *impl_;
  m.reset_flags();
  m.run_force_stages(Real(0));
  m.forces_ready = true;
}

template <class Real>
void CudaStep<Real>::step() {
  Impl& m = *impl_;
  if (!m.forces_ready) evaluate_forces();  // F_0, T_0 for the first half-step
  if (m.host_walls) m.host_walls->open_outlets(m.time);
  m.reset_flags();
  if (m.count > 0) {
    m.timed(Stage::integrate_begin, [&] {
      integrate_begin_kernel<<<blocks_for(m.count), kBlock>>>(m.view, m.bodies.data(), m.dt,
                                                              m.flag.data());
      TALUS_CUDA_LAUNCH_CHECK();
    });
    const int failed = m.read_flag(failed_rotation);
    if (failed != INT_MAX) {
      const long long id = download(m.global_ids.data() + failed, 1)[0];
      throw std::runtime_error(
          m.scene.file + ": particle " + std::to_string(id) +
          " spins too fast for time.step (the implicit-midpoint rotation did not converge)");
    }
  }
  m.time += m.scene.time_step;
  ++m.steps;
  m.run_force_stages(m.dt);
  if (m.count > 0) {
    m.timed(Stage::integrate_end, [&] {
      integrate_end_kernel<<<blocks_for(m.count), kBlock>>>(m.view, m.bodies.data(), m.dt);
      TALUS_CUDA_LAUNCH_CHECK();
    });
  }
}

template <class Real>
double CudaStep<Real>::time() const {
  return impl_->time;
}
template <class Real>
long long CudaStep<Real>::steps() const {
  return impl_->steps;
}
template <class Real>
const StepPlan& CudaStep<Real>::plan() const {
  return impl_->plan;
}
template <class Real>
int CudaStep<Real>::particle_count() const {
  return impl_->count;
}
template <class Real>
const std::array<double, 9>& CudaStep<Real>::stage_seconds() const {
  return impl_->stage_seconds;
}
template <class Real>
std::size_t CudaStep<Real>::pair_contact_count() const {
  return static_cast<std::size_t>(impl_->touching_count());
}

template <class Real>
long long CudaStep<Real>::pair_list_builds() const {
  return impl_->list_builds;
}

template <class Real>
std::size_t CudaStep<Real>::candidate_pair_count() const {
  return static_cast<std::size_t>(impl_->candidates);
}
template <class Real>
std::size_t CudaStep<Real>::wall_contact_count() const {
  return impl_->wall_contact_count;
}

template <class Real>
std::vector<std::string> CudaStep<Real>::allocated_arrays() const {
  std::vector<std::string> names;
  for (const auto& [name, values] : impl_->storage) names.push_back(name);
  names.insert(names.end(), {"template_id", "material_id", "global_id"});
  return names;
}

template <class Real>
std::size_t CudaStep<Real>::allocated_bytes() const {
  const Impl& m = *impl_;
  std::size_t bytes = m.count * (2 * sizeof(int) + sizeof(long long));
  for (const auto& entry : m.storage) bytes += entry.second.size() * sizeof(Real);
  bytes += pair_list_bytes() + m.wall_history.bytes() +
           (m.wall_touching.size() + m.wall_contacts.size()) * sizeof(WallContactRecord<Real>) +
           (m.wall_keys.size() + m.sorted_wall_keys.size()) * sizeof(long long) +
           (m.wall_index.size() + m.sorted_wall_index.size() + m.wall_slot.size()) * sizeof(int) +
           m.temp.size() + m.wall_bytes();
  return bytes;
}

template <class Real>
bool CudaStep<Real>::templates_in_constant_memory() const {
  return impl_->constant_region >= 0;
}

template <class Real>
std::size_t CudaStep<Real>::pair_list_bytes() const {
  const Impl& m = *impl_;
  std::size_t bytes =
      m.slot_state.size() + m.slot_history.size() * sizeof(ContactHistoryData<Real>) +
      m.slot_forces.size() * sizeof(SlotForce<Real>) +
      (m.keyed.size() + m.store.size()) * sizeof(KeyedHistory<Real>) +
      (m.built_x.size() + m.built_y.size() + m.built_z.size()) * sizeof(Real) +
      (m.entry_particle.size() + m.entry_slot.size() + m.sorted_particle.size() +
       m.sorted_slot.size() + m.entry_begin.size() + m.entry_end.size() + m.order.size() +
       m.sorted_order.size() + m.deferred.size() + m.histogram.size()) *
          sizeof(int) +
      m.masks.size() * sizeof(unsigned long long) + m.keys.size() + m.sorted_keys.size();
  if (m.broad_phase) bytes += m.broad_phase->allocated_bytes();
  return bytes;
}

template <class Real>
Vec3d CudaStep<Real>::wall_force(int w) const {
  impl_->sum_walls();
  return impl_->wall_force.at(w);
}

template <class Real>
Vec3d CudaStep<Real>::wall_torque(int w) const {
  impl_->sum_walls();
  return impl_->wall_torque.at(w);
}

template <class Real>
std::vector<TrajectoryRow> CudaStep<Real>::trajectory_rows() const {
  return particle_rows(impl_->host_copy().view);
}

template <class Real>
double CudaStep<Real>::kinetic_energy() const {
  return particle_kinetic_energy(impl_->host_copy().view, impl_->host_bodies);
}

template <class Real>
double CudaStep<Real>::bed_height(const Vec3d& gravity) const {
  return particle_bed_height(impl_->host_copy().view, impl_->host_bodies, gravity);
}

std::unique_ptr<AnyStep> make_cuda_step(const Scene& scene) {
  if (scene.precision == Precision::float32) {
    return std::make_unique<StepAdapter<CudaStep<float>>>(scene, "cuda");
  }
  return std::make_unique<StepAdapter<CudaStep<double>>>(scene, "cuda");
}

template class CudaStep<double>;
template class CudaStep<float>;

}  // namespace talus
