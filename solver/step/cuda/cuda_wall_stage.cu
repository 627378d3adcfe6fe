// The CUDA step's wall contacts (cuda_wall_stage.cuh): the kernels and their launches, the
// walls' upload and placement, the ordering of the touching records, the history store.
#include "solver/step/cuda/cuda_wall_stage.cuh"

#include <cub/cub.cuh>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "solver/contact/contact_laws.hpp"
#include "solver/core/cub_call.cuh"
#include "solver/step/wall_kernels.hpp"

namespace talus {

namespace {

template <class Real>
struct WallArgs {
  const WallFacets<Real>* facets = nullptr;  // per wall: device corners and grid
  const WallMotionData<Real>* motions = nullptr;
  const int* materials = nullptr;
  int walls = 0;
};

// The wall contacts run in three kernels, so that a particle's facets are clipped by threads of
// their own: one thread per (particle, wall) that walks the particle's facets (a cap's stand-in,
// the grid's facets within its bounding sphere, walls/wall_contact.hpp) and a warp of them does
// even work, where one thread per (particle, wall) doing it all left a warp waiting for its
// deepest particle and a small scene's few threads each clipping a dozen facets in a row.
//
// 1. One thread per (particle, wall), wall-major (thread k = w * count + i): its facets counted,
//    a run of that many slots reserved (one atomicAdd, flag wall_candidates, counted past the
//    capacity too) and the facets written there in order; run_first[k], run_count[k] say where.
//    (A small scene's: a warp per (particle, wall), wall_candidates_warp_kernel.)
template <class Real>
__device__ void wall_candidates_of(const ParticleView<Real>& p, const PairLawTables<Real>& t,
                                   const WallArgs<Real>& walls, long long k,
                                   int* __restrict__ run_first, int* __restrict__ run_count,
                                   WallCandidate<Real>* __restrict__ candidates, int capacity,
                                   int* flag) {
  const int w = static_cast<int>(k / p.count), i = static_cast<int>(k % p.count);
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  int count = 0;
  const Vec3<Real> centre = p.position.get(i);
  // The first kKept facets' corners kept as they are found, so that a particle near a few
  // facets (nearly all) walks its facets once; one near more walks them again to write them.
  constexpr int kKept = 4;
  Vec3<Real> kept[3 * kKept];
  if (!body.sphere) {
    visit_wall_facets(centre, body.shape.bounding_radius, walls.facets[w],
                      [&](const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
                        if (count < kKept) {
                          kept[3 * count] = a, kept[3 * count + 1] = b, kept[3 * count + 2] = c;
                        }
                        ++count;
                        return true;
                      });
  }
  const int first = count > 0 ? atomicAdd(flag + wall_candidates, count) : 0;
  run_first[k] = first;
  run_count[k] = count;
  if (count == 0 || first > capacity - count) return;  // none, or no room: the stage grows it
  if (count <= kKept) {
    for (int e = 0; e < count; ++e) {
      candidates[first + e] =
          WallCandidate<Real>{kept[3 * e], kept[3 * e + 1], kept[3 * e + 2], static_cast<int>(k)};
    }
    return;
  }
  int at = first;
  visit_wall_facets(centre, body.shape.bounding_radius, walls.facets[w],
                    [&](const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
                      candidates[at++] = WallCandidate<Real>{a, b, c, static_cast<int>(k)};
                      return true;
                    });
}

template <class Real>
__global__ void wall_candidates_kernel(ParticleView<Real> p, PairLawTables<Real> t,
                                       WallArgs<Real> walls, int* __restrict__ run_first,
                                       int* __restrict__ run_count,
                                       WallCandidate<Real>* __restrict__ candidates, int capacity,
                                       int* flag) {
  const long long k = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k >= static_cast<long long>(p.count) * walls.walls) return;
  wall_candidates_of(p, t, walls, k, run_first, run_count, candidates, capacity, flag);
}

// 1'. The same with a warp per (particle, wall), for small scenes (kWarpCandidatePairs), whose
//    step waits on the slowest thread: one thread walking a curved wall's grid cells (a cell
//    lists every segment near it, a rim every sliver of a cap's fan) took 0.1 to 0.4 ms on the
//    H100 for the built-in scene, most of it waiting on each facet's loads in turn. The warp
//    gathers the cells' lists into shared memory, sorts them (bitonic) and drops repeats, then
//    its lanes test 32 facets at a time and write the kept ones in ascending order (a ballot
//    each 32): the facets, the stand-ins and the order of visit_wall_facets, so the same
//    candidates. A cursor it cannot gather (no grid, more than kMergedCells cells, more than
//    kWarpListRoom entries) is walked by lane 0 as above.
constexpr int kWarpListRoom = 256;
constexpr long long kWarpCandidatePairs = 1 << 16;

template <class Real>
__global__ void __launch_bounds__(kBlock)
    wall_candidates_warp_kernel(ParticleView<Real> p, PairLawTables<Real> t, WallArgs<Real> walls,
                                int* __restrict__ run_first, int* __restrict__ run_count,
                                WallCandidate<Real>* __restrict__ candidates, int capacity,
                                int* flag) {
  __shared__ int listed[kBlock / 32][kWarpListRoom];
  __shared__ unsigned char kept[kBlock / 32][kWarpListRoom];
  const int lane = threadIdx.x & 31;
  const long long k = (static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x) >> 5;
  if (k >= static_cast<long long>(p.count) * walls.walls) return;  // the whole warp
  int* entries = listed[threadIdx.x >> 5];
  unsigned char* keep = kept[threadIdx.x >> 5];
  const int w = static_cast<int>(k / p.count), i = static_cast<int>(k % p.count);
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  const WallFacets<Real>& facets = walls.facets[w];
  const Vec3<Real> centre = p.position.get(i);
  const Real radius = body.shape.bounding_radius;
  int total = 0;
  FacetCursor<Real> near(0);
  if (!body.sphere) {
    near = facets.near(centre, radius);
    if (near.merging()) {
      for (int l = 0; l < near.lists(); ++l) total += near.list_end(l) - near.list_begin(l);
    }
  }
  if (body.sphere || !near.merging() || total > kWarpListRoom) {
    if (lane == 0)
      wall_candidates_of(p, t, walls, k, run_first, run_count, candidates, capacity, flag);
    return;
  }
  // The lists' entries, then padding, sorted ascending; entries at or above the present count
  // (an outlet's plate not yet there) are skipped as the cursor skips them.
  int size = 1;
  while (size < total) size <<= 1;
  for (int e = lane; e < size; e += 32) {
    int value = INT_MAX;
    if (e < total) {
      int l = 0, offset = 0;
      while (e - offset >= near.list_end(l) - near.list_begin(l)) {
        offset += near.list_end(l) - near.list_begin(l);
        ++l;
      }
      value = near.entries()[near.list_begin(l) + e - offset];
      if (value >= near.count()) value = INT_MAX;
    }
    entries[e] = value;
  }
  __syncwarp();
  for (int span = 2; span <= size; span <<= 1) {
    for (int stride = span >> 1; stride > 0; stride >>= 1) {
      for (int e = lane; e < size; e += 32) {
        const int partner = e ^ stride;
        if (partner > e) {
          const int x = entries[e], y = entries[partner];
          if ((x > y) == ((e & span) == 0)) entries[e] = y, entries[partner] = x;
        }
      }
      __syncwarp();
    }
  }
  // The patches that hold the particle's circle and those whose plane it does not reach, as
  // visit_wall_facets finds them (kMaxPatchesPerWall <= 32: a lane each).
  bool holds = false, clear = false;
  if (lane < facets.patch_count && facets.patches[lane].end <= facets.count) {
    const PatchHit<Real> hit =
        patch_hit(facets.patches[lane], facets.rotation, facets.translation, centre, radius);
    holds = hit.holds, clear = hit.clear;
  }
  const unsigned held = __ballot_sync(0xffffffffu, holds);
  const unsigned cleared = __ballot_sync(0xffffffffu, clear);
  // Each distinct facet kept or not: a held patch's first listed facet stands in for the patch,
  // its others and a clear patch's are skipped, any other facet kept within the bounding sphere.
  const auto patch_of = [&](int f) {
    for (int q = 0; q < facets.patch_count; ++q) {
      if (((held | cleared) >> q & 1u) && f >= facets.patches[q].first && f < facets.patches[q].end)
        return q;
    }
    return -1;
  };
  int count = 0;
  for (int base = 0; base < size; base += 32) {
    const int e = base + lane;
    bool take = false;
    if (e < size) {
      const int f = entries[e];
      if (f != INT_MAX && (e == 0 || entries[e - 1] != f)) {
        const int q = patch_of(f);
        if (q >= 0) {
          take = (held >> q & 1u) && (e == 0 || entries[e - 1] < facets.patches[q].first);
        } else {
          const Vec3<Real> a = facets.corners[3 * f], b = facets.corners[3 * f + 1];
          const Vec3<Real> c = facets.corners[3 * f + 2];
          const Vec3<Real> n = cross(b - a, c - a);
          const Real d = dot(n, centre - a);
          take = !(d * d > Real(1.001) * radius * radius * dot(n, n)) &&
                 !(norm(closest_point_on_triangle(centre, a, b, c) - centre) > radius);
        }
      }
      keep[e] = take ? 1 : 0;
    }
    count += __popc(__ballot_sync(0xffffffffu, take));
  }
  __syncwarp();
  int first = 0;
  if (lane == 0) {
    first = count > 0 ? atomicAdd(flag + wall_candidates, count) : 0;
    run_first[k] = first;
    run_count[k] = count;
  }
  first = __shfl_sync(0xffffffffu, first, 0);
  if (count == 0 || first > capacity - count) return;  // none, or no room: the stage grows it
  int at = first;
  for (int base = 0; base < size; base += 32) {
    const int e = base + lane;
    const bool take = e < size && keep[e] != 0;
    const unsigned taken = __ballot_sync(0xffffffffu, take);
    if (take) {
      const int f = entries[e];
      Vec3<Real> a, b, c;
      const int q = patch_of(f);
      if (q >= 0) {
        patch_stand_in(
            patch_hit(facets.patches[q], facets.rotation, facets.translation, centre, radius),
            radius, a, b, c);
      } else {
        a = facets.corners[3 * f], b = facets.corners[3 * f + 1], c = facets.corners[3 * f + 2];
      }
      candidates[at + __popc(taken & ((1u << lane) - 1))] =
          WallCandidate<Real>{a, b, c, static_cast<int>(k)};
    }
    at += __popc(taken);
  }
}

// 2. One thread per reserved slot: the facet clipped against its particle (slots beyond the
//    count, or all of them when the capacity was short, do nothing).
template <class Real>
__global__ void wall_clip_kernel(ParticleView<Real> p, PairLawTables<Real> t,
                                 const WallCandidate<Real>* __restrict__ candidates, int capacity,
                                 const int* __restrict__ flag,
                                 WallContact<Real>* __restrict__ clipped) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  const int used = flag[wall_candidates];
  if (e >= capacity || e >= used || used > capacity) return;
  const WallCandidate<Real> c = candidates[e];
  const int i = static_cast<int>(c.owner % p.count);
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  const Pose<Real> pose{p.position.get(i), p.orientation.get(i)};
  clipped[e] = clip_against_triangle_sized(body.shape, pose, c.a, c.b, c.c);
}

// 3. One thread per (particle, wall): its clipped facets summed in order (WallGeometrySum, the
//    host's arithmetic), a sphere's nearest facet found, the contact law applied. Only the
//    touching records are kept (a few per cent of the particle-wall pairs in a bed), appended in
//    arrival order to `touching[0 .. capacity)`, their number counted in flag[touching_walls] even
//    past the capacity (the caller then grows the buffer and runs the kernels again: they only
//    read the old histories, so a second run writes the same records); order_wall_contacts then
//    puts them in wall-major order. Law: the scene's contact law (contact/laws/).
template <class Law, class Real>
__global__ void wall_kernel(ParticleView<Real> p, PairLawTables<Real> t, WallArgs<Real> walls,
                            Real spring_dt, HistoryIn old,
                            const ContactHistoryData<Real>* __restrict__ histories,
                            const int* __restrict__ run_first, const int* __restrict__ run_count,
                            const WallContact<Real>* __restrict__ clipped, int clip_capacity,
                            WallContactRecord<Real>* __restrict__ touching, int capacity,
                            int* flag) {
  const long long k = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k >= static_cast<long long>(p.count) * walls.walls) return;
  if (flag[wall_candidates] > clip_capacity) return;  // run again with room for every facet
  const int w = static_cast<int>(k / p.count), i = static_cast<int>(k % p.count);
  const BodyProperties<Real>& body = t.bodies[p.template_id[i]];
  WallContactGeometry<Real> g;
  if (body.sphere) {
    g = sphere_wall_geometry(p.position.get(i), body.sphere_radius, walls.facets[w],
                             t.linear.stiffness);
  } else {
    WallGeometrySum<Law, Real> sum = wall_geometry_sum<Law>(p, t, i);
    const int first = run_first[k], end = first + run_count[k];
    for (int e = first; e < end && sum.add(clipped[e]); ++e) {
    }
    g = sum.finish();
  }
  const WallContactRecord<Real> r =
      wall_contact_with_geometry<Law>(p, t, i, w, walls.materials[w], walls.motions[w], spring_dt,
                                      old.keys, histories, old.size(), g);
  if (r.degenerate) atomicMin(flag + degenerate_wall, static_cast<int>(k));
  if (!r.in_contact) return;
  const int at = atomicAdd(flag + touching_walls, 1);
  if (at < capacity) touching[at] = r;
}

// The sort key of touching record j, wall-major as the host's order: wall * count + particle.
template <class Real>
__global__ void wall_contact_keys(const WallContactRecord<Real>* __restrict__ touching, int n,
                                  int count, long long* __restrict__ keys,
                                  int* __restrict__ index) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= n) return;
  keys[j] = static_cast<long long>(touching[j].wall) * count + touching[j].particle;
  index[j] = j;
}

// The touching records in key order, and each (particle, wall)'s place among them (wall_slot,
// -1 elsewhere: cleared before the wall kernel).
// (In a graph step for the whole buffer, n_at the touching count on the device.)
template <class Real>
__global__ void order_wall_contacts(const WallContactRecord<Real>* __restrict__ touching,
                                    const long long* __restrict__ sorted_keys,
                                    const int* __restrict__ sorted_index, int n,
                                    const int* __restrict__ n_at,
                                    WallContactRecord<Real>* __restrict__ contacts,
                                    int* __restrict__ wall_slot) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n || (n_at && s >= *n_at)) return;
  contacts[s] = touching[sorted_index[s]];
  wall_slot[sorted_keys[s]] = s;
}

// A moving wall's corners where it is now (one thread per corner): the mesh-frame corner moved
// in double by the transform the host computed (wall_transform), then rounded to Real, as
// WallContactStage::place does on the host (the same arithmetic, but for nvcc's fused
// multiply-adds). Placing here rather than on the host saves the host's loop over every corner
// and the upload of all of them each step; only the transform crosses.
// The transform is the wall's placement, copied to the device with the step's other inputs.
template <class Real>
__global__ void place_wall_kernel(const Vec3d* __restrict__ mesh_corners, int n,
                                  const WallPlacement<Real>* __restrict__ placement,
                                  Vec3<Real>* __restrict__ corners) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  corners[k] = Vec3<Real>(rotate(placement->corner_rotation, mesh_corners[k]) +
                          placement->corner_translation);
}

// Every wall's view on the device where the wall is now (one thread per wall): its present
// facets and transform, from its placement.
template <class Real>
__global__ void set_wall_views_kernel(WallFacets<Real>* __restrict__ views,
                                      const WallPlacement<Real>* __restrict__ placements,
                                      int walls) {
  const int w = blockIdx.x * blockDim.x + threadIdx.x;
  if (w >= walls) return;
  views[w].count = placements[w].count;
  views[w].rotation = placements[w].rotation;
  views[w].translation = placements[w].translation;
}

// A graph step's sort keys (wall_contact_keys) for every record the buffer holds: those past the
// touching count (read on the device) get `beyond`, above every real key, and sort last.
template <class Real>
__global__ void wall_contact_keys_all(const WallContactRecord<Real>* __restrict__ touching,
                                      int capacity, const int* __restrict__ touching_count,
                                      int count, long long beyond, long long* __restrict__ keys,
                                      int* __restrict__ index) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= capacity) return;
  keys[j] = j < *touching_count
                ? static_cast<long long>(touching[j].wall) * count + touching[j].particle
                : beyond;
  index[j] = j;
}

// A graph step's next history store (copy_histories) for every entry the buffer holds: those
// past the touching count get a key above every real one, and sort last.
template <class Record, class Real>
__global__ void copy_histories_all(const Record* __restrict__ contacts, int capacity,
                                   const int* __restrict__ touching_count,
                                   PairKey* __restrict__ keys,
                                   ContactHistoryData<Real>* __restrict__ histories) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= capacity) return;
  if (k < *touching_count) {
    keys[k] = contacts[k].key;
    histories[k] = contacts[k].history;
  } else {
    keys[k] = PairKey{LLONG_MAX, LLONG_MAX};
    histories[k] = ContactHistoryData<Real>();
  }
}

// A graph step's history store back into the buffers the graph reads (the current ones), and its
// count on the device; nothing when the step did not finish (its store stays).
template <class Real>
__global__ void keep_history_kernel(const PairKey* __restrict__ next_keys,
                                    const ContactHistoryData<Real>* __restrict__ next, int capacity,
                                    const int* __restrict__ touching_count, AbortCheck abort,
                                    PairKey* __restrict__ keys,
                                    ContactHistoryData<Real>* __restrict__ histories,
                                    int* __restrict__ count) {
  if (abort.aborted()) return;
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  const int n = *touching_count;
  if (k == 0) *count = n;
  if (k >= capacity || k >= n) return;
  keys[k] = next_keys[k];
  histories[k] = next[k];
}

// The next history store from the touching contacts (sorted afterwards).
template <class Record, class Real>
__global__ void copy_histories(const Record* __restrict__ contacts, int count,
                               PairKey* __restrict__ keys,
                               ContactHistoryData<Real>* __restrict__ histories) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  keys[k] = contacts[k].key;
  histories[k] = contacts[k].history;
}

// The energy probe's sums over the ordered wall contacts (one thread per contact; a few per
// cent of the particle-wall pairs, so plain atomics).
// In a graph step launched for the capacity n, the count read on the device (n_at).
template <class Real>
__global__ void wall_energy_kernel(const WallContactRecord<Real>* __restrict__ contacts, int n,
                                   const int* __restrict__ n_at, AbortCheck abort,
                                   double* __restrict__ sums) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (abort.aborted() || k >= n || (n_at && k >= *n_at)) return;
  const WallContactRecord<Real>& c = contacts[k];
  atomicAdd(sums + sum_dissipation, double(c.dissipation));
  atomicAdd(sums + sum_normal, double(c.normal_energy));
  atomicAdd(sums + sum_tangential, double(c.tangential_energy));
  atomicAdd(sums + sum_wall_power, double(c.wall_power));
}

}  // namespace

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
  upload(time);
}

template <class Real>
DeviceWallStage<Real>::~DeviceWallStage() {
  if (placements_host_) cudaFreeHost(placements_host_);  // no throw from a destructor
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
  shared_.temp.grow_to(bytes);
  if (tangential_history()) {
    bytes = 0;
    TALUS_CUDA_CHECK(cub::DeviceMergeSort::SortPairs(nullptr, bytes, history_.keys[next].data(),
                                                     history_.histories[next].data(), capacity,
                                                     KeyLess()));
    shared_.temp.grow_to(bytes);
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
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
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
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
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
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
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
    cub_call(shared_.temp, [&](void* t, std::size_t& b) {
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
         motions_.size() * sizeof(WallMotionData<Real>) + history_.bytes() +
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

template class DeviceWallStage<double>;
template class DeviceWallStage<float>;

}  // namespace talus
