// The kernels and device-side helpers of the CUDA step (cuda_step.cu, its only includer): one
// thread per particle, per candidate pair or per (particle, wall), each calling the TALUS_HD
// function the host step calls; the accumulation over each particle's contacts in the host's
// order; the double-buffered device history store. Internal: everything is in an unnamed
// namespace of this one translation unit.
#pragma once

#include <cub/cub.cuh>

#include <algorithm>
#include <chrono>
#include <climits>
#include <vector>

#include "solver/core/device_buffer.hpp"
#include "solver/step/contact_stage.hpp"
#include "solver/step/host_step.hpp"
#include "solver/step/wall_stage.hpp"

namespace talus {

namespace {

constexpr int kBlock = 128;

int blocks_for(long long n) {
  return static_cast<int>((n + kBlock - 1) / kBlock);
}

double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Flags the kernels raise (the lowest index wins: atomicMin), read after their stage.
enum Flag {
  failed_rotation = 0,
  degenerate_pair = 1,
  degenerate_wall = 2,
  selected = 3,
  touching_pairs = 4,
  deferred_pairs = 5,
  touching_walls = 6,
  flags
};

// ---- Per-particle stages (particle_kernels.hpp) ----

template <class Real>
__global__ void integrate_begin_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies,
                                       Real dt, int* flag) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= p.count) return;
  if (!integrate_begin(p, bodies, i, dt)) atomicMin(flag + failed_rotation, i);
}

template <class Real>
__global__ void clear_forces_kernel(ParticleView<Real> p) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < p.count) clear_forces(p, i);
}

template <class Real>
__global__ void gravity_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies,
                               Vec3<Real> g) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < p.count) add_gravity(p, bodies, i, g);
}

template <class Real>
__global__ void drag_kernel(ParticleView<Real> p, Real alpha) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < p.count) add_drag(p, i, alpha);
}

template <class Real>
__global__ void integrate_end_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies,
                                     Real dt) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < p.count) integrate_end(p, bodies, i, dt);
}

// ---- Pair contacts (pair_kernels.hpp) ----

// The workspace capacity of the ordered pair (ia, ib): 0 when its geometry needs none (linear
// model, spheres), else overlap_capacity_for of the two templates' faces, as the host picks it.
template <class Real>
TALUS_HD int pair_capacity(const BodyProperties<Real>& a, const BodyProperties<Real>& b,
                           bool volume_model) {
  if (!volume_model || a.sphere || b.sphere) return 0;
  return overlap_capacity_for(a.faces + b.faces);
}

struct HistoryIn {
  const PairKey* keys;
  int count;
};

// What a touching candidate slot k holds for the accumulation (deterministic mode): the force on
// its ordered A and the contact point; slot_state[k] says whether it touches and which of
// pairs[k].a, pairs[k].b is A.
template <class Real>
struct SlotForce {
  Vec3<Real> force_on_a;  // N; B gets the opposite
  Vec3<Real> point;       // m
};
enum SlotState : unsigned char { slot_apart = 0, slot_a_first = 1, slot_b_first = 2 };

template <class Real>
__device__ void atomic_add(const Soa3<Real>& s, int i, const Vec3<Real>& v) {
  atomicAdd(s.x + i, v.x);
  atomicAdd(s.y + i, v.y);
  atomicAdd(s.z + i, v.z);
}

// The rest of slot k's work once its geometry g is known: the force law with the slot's history
// (read and replaced in place: the list, and with it every pair's slot, stays until the next
// rebuild, which carries the histories over), the slot's state, and the force: added to the
// two particles at once by atomics (Atomic, deterministic: false) or kept in the slot for
// accumulate_kernel. Returns whether the pair touches.
template <class Real, bool Atomic>
__device__ bool finish_slot(const ParticleView<Real>& p, const PairLawTables<Real>& t,
                            const ContactPair& pair, int ia, int ib, int k,
                            const PairGeometryData<Real>& g, Real spring_dt,
                            ContactHistoryData<Real>* __restrict__ histories,
                            SlotForce<Real>* __restrict__ forces,
                            unsigned char* __restrict__ slot_state, int* flag) {
  ContactHistoryData<Real> previous;
  if (histories && g.in_contact) previous = histories[k];
  const PairContactRecord<Real> r = pair_contact_force(p, t, ia, ib, g, spring_dt, previous);
  if (histories) histories[k] = r.in_contact ? r.history : ContactHistoryData<Real>();
  slot_state[k] = !r.in_contact ? slot_apart : (ia == pair.a ? slot_a_first : slot_b_first);
  if (r.degenerate) atomicMin(flag + degenerate_pair, k);
  if (!r.in_contact) return false;
  if constexpr (Atomic) {
    atomic_add(p.force, ia, r.force_on_a);
    atomic_add(p.force, ib, -r.force_on_a);
    if (p.torque.present()) {
      atomic_add(p.torque, ia, cross(r.point - p.position.get(ia), r.force_on_a));
      atomic_add(p.torque, ib, cross(r.point - p.position.get(ib), -r.force_on_a));
    }
  } else {
    forces[k] = SlotForce<Real>{r.force_on_a, r.point};
  }
  return true;
}

// Adds the block's touching slots to *touching (one atomic per block). Every thread calls it.
__device__ void count_touching(bool in_contact, int* touching) {
  const int block_touching = __syncthreads_count(in_contact);
  if (threadIdx.x == 0 && block_touching > 0) atomicAdd(touching, block_touching);
}

// What each slot needs besides the list and its own arrays.
template <class Real>
struct SlotArgs {
  const ContactPair* pairs = nullptr;
  Real spring_dt = 0;
  ContactHistoryData<Real>* histories = nullptr;  // volume model
  SlotForce<Real>* forces = nullptr;              // deterministic mode
  unsigned char* slot_state = nullptr;
  int* flag = nullptr;
  int* touching = nullptr;
};

// One thread per slot of the pair list (or of the given `slots`), the whole pair in one thread;
// this launch computes only the pairs of workspace capacity `Capacity` (another launch per
// capacity present in the scene computes the rest), so a thread's local memory is the
// workspace of its own template pair. Used for the linear model and spheres (Capacity 0), for
// template pairs with more than 64 faces together, and for the few pairs the phased kernels
// defer.
template <class Real, int Capacity, bool Atomic>
__global__ void __launch_bounds__(kBlock)
    pair_kernel(ParticleView<Real> p, PairLawTables<Real> t, SlotArgs<Real> s, const int* slots,
                int count) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  bool in_contact = false;
  if (j < count) {
    const int k = slots ? slots[j] : j;
    const ContactPair pair = s.pairs[k];
    int ia, ib;
    order_pair(p, t, pair.a, pair.b, ia, ib);
    const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
    const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
    if (pair_capacity(a, b, t.volume_model) == Capacity) {
      PairGeometryData<Real> g;
      if constexpr (Capacity == 0) {
        g = simple_pair_geometry(p, t, ia, ib);
      } else {
        const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
        const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
        OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
        g = polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace);
      }
      in_contact = finish_slot<Real, Atomic>(p, t, pair, ia, ib, k, g, s.spring_dt, s.histories,
                                             s.forces, s.slot_state, s.flag);
    }
  }
  count_touching(in_contact, s.touching);
}

// ---- The phased pair stage: polyhedron pairs of at most 64 faces together ----
// A thread's overlap workspace is sized for every face plane of its two templates (3.7 KB in
// double for two dodecahedra), but a shallow contact keeps only a few planes after culling.
// Phase 1 culls (GJK, then overlap_cull_mask: a 64-bit mask of the kept planes); the slots are
// then sorted by their number of kept planes, and phase 2 builds the polytope with a workspace
// of 8, 16, 32 or 64 planes, one launch per size over its range of the sorted slots, so a warp's
// pairs do similar work in little local memory (the overlap batch's phased_sorted kernel,
// benchmarks/README.md). The result is overlap_polyhedra's bit for bit (overlap_from_mask).
constexpr int kMaxMaskPlanes = 64;
constexpr unsigned char kOtherPath = 255;  // a slot phase 1 leaves to pair_kernel

// Phase 1. key[k]: 0 when the slot is settled here (GJK or the culling decides it apart),
// m + 1 with m kept planes, kOtherPath when the pair is not a phased one (a sphere, the linear
// model, more than 64 faces). `histogram` counts the keys 0 .. 65 (one atomic per block and key).
// Register-bound: 164 registers a thread left 6 warps per SM; capped for 4 blocks (16 warps)
// the kernel ran 1.2x faster in the step (H100, the 1e6 bed: pair stage 23.4 -> 21.5 ms), while
// the polytope kernel's caps (6 or 8 blocks) spilled and lost 1.2-1.5x.
template <class Real>
__global__ void __launch_bounds__(kBlock, 4)
    cull_pair_kernel(ParticleView<Real> p, PairLawTables<Real> t, SlotArgs<Real> s, int count,
                     unsigned long long* __restrict__ masks, unsigned char* __restrict__ keys,
                     int* __restrict__ order, int* __restrict__ histogram) {
  __shared__ int block_histogram[kMaxMaskPlanes + 2];
  for (int b = threadIdx.x; b < kMaxMaskPlanes + 2; b += blockDim.x) block_histogram[b] = 0;
  __syncthreads();
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < count) {
    const ContactPair pair = s.pairs[k];
    int ia, ib;
    order_pair(p, t, pair.a, pair.b, ia, ib);
    const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
    const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
    unsigned char key = kOtherPath;
    if (pair_capacity(a, b, t.volume_model) > 0 && a.faces + b.faces <= kMaxMaskPlanes) {
      const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
      const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
      // As polyhedra_volume_geometry: GJK first, then the overlap's own culling.
      PairGeometryData<Real> g;
      int kept = -1;
      if (gjk_intersect(a.shape, pose_a, b.shape, pose_b).intersecting) {
        OverlapResult<Real> result;
        unsigned long long mask = 0;
        kept = overlap_cull_mask(a.shape, pose_a, b.shape, pose_b, OverlapOptions(), mask, result);
        if (kept >= 0)
          masks[k] = mask;
        else
          g = volume_geometry_from(result);  // separate, touching or degenerate: no contact
      }
      if (kept < 0) {
        finish_slot<Real, false>(p, t, pair, ia, ib, k, g, s.spring_dt, s.histories, s.forces,
                                 s.slot_state, s.flag);
        key = 0;
      } else {
        key = static_cast<unsigned char>(kept + 1);
      }
      atomicAdd(&block_histogram[key], 1);
    }
    keys[k] = key;
    order[k] = k;
  }
  __syncthreads();
  for (int b = threadIdx.x; b < kMaxMaskPlanes + 2; b += blockDim.x)
    if (block_histogram[b] > 0) atomicAdd(&histogram[b], block_histogram[b]);
}

// Phase 2 over the sorted slots order[begin .. begin + count): the polytope from the slot's mask
// in a workspace of Cap planes, then the force. A pair the workspace cannot hold (the hull
// needs more room than its planes suggest; rare) is appended to `deferred` for pair_kernel.
template <class Real, int Cap, bool Atomic>
__global__ void __launch_bounds__(kBlock)
    polytope_pair_kernel(ParticleView<Real> p, PairLawTables<Real> t, SlotArgs<Real> s,
                         const int* __restrict__ order, int begin, int count,
                         const unsigned long long* __restrict__ masks, int* deferred,
                         int* deferred_count) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  bool in_contact = false;
  if (j < count) {
    const int k = order[begin + j];
    const ContactPair pair = s.pairs[k];
    int ia, ib;
    order_pair(p, t, pair.a, pair.b, ia, ib);
    const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
    const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
    const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
    const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
    OverlapWorkspace<Real, Cap> workspace;  // per-thread local memory
    const OverlapResult<Real> overlap =
        overlap_from_mask(a.shape, pose_a, b.shape, pose_b, masks[k], workspace);
    if (overlap.workspace_overrun) {
      deferred[atomicAdd(deferred_count, 1)] = k;
    } else {
      in_contact =
          finish_slot<Real, Atomic>(p, t, pair, ia, ib, k, volume_geometry_from(overlap),
                                    s.spring_dt, s.histories, s.forces, s.slot_state, s.flag);
    }
  }
  count_touching(in_contact, s.touching);
}

// ---- The pair list's rebuild (a Verlet list: kept while no particle has moved skin / 2) ----

// The largest squared displacement since the list was built, as the bits of a non-negative
// double (their integer order is their numeric order): one atomicMax per block.
template <class Real>
__global__ void max_displacement_kernel(ParticleView<Real> p, const Real* __restrict__ x0,
                                        const Real* __restrict__ y0, const Real* __restrict__ z0,
                                        unsigned long long* largest) {
  using BlockReduce = cub::BlockReduce<double, kBlock>;
  __shared__ typename BlockReduce::TempStorage temp;
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  double d2 = 0;
  if (i < p.count) {
    const double dx = double(p.position.x[i]) - double(x0[i]);
    const double dy = double(p.position.y[i]) - double(y0[i]);
    const double dz = double(p.position.z[i]) - double(z0[i]);
    d2 = dx * dx + dy * dy + dz * dz;
  }
  const double block_max =
      BlockReduce(temp).Reduce(d2, [](double u, double v) { return u < v ? v : u; });
  if (threadIdx.x == 0)
    atomicMax(largest, static_cast<unsigned long long>(__double_as_longlong(block_max)));
}

// A touching slot's history, keyed by the pair's global ids, for the next list.
template <class Real>
struct KeyedHistory {
  PairKey key;
  ContactHistoryData<Real> history;
  bool touching = false;
};

template <class Real>
__global__ void key_histories(const long long* __restrict__ global_id,
                              const ContactPair* __restrict__ pairs, int count,
                              const unsigned char* __restrict__ slot_state,
                              const ContactHistoryData<Real>* __restrict__ histories,
                              KeyedHistory<Real>* __restrict__ keyed) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  KeyedHistory<Real> h;
  h.touching = slot_state[k] != slot_apart;
  h.key = make_pair_key(global_id[pairs[k].a], global_id[pairs[k].b]);
  h.history = histories[k];
  keyed[k] = h;
}

// Each slot of the new list takes its pair's history from the store (sorted by key; the default
// for a pair that was not touching), and starts apart.
template <class Real>
__global__ void carry_histories(const long long* __restrict__ global_id,
                                const ContactPair* __restrict__ pairs, int count,
                                const KeyedHistory<Real>* __restrict__ store, int stored,
                                ContactHistoryData<Real>* __restrict__ histories,
                                unsigned char* __restrict__ slot_state) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  const PairKey key = make_pair_key(global_id[pairs[k].a], global_id[pairs[k].b]);
  int lo = 0, hi = stored;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (key_less(store[mid].key, key)) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  const bool found = lo < stored && store[lo].key.low == key.low && store[lo].key.high == key.high;
  if (histories) histories[k] = found ? store[lo].history : ContactHistoryData<Real>();
  slot_state[k] = slot_apart;
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

// Two CSR entries per candidate slot k: (a, k) and (b, k).
__global__ void emit_entries(const ContactPair* __restrict__ pairs, int count,
                             int* __restrict__ particle, int* __restrict__ slot) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  particle[2 * k] = pairs[k].a;
  particle[2 * k + 1] = pairs[k].b;
  slot[2 * k] = slot[2 * k + 1] = k;
}

// begin[i], end[i]: particle i's range of the sorted entries (both 0 when it has none).
__global__ void entry_ranges(const int* __restrict__ sorted_particle, int n, int* begin, int* end) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n) return;
  const int i = sorted_particle[s];
  if (s == 0 || sorted_particle[s - 1] != i) begin[i] = s;
  if (s == n - 1 || sorted_particle[s + 1] != i) end[i] = s + 1;
}

// ---- Wall contacts (wall_kernels.hpp) ----

template <class Real>
struct WallArgs {
  const WallFacets<Real>* facets = nullptr;  // per wall: device corners and grid
  const WallMotionData<Real>* motions = nullptr;
  const int* materials = nullptr;
  int walls = 0;
};

// One thread per (particle, wall), wall-major (thread w * count + i). Only the touching records
// are kept (a few per cent of the particle-wall pairs in a bed), appended in arrival order to
// `touching[0 .. capacity)`, their number counted in flag[touching_walls] even past the capacity
// (the caller then grows the buffer and runs the kernel again: it only reads the old histories, so
// a second run writes the same records); order_wall_contacts then puts them in wall-major order.
template <class Real>
__global__ void wall_kernel(ParticleView<Real> p, PairLawTables<Real> t, WallArgs<Real> walls,
                            Real spring_dt, HistoryIn old,
                            const ContactHistoryData<Real>* __restrict__ histories,
                            WallContactRecord<Real>* __restrict__ touching, int capacity,
                            int* flag) {
  const long long k = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k >= static_cast<long long>(p.count) * walls.walls) return;
  const int w = static_cast<int>(k / p.count), i = static_cast<int>(k % p.count);
  const WallContactRecord<Real> r =
      wall_contact(p, t, i, w, walls.materials[w], walls.facets[w], walls.motions[w], spring_dt,
                   old.keys, histories, old.count);
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
template <class Real>
__global__ void order_wall_contacts(const WallContactRecord<Real>* __restrict__ touching,
                                    const long long* __restrict__ sorted_keys,
                                    const int* __restrict__ sorted_index, int n,
                                    WallContactRecord<Real>* __restrict__ contacts,
                                    int* __restrict__ wall_slot) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n) return;
  contacts[s] = touching[sorted_index[s]];
  wall_slot[sorted_keys[s]] = s;
}

// A moving wall's corners where it is now (one thread per corner): the mesh-frame corner moved
// in double by the transform the host computed (wall_transform), then rounded to Real, as
// WallContactStage::place does on the host (the same arithmetic, but for nvcc's fused
// multiply-adds). Placing here rather than on the host saves the host's loop over every corner
// and the upload of all of them each step; only the transform crosses.
template <class Real>
__global__ void place_wall_kernel(const Vec3d* __restrict__ mesh_corners, int n, Quatd rotation,
                                  Vec3d translation, Vec3<Real>* __restrict__ corners) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  corners[k] = Vec3<Real>(rotate(rotation, mesh_corners[k]) + translation);
}

// ---- Accumulation: one thread per particle, its touching slots in pair order, then its walls ----

template <class Real>
__global__ void accumulate_kernel(ParticleView<Real> p, const ContactPair* __restrict__ pairs,
                                  const unsigned char* __restrict__ slot_state,
                                  const SlotForce<Real>* __restrict__ forces,
                                  const int* __restrict__ sorted_slot,
                                  const int* __restrict__ begin, const int* __restrict__ end,
                                  const WallContactRecord<Real>* __restrict__ wall_contacts,
                                  const int* __restrict__ wall_slot, int walls) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= p.count) return;
  // The same additions, in the same order, as add_pair_force and add_wall_force on the host: the
  // list is sorted by (a, b), so a particle's touching slots come in the host's contact order.
  Vec3<Real> f = p.force.get(i), t;
  const bool torque = p.torque.present();
  if (torque) t = p.torque.get(i);
  const Vec3<Real> x = p.position.get(i);
  if (forces) {
    for (int s = begin[i]; s < end[i]; ++s) {
      const int k = sorted_slot[s];
      const unsigned char state = slot_state[k];
      if (state == slot_apart) continue;
      const SlotForce<Real> c = forces[k];
      const int a = state == slot_a_first ? pairs[k].a : pairs[k].b;
      if (a == i) {
        f = f + c.force_on_a;
        if (torque) t = t + cross(c.point - x, c.force_on_a);
      } else {
        f = f - c.force_on_a;
        if (torque) t = t + cross(c.point - x, -c.force_on_a);
      }
    }
  }
  for (int w = 0; w < walls; ++w) {
    const int slot = wall_slot[static_cast<long long>(w) * p.count + i];
    if (slot < 0) continue;
    const WallContactRecord<Real>& c = wall_contacts[slot];
    f = f + c.force;
    if (torque) t = t + cross(c.point - x, c.force);
  }
  p.force.set(i, f);
  if (torque) p.torque.set(i, t);
}

struct KeyLess {
  __host__ __device__ bool operator()(const PairKey& p, const PairKey& q) const {
    return key_less(p, q);
  }
  template <class Real>
  __host__ __device__ bool operator()(const KeyedHistory<Real>& p,
                                      const KeyedHistory<Real>& q) const {
    return key_less(p.key, q.key);
  }
};

struct Touching {
  template <class Real>
  __host__ __device__ bool operator()(const KeyedHistory<Real>& h) const {
    return h.touching;
  }
};

template <class T>
std::vector<T> download(const T* device, std::size_t count) {
  std::vector<T> host(count);
  if (count > 0) {
    TALUS_CUDA_CHECK(cudaMemcpy(host.data(), device, count * sizeof(T), cudaMemcpyDeviceToHost));
  }
  return host;
}

// A sorted history store (keys and their histories) in device memory, double-buffered: the
// pair stage reads the current one while the next is written into the other.
template <class Real>
struct DeviceHistory {
  DeviceBuffer<PairKey> keys[2];
  DeviceBuffer<ContactHistoryData<Real>> histories[2];
  int current = 0, count = 0;
  HistoryIn in() const { return {keys[current].data(), count}; }
  const ContactHistoryData<Real>* values() const { return histories[current].data(); }
  std::size_t bytes() const {
    return (keys[0].size() + keys[1].size()) * sizeof(PairKey) +
           (histories[0].size() + histories[1].size()) * sizeof(ContactHistoryData<Real>);
  }
};

// The host law tables copied into one device buffer `storage`, in the same layout; the returned
// tables point into it and at the device template views `device_bodies`.
template <class Real>
PairLawTables<Real> upload_law_tables(const PairLawTables<Real>& h,
                                      const BodyProperties<Real>* device_bodies,
                                      DeviceBuffer<Real>& storage) {
  const int materials = h.materials, pairs = materials * materials;
  std::vector<Real> values;
  values.insert(values.end(), h.youngs_modulus, h.youngs_modulus + materials);
  values.insert(values.end(), h.poisson_ratio, h.poisson_ratio + materials);
  values.insert(values.end(), h.pair_friction, h.pair_friction + pairs);
  values.insert(values.end(), h.pair_restitution, h.pair_restitution + pairs);
  values.insert(values.end(), h.pair_damping_ratio, h.pair_damping_ratio + pairs);
  storage.upload(values);
  PairLawTables<Real> d = h;
  const Real* base = storage.data();
  d.bodies = device_bodies;
  d.youngs_modulus = base;
  d.poisson_ratio = base + materials;
  d.pair_friction = base + 2 * materials;
  d.pair_restitution = base + 2 * materials + pairs;
  d.pair_damping_ratio = base + 2 * materials + 2 * pairs;
  return d;
}

}  // namespace

}  // namespace talus
