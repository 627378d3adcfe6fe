// The CUDA step's pair contacts (cuda_pair_stage.cuh): the kernels over the list's slots and
// their launches, compiled once per precision in a generated file of its own
// (solver/CMakeLists.txt: `template class DevicePairStage<float>` and `<double>` side by side in
// a parallel build). Included only from those files.
#pragma once

#include "solver/step/cuda/cuda_pair_stage.cuh"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "solver/contact/contact_laws.hpp"
#include "solver/step/pair_kernels.hpp"

namespace talus {

namespace {

// ---- Pair contacts (pair_kernels.hpp) ----

// The workspace capacity of the ordered pair (ia, ib) under Law: 0 when its geometry needs none
// (the linear law, spheres), else overlap_capacity_for of the two templates' faces, as the host
// picks it.
template <class Law, class Real>
TALUS_HD int pair_capacity(const BodyProperties<Real>& a, const BodyProperties<Real>& b) {
  if (!Law::kVolumeGeometry || a.sphere || b.sphere) return 0;
  return overlap_capacity_for(a.faces + b.faces);
}

template <class Real>
__device__ void atomic_add(const Soa3<Real>& s, int i, const Vec3<Real>& v) {
  atomicAdd(s.x + i, v.x);
  atomicAdd(s.y + i, v.y);
  atomicAdd(s.z + i, v.z);
}

// Whether this rank counts the contact of particles a and b (its energies and its number): in
// one process (owned INT_MAX) every one; decomposed (docs/parallel.md), those of two own
// particles and those whose own particle has the lower global id, so that each contact is
// counted by one rank.
template <class Real>
__device__ bool attributed(const ParticleView<Real>& p, int a, int b, int owned) {
  const bool own_a = a < owned, own_b = b < owned;
  if (own_a && own_b) return true;
  return own_a ? p.global_id[a] < p.global_id[b] : own_b && p.global_id[b] < p.global_id[a];
}

// The rest of slot k's work once its geometry g is known: the force law with the slot's history
// (read and replaced in place: the list, and with it every pair's slot, stays until the next
// rebuild, which carries the histories over), the slot's state, and the force: added to the
// two particles at once by atomics (Atomic, deterministic: false) or kept in the slot for
// accumulate_kernel. Returns whether the pair touches and is this rank's to count (attributed).
template <class Law, class Real, bool Atomic>
__device__ bool finish_slot(const ParticleView<Real>& p, const PairLawTables<Real>& t,
                            const ContactPair& pair, int ia, int ib, int k,
                            const PairGeometryData<Real>& g, Real spring_dt,
                            ContactHistoryData<Real>* __restrict__ histories,
                            SlotForce<Real>* __restrict__ forces,
                            unsigned char* __restrict__ slot_state, int* flag,
                            double* __restrict__ energy_sums, int owned) {
  ContactHistoryData<Real> previous;
  if (histories && g.in_contact) previous = histories[k];
  const PairContactRecord<Real> r = pair_contact_force<Law>(p, t, ia, ib, g, spring_dt, previous);
  if (histories) histories[k] = r.in_contact ? r.history : ContactHistoryData<Real>();
  slot_state[k] = !r.in_contact ? slot_apart : (ia == pair.a ? slot_a_first : slot_b_first);
  if (r.degenerate) atomicMin(flag + degenerate_pair, k);
  if (!r.in_contact) return false;
  const bool counted = attributed(p, ia, ib, owned);
  if (energy_sums && counted) {
    atomicAdd(energy_sums + sum_dissipation, double(r.dissipation));
    atomicAdd(energy_sums + sum_normal, double(r.normal_energy));
    atomicAdd(energy_sums + sum_tangential, double(r.tangential_energy));
  }
  if constexpr (Atomic) {
    atomic_add(p.force, ia, r.force_on_a);
    atomic_add(p.force, ib, -r.force_on_a);
    if (p.torque.present()) {
      atomic_add(p.torque, ia, cross(r.point - p.position.get(ia), r.force_on_a) + r.couple);
      atomic_add(p.torque, ib, cross(r.point - p.position.get(ib), -r.force_on_a) - r.couple);
    }
  } else {
    forces[k] = SlotForce<Real>{r.force_on_a, r.point, r.couple};
  }
  return counted;
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
  ContactHistoryData<Real>* histories = nullptr;  // a law with a tangential history
  SlotForce<Real>* forces = nullptr;              // deterministic mode
  unsigned char* slot_state = nullptr;
  int* flag = nullptr;
  int* touching = nullptr;
  bool gjk_filter = true;         // DeviceStepShared::gjk_filter
  double* energy_sums = nullptr;  // DeviceStepShared::energy_sums
  int owned = INT_MAX;            // decomposed: DeviceStepShared::owned (attributed)
  int first = 0;                  // the launch's first slot: its slot j is the list's first + j
};

// One thread per slot of the launch's range (or of the given `slots`, numbered from its start),
// the whole pair in one thread;
// this launch computes only the pairs of workspace capacity `Capacity` (another launch per
// capacity present in the scene computes the rest), so a thread's local memory is the
// workspace of its own template pair. Used for the linear model and spheres (Capacity 0), for
// template pairs with more than 64 faces together, and for the few pairs the phased kernels
// defer. Law: the scene's contact law (contact/laws/). count_at: the number of `slots` on the
// device (a graph step, launched for `count`, their capacity), else null.
template <class Law, class Real, int Capacity, bool Atomic>
__global__ void __launch_bounds__(kBlock)
    pair_kernel(ParticleView<Real> p, PairLawTables<Real> t, SlotArgs<Real> s, const int* slots,
                int count, const int* count_at) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (count_at) count = min(count, *count_at);
  bool in_contact = false;
  if (j < count) {
    const int k = s.first + (slots ? slots[j] : j);
    const ContactPair pair = s.pairs[k];
    int ia, ib;
    order_pair(p, t, pair.a, pair.b, ia, ib);
    const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
    const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
    if (pair_capacity<Law>(a, b) == Capacity) {
      PairGeometryData<Real> g;
      if constexpr (Capacity == 0) {
        g = simple_pair_geometry<Law>(p, t, ia, ib);
      } else {
        const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
        const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
        OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
        g = polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace);
      }
      in_contact =
          finish_slot<Law, Real, Atomic>(p, t, pair, ia, ib, k, g, s.spring_dt, s.histories,
                                         s.forces, s.slot_state, s.flag, s.energy_sums, s.owned);
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
// benchmarks/README.md). The result is overlap_polyhedra's bit for bit (overlap_from_mask). The
// sort, the ranges and the deferral list are the overlap batch's too (phased_overlap.cuh).
constexpr unsigned char kOtherPath = 255;  // a slot phase 1 leaves to pair_kernel

// Phase 1. key[k]: 0 when the slot is settled here (GJK or the culling decides it apart),
// m + 1 with m kept planes, kOtherPath when the pair is not a phased one (a sphere, the linear
// model, more than 64 faces). `histogram` counts the keys 0 .. 65 (one atomic per block and key).
// Register-bound: uncapped, its registers left few warps per SM; capped for 4 blocks (16 warps)
// it ran faster in the step, while caps on the polytope kernel (6 or 8 blocks) spilled and made
// it slower (the registers, warps and times: benchmarks/history/README.md). Law: a law of volume
// geometry (the phased path is only theirs).
template <class Law, class Real>
__global__ void __launch_bounds__(kBlock, 4)
    cull_pair_kernel(ParticleView<Real> p, PairLawTables<Real> t, SlotArgs<Real> s, int count,
                     unsigned long long* __restrict__ masks, unsigned char* __restrict__ keys,
                     int* __restrict__ order, int* __restrict__ histogram) {
  __shared__ int block_histogram[kPhasedKeys];
  for (int b = threadIdx.x; b < kPhasedKeys; b += blockDim.x) block_histogram[b] = 0;
  __syncthreads();
  const int j = blockIdx.x * blockDim.x + threadIdx.x;  // the scratch's index; the slot's is k
  if (j < count) {
    const int k = s.first + j;
    const ContactPair pair = s.pairs[k];
    int ia, ib;
    order_pair(p, t, pair.a, pair.b, ia, ib);
    const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
    const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
    unsigned char key = kOtherPath;
    if (pair_capacity<Law>(a, b) > 0 && a.faces + b.faces <= kMaxPhasedPlanes) {
      const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
      const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
      // As polyhedra_volume_geometry: GJK first, then the overlap's own culling.
      PairGeometryData<Real> g;
      int kept = -1;
      if (!s.gjk_filter || gjk_intersect(a.shape, pose_a, b.shape, pose_b).intersecting) {
        OverlapResult<Real> result;
        unsigned long long mask = 0;
        kept = overlap_cull_mask(a.shape, pose_a, b.shape, pose_b, OverlapOptions(), mask, result);
        if (kept >= 0)
          masks[j] = mask;
        else
          g = volume_geometry_from(result);  // separate, touching or degenerate: no contact
      }
      if (kept < 0) {
        finish_slot<Law, Real, false>(p, t, pair, ia, ib, k, g, s.spring_dt, s.histories, s.forces,
                                      s.slot_state, s.flag, s.energy_sums, s.owned);
        key = 0;
      } else {
        key = static_cast<unsigned char>(kept + 1);
      }
      atomicAdd(&block_histogram[key], 1);
    }
    keys[j] = key;
    order[j] = j;
  }
  __syncthreads();
  for (int b = threadIdx.x; b < kPhasedKeys; b += blockDim.x)
    if (block_histogram[b] > 0) atomicAdd(&histogram[b], block_histogram[b]);
}

// Phase 2 over the sorted slots order[begin .. begin + count): the polytope from the slot's mask
// in a workspace of Cap planes (by the vertex enumeration alone for 8), then the force. A pair
// the workspace cannot hold (the hull needs more room than its planes suggest; rare) or the
// enumeration declines is appended to `deferred` for pair_kernel.
// The enumeration's kernel (Cap 8) at least 3 blocks an SM (12 warps, 168 registers, as ptxas
// chooses for its other variants): left free, with the default law's atomic sums it took 224
// (8 warps) and ran slower on the 1e6 bed (benchmarks/history/README.md, session 13). The
// workspace kernels keep no such bound: under it they spill.
// buckets: the ranges on the device (a graph step, launched for every slot), else null and the
// range is begin, count.
template <class Law, class Real, int Cap, bool Atomic>
__global__ void __launch_bounds__(kBlock, Cap == kEnumerationPlanes ? 3 : 1)
    polytope_pair_kernel(ParticleView<Real> p, PairLawTables<Real> t, SlotArgs<Real> s,
                         const int* __restrict__ order, int begin, int count,
                         const PhasedBuckets* __restrict__ buckets,
                         const unsigned long long* __restrict__ masks, int* deferred,
                         int* deferred_count) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  if (buckets) {
    const PhasedRange range = buckets->workspace(Cap);
    begin = range.begin;
    count = min(count, range.count);
  }
  bool in_contact = false;
  if (e < count) {
    const int j = order[begin + e];  // the scratch's index; the slot's is k
    const int k = s.first + j;
    const ContactPair pair = s.pairs[k];
    int ia, ib;
    order_pair(p, t, pair.a, pair.b, ia, ib);
    const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
    const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
    const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
    const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
    OverlapResult<Real> overlap;
    if constexpr (Cap == kEnumerationPlanes) {
      // The fewest planes: the vertex enumeration alone, no workspace and no hull in the
      // thread; a pair it declines (a vertex of four planes, twins, ...) is deferred to
      // pair_kernel, whose overlap_polyhedra gives the host's result (it declines there too).
      // The planes in shared memory, as the overlap batch's enumerate_kernel keeps them.
      const overlap_detail::EnumerationBodies<Real> bodies{a.shape,         b.shape,
                                                           pose_a.position, pose_a.orientation,
                                                           pose_b.position, pose_b.orientation,
                                                           Real(0)};
      if (!overlap_enumerate_from_mask(bodies, masks[j], shared_enumeration_planes<Real, kBlock>(),
                                       kBlock, overlap))
        overlap.workspace_overrun = true;
    } else {
      OverlapWorkspace<Real, Cap> workspace;  // per-thread local memory
      overlap = overlap_from_mask(a.shape, pose_a, b.shape, pose_b, masks[j], workspace);
    }
    if (overlap.workspace_overrun) {
      deferred[atomicAdd(deferred_count, 1)] = j;
    } else {
      in_contact = finish_slot<Law, Real, Atomic>(
          p, t, pair, ia, ib, k, volume_geometry_from(overlap), s.spring_dt, s.histories, s.forces,
          s.slot_state, s.flag, s.energy_sums, s.owned);
    }
  }
  count_touching(in_contact, s.touching);
}

// What each slot needs besides the particles and the tables.
template <class Real>
SlotArgs<Real> slot_args(DeviceStepShared<Real>& shared, DevicePairList<Real>& list, Real spring_dt,
                         int first) {
  SlotArgs<Real> a;
  a.pairs = list.pairs();
  a.spring_dt = spring_dt;
  a.histories = list.histories();
  a.forces = list.forces();
  a.slot_state = list.slot_state();
  a.flag = shared.flags.data();
  a.touching = shared.flags.at(touching_pairs);
  a.gjk_filter = shared.gjk_filter;
  a.energy_sums = shared.energy_sums.size() > 0 ? shared.energy_sums.data() : nullptr;
  a.owned = shared.owned >= 0 ? shared.owned : INT_MAX;
  a.first = first;
  return a;
}

}  // namespace

template <class Real>
DevicePairStage<Real>::DevicePairStage(DeviceStepShared<Real>& shared, DevicePairList<Real>& list,
                                       const std::vector<BodyProperties<Real>>& host_bodies)
    : shared_(shared), list_(list) {
  if (shared.constant_region >= 0)
    fill_template_region(shared.device_bodies, shared.constant_region);
  // One pair launch per workspace capacity among the scene's template pairs.
  for (const BodyProperties<Real>& a : host_bodies) {
    for (const BodyProperties<Real>& b : host_bodies) {
      const int capacity = with_contact_law(*shared.scene.effects.contact, [&](auto law) {
        return pair_capacity<decltype(law)>(a, b);
      });
      if (std::find(capacities_.begin(), capacities_.end(), capacity) == capacities_.end())
        capacities_.push_back(capacity);
    }
  }
  std::sort(capacities_.begin(), capacities_.end());
  // The phased path when some template pair has at most 64 planes: its capacity is then 32 or
  // 64 (a pair with more goes to pair_kernel with its own capacity).
  for (const int capacity : capacities_)
    phased_ = phased_ || (capacity > 0 && capacity <= kMaxPhasedPlanes);
  if (phased_) {
    for (cudaStream_t& stream : streams_) TALUS_CUDA_CHECK(cudaStreamCreate(&stream));
    TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&fork_, cudaEventDisableTiming));
    for (cudaEvent_t& join : joins_)
      TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&join, cudaEventDisableTiming));
  }
}

template <class Real>
DevicePairStage<Real>::~DevicePairStage() {
  for (cudaStream_t stream : streams_) {
    if (stream) cudaStreamDestroy(stream);  // no throw from a destructor
  }
  if (fork_) cudaEventDestroy(fork_);
  for (cudaEvent_t join : joins_) {
    if (join) cudaEventDestroy(join);
  }
}

// pair_kernel for the pairs of capacity Capacity among `slots` (all slots when null), n of them
// (at most n, their number at count_at on the device, when that is not null).
template <class Real>
template <class Law, int Capacity>
void DevicePairStage<Real>::launch_pairs(const int* slots, int n, const int* count_at) {
  if (n <= 0) return;
  const SlotArgs<Real> args = slot_args(shared_, list_, spring_dt_, first_);
  const ParticleView<Real>& v = shared_.view;
  const cudaStream_t stream = shared_.stream;
  if (shared_.scene.deterministic) {
    pair_kernel<Law, Real, Capacity, false>
        <<<blocks_for(n), kBlock, 0, stream>>>(v, shared_.tables, args, slots, n, count_at);
  } else {
    pair_kernel<Law, Real, Capacity, true>
        <<<blocks_for(n), kBlock, 0, stream>>>(v, shared_.tables, args, slots, n, count_at);
  }
  TALUS_CUDA_LAUNCH_CHECK();
}

// A law without volume geometry has only capacity 0 (no workspace kernels are made for it).
template <class Real>
template <class Law>
void DevicePairStage<Real>::launch_pairs(int capacity, const int* slots, int n,
                                         const int* count_at) {
  if constexpr (!Law::kVolumeGeometry) {
    return launch_pairs<Law, 0>(slots, n, count_at);
  } else {
    switch (capacity) {
      case 0:
        return launch_pairs<Law, 0>(slots, n, count_at);
      case 32:
        return launch_pairs<Law, 32>(slots, n, count_at);
      case 64:
        return launch_pairs<Law, 64>(slots, n, count_at);
      case 128:
        return launch_pairs<Law, 128>(slots, n, count_at);
      default:
        return launch_pairs<Law, 256>(slots, n, count_at);
    }
  }
}

// Phase 2 with a workspace of Cap planes over its range of the sorted slots, on `stream`; in a
// graph step (`buckets` null) over every slot, the range read on the device.
template <class Real>
template <class Law, int Cap>
void DevicePairStage<Real>::launch_polytopes(const PhasedBuckets* buckets, int slots,
                                             cudaStream_t stream) {
  const PhasedRange range = buckets ? buckets->workspace(Cap) : PhasedRange{0, slots};
  if (range.count <= 0) return;
  const SlotArgs<Real> args = slot_args(shared_, list_, spring_dt_, first_);
  const PhasedBuckets* on_device = buckets ? nullptr : scratch_.device_buckets();
  const auto launch = [&](auto kernel) {
    kernel<<<blocks_for(range.count), kBlock, 0, stream>>>(
        shared_.view, shared_.tables, args, scratch_.sorted_order(), range.begin, range.count,
        on_device, scratch_.masks(), scratch_.deferred(), scratch_.deferred_counter());
    TALUS_CUDA_LAUNCH_CHECK();
  };
  if (shared_.scene.deterministic) {
    launch(polytope_pair_kernel<Law, Real, Cap, false>);
  } else {
    launch(polytope_pair_kernel<Law, Real, Cap, true>);
  }
}

// The phased path over every slot: cull, sort by kept planes, polytopes, deferred pairs.
// In a graph step nothing is read back: the ranges are cut on the device and each polytope
// kernel is launched for every slot (its threads past the range return at once), the deferred
// pairs' kernel for every slot too, their number read on the device.
template <class Real>
template <class Law>
void DevicePairStage<Real>::compute_phased(int n, bool wait) {
  const cudaStream_t stream = shared_.stream;
  const bool graph = shared_.graph_mode || !wait;  // nothing read back
  // Room for every slot at a step's first range, so that a later range of the step does not
  // reallocate what the first one's kernels still read.
  scratch_.prepare(first_ == 0 ? std::max(n, list_.candidates()) : n, stream);
  cull_pair_kernel<Law><<<blocks_for(n), kBlock, 0, stream>>>(
      shared_.view, shared_.tables, slot_args(shared_, list_, spring_dt_, first_), n,
      scratch_.masks(), scratch_.keys(), scratch_.order(), scratch_.histogram());
  TALUS_CUDA_LAUNCH_CHECK();
  // kOtherPath (255) sorts last.
  scratch_.sort(n, kOtherPath, shared_.temp, stream);
  PhasedBuckets buckets;
  if (graph) {
    scratch_.buckets_on_device(stream);
  } else {
    buckets = scratch_.buckets();
  }
  const PhasedBuckets* host_buckets = graph ? nullptr : &buckets;
  // Each workspace size runs on a stream of its own: a small bucket (a few thousand deep pairs
  // among millions) then runs beside the large one instead of as a tail with the GPU nearly
  // idle. The side streams start after the sort (an event on the step's stream) and the step's
  // stream waits for them all (an event each) before the deferred pairs; in a graph these are
  // its edges. The larger sizes are launched first so that their blocks are scheduled early.
  TALUS_CUDA_CHECK(cudaEventRecord(fork_, stream));
  for (const cudaStream_t side : streams_) TALUS_CUDA_CHECK(cudaStreamWaitEvent(side, fork_, 0));
  launch_polytopes<Law, 64>(host_buckets, n, streams_[3]);
  launch_polytopes<Law, 32>(host_buckets, n, streams_[2]);
  launch_polytopes<Law, 16>(host_buckets, n, streams_[1]);
  launch_polytopes<Law, 8>(host_buckets, n, streams_[0]);
  for (int s = 0; s < kPhasedSizes; ++s) {
    TALUS_CUDA_CHECK(cudaEventRecord(joins_[s], streams_[s]));
    TALUS_CUDA_CHECK(cudaStreamWaitEvent(stream, joins_[s], 0));
  }
  const int late = graph ? n : scratch_.deferred_count();
  const int* late_at = graph ? scratch_.deferred_counter() : nullptr;
  for (const int capacity : capacities_) {
    if (capacity > 0 && capacity <= kMaxPhasedPlanes)
      launch_pairs<Law>(capacity, scratch_.deferred(), late, late_at);
  }
}

// The launches under the scene's law Law; the phased path only for a law of volume geometry.
template <class Real>
template <class Law>
void DevicePairStage<Real>::launch_all(int candidates, bool wait) {
  if constexpr (Law::kVolumeGeometry) {
    if (phased_) compute_phased<Law>(candidates, wait);
  }
  for (const int capacity : capacities_) {
    if (!phased_ || capacity == 0 || capacity > kMaxPhasedPlanes)
      launch_pairs<Law>(capacity, nullptr, candidates, nullptr);
  }
}

template <class Real>
void DevicePairStage<Real>::compute(Real spring_dt, int first, int count, bool wait) {
  if (first == 0) {
    contact_count_ = 0;
    contact_count_ready_ = true;
  }
  if (first < 0 || count < 0 || first + count > list_.candidates())
    throw std::logic_error("DevicePairStage::compute: slots " + std::to_string(first) + " + " +
                           std::to_string(count) + " of " + std::to_string(list_.candidates()));
  if (count == 0) return;
  spring_dt_ = spring_dt;
  first_ = first;
  with_contact_law(*shared_.scene.effects.contact,
                   [&](auto law) { launch_all<decltype(law)>(count, wait); });
  contact_count_ready_ = false;  // flag[touching_pairs], read when asked or at check_flags
}

template <class Real>
void DevicePairStage<Real>::check_flags(const std::array<int, flags>& all) {
  const int bad = all[degenerate_pair];
  if (bad != INT_MAX) {
    const ContactPair pair = download(list_.pairs() + bad, 1)[0];
    throw std::runtime_error(degenerate_pair_message(shared_.scene, shared_.pose_report(pair.a),
                                                     shared_.pose_report(pair.b)));
  }
  // Also after a graph step, where compute() ran only when the graph was captured.
  contact_count_ = list_.candidates() > 0 ? all[touching_pairs] : 0;
  contact_count_ready_ = true;
}

template <class Real>
long long DevicePairStage<Real>::touching_count() const {
  if (!contact_count_ready_) {
    contact_count_ = shared_.flags.read(touching_pairs);
    contact_count_ready_ = true;
  }
  return contact_count_;
}

template <class Real>
std::size_t DevicePairStage<Real>::bytes() const {
  return scratch_.bytes();
}

}  // namespace talus
