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
enum Flag { failed_rotation = 0, degenerate_pair = 1, degenerate_wall = 2, selected = 3, flags };

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

// One thread per candidate pair; this launch computes only the pairs of workspace capacity
// `Capacity` (another launch per capacity present in the scene computes the rest), so a
// thread's local memory is the workspace of its own template pair.
template <class Real, int Capacity>
__global__ void pair_kernel(ParticleView<Real> p, PairLawTables<Real> t,
                            const ContactPair* __restrict__ pairs, int count, Real spring_dt,
                            HistoryIn old, const ContactHistoryData<Real>* __restrict__ histories,
                            PairContactRecord<Real>* __restrict__ records, int* flag) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  int ia, ib;
  order_pair(p, t, pairs[k].a, pairs[k].b, ia, ib);
  const BodyProperties<Real>& a = t.bodies[p.template_id[ia]];
  const BodyProperties<Real>& b = t.bodies[p.template_id[ib]];
  if (pair_capacity(a, b, t.volume_model) != Capacity) return;
  PairGeometryData<Real> g;
  if constexpr (Capacity == 0) {
    g = simple_pair_geometry(p, t, ia, ib);
  } else {
    const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
    const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
    OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
    g = polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace);
  }
  const PairContactRecord<Real> r =
      pair_contact_force(p, t, ia, ib, g, spring_dt, old.keys, histories, old.count);
  records[k] = r;
  if (r.degenerate) atomicMin(flag + degenerate_pair, k);
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

// Two CSR entries per contact k: (a, k) and (b, k).
template <class Real>
__global__ void emit_entries(const PairContactRecord<Real>* __restrict__ contacts, int count,
                             int* __restrict__ particle, int* __restrict__ contact) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  particle[2 * k] = contacts[k].a;
  particle[2 * k + 1] = contacts[k].b;
  contact[2 * k] = contact[2 * k + 1] = k;
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

// One thread per (particle, wall), wall-major: record w * count + i.
template <class Real>
__global__ void wall_kernel(ParticleView<Real> p, PairLawTables<Real> t, WallArgs<Real> walls,
                            Real spring_dt, HistoryIn old,
                            const ContactHistoryData<Real>* __restrict__ histories,
                            WallContactRecord<Real>* __restrict__ records, int* flag) {
  const long long k = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k >= static_cast<long long>(p.count) * walls.walls) return;
  const int w = static_cast<int>(k / p.count), i = static_cast<int>(k % p.count);
  const WallContactRecord<Real> r =
      wall_contact(p, t, i, w, walls.materials[w], walls.facets[w], walls.motions[w], spring_dt,
                   old.keys, histories, old.count);
  records[k] = r;
  if (r.degenerate) atomicMin(flag + degenerate_wall, static_cast<int>(k));
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

// ---- Accumulation: one thread per particle, its contacts in pair order, then its walls ----

template <class Real>
__global__ void accumulate_kernel(ParticleView<Real> p,
                                  const PairContactRecord<Real>* __restrict__ contacts,
                                  const int* __restrict__ sorted_contact,
                                  const int* __restrict__ begin, const int* __restrict__ end,
                                  const WallContactRecord<Real>* __restrict__ wall_records,
                                  int walls) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= p.count) return;
  // The same additions, in the same order, as add_pair_force and add_wall_force on the host.
  Vec3<Real> f = p.force.get(i), t;
  const bool torque = p.torque.present();
  if (torque) t = p.torque.get(i);
  const Vec3<Real> x = p.position.get(i);
  if (contacts) {
    for (int s = begin[i]; s < end[i]; ++s) {
      const PairContactRecord<Real>& c = contacts[sorted_contact[s]];
      if (c.a == i) {
        f = f + c.force_on_a;
        if (torque) t = t + cross(c.point - x, c.force_on_a);
      } else {
        f = f - c.force_on_a;
        if (torque) t = t + cross(c.point - x, -c.force_on_a);
      }
    }
  }
  for (int w = 0; w < walls; ++w) {
    const WallContactRecord<Real>& c = wall_records[static_cast<long long>(w) * p.count + i];
    if (!c.in_contact) continue;
    f = f + c.force;
    if (torque) t = t + cross(c.point - x, c.force);
  }
  p.force.set(i, f);
  if (torque) p.torque.set(i, t);
}

struct InContact {
  template <class Record>
  __host__ __device__ bool operator()(const Record& r) const {
    return r.in_contact;
  }
};

struct KeyLess {
  __host__ __device__ bool operator()(const PairKey& p, const PairKey& q) const {
    return key_less(p, q);
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
