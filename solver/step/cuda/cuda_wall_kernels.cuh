// The CUDA wall stage's kernels (cuda_wall_stage.cuh): the facets to clip (a thread, or for
// small scenes a warp, per particle and wall), the clipping (a thread per facet), the law over
// each particle's clipped facets, the ordering of the touching records, the walls' placement and
// the history store. Included only by cuda_wall_stage.cu.
#pragma once

#include <climits>

#include "solver/step/cuda/cuda_step_common.cuh"
#include "solver/step/cuda/cuda_wall_stage.cuh"
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

}  // namespace talus
