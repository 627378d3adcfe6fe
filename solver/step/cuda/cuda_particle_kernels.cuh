// The CUDA step's per-particle kernels (the stages of particle_kernels.hpp, one thread per
// particle), the deterministic accumulation over each particle's slots and wall contacts, and the
// flagging of particles that left the domain box.
// Included only by cuda_step.cu.
#pragma once

#include "solver/step/cuda/cuda_step_common.cuh"
#include "solver/step/host/wall_stage.hpp"
#include "solver/step/particle_kernels.hpp"

namespace talus {

namespace {

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

// (Nothing when `abort` says a graph step's wall stage did not finish: cuda_step.cu.)
template <class Real>
__global__ void integrate_end_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies,
                                     Real dt, AbortCheck abort) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < p.count && !abort.aborted()) integrate_end(p, bodies, i, dt);
}

// ---- Accumulation: one thread per particle, its touching slots in pair order, then its walls ----

template <class Real>
__global__ void accumulate_kernel(ParticleView<Real> p, const ContactPair* __restrict__ pairs,
                                  const unsigned char* __restrict__ slot_state,
                                  const SlotForce<Real>* __restrict__ forces,
                                  const int* __restrict__ sorted_slot,
                                  const int* __restrict__ begin, const int* __restrict__ end,
                                  const WallContactRecord<Real>* __restrict__ wall_contacts,
                                  const int* __restrict__ wall_slot, int walls, AbortCheck abort) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= p.count || abort.aborted()) return;
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
        if (torque) t = t + (cross(c.point - x, c.force_on_a) + c.couple);
      } else {
        f = f - c.force_on_a;
        if (torque) t = t + (cross(c.point - x, -c.force_on_a) - c.couple);
      }
    }
  }
  for (int w = 0; w < walls; ++w) {
    const int slot = wall_slot[static_cast<long long>(w) * p.count + i];
    if (slot < 0) continue;
    const WallContactRecord<Real>& c = wall_contacts[slot];
    f = f + c.force;
    if (torque) t = t + (cross(c.point - x, c.force) + c.couple);
  }
  p.force.set(i, f);
  if (torque) p.torque.set(i, t);
}

// ---- Removal at the domain box ----

// Particles whose centroid has left the domain box `lo` .. `hi` (half-open, as Box::contains;
// a non-finite one stays, for the watchdog): keep[i] 0, their energy (particle_energy) in
// energy[i], counted in `outside`; index[i] = i for the selection of the kept.
template <class Real>
__global__ void outside_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies, Vec3d lo,
                               Vec3d hi, Vec3d g, bool gravity, unsigned char* keep, double* energy,
                               int* index, int* outside) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= p.count) return;
  index[i] = i;
  const Vec3d x(p.position.get(i));
  const bool inside =
      x.x >= lo.x && x.x < hi.x && x.y >= lo.y && x.y < hi.y && x.z >= lo.z && x.z < hi.z;
  const bool leaves = !inside && is_finite(x.x + x.y + x.z);
  keep[i] = leaves ? 0 : 1;
  energy[i] = 0;
  if (!leaves) return;
  atomicAdd(outside, 1);
  energy[i] = particle_energy(p, bodies[p.template_id[i]], gravity ? &g : nullptr, i);
}

// The own particles' energies summed on the device (CudaStep::energy, every 100 steps for the
// energy watch and at each energy probe): three numbers come back instead of every particle's
// state, which at millions of particles cost more than the steps between. Each block of
// kEnergyBlock threads sums its particles' parts in a fixed tree, then one block sums the blocks'
// sums, each thread a fixed stride of them, in the same tree: the same particles in the same
// order give the same bits (a resumed run's probes are the uninterrupted run's).
constexpr int kEnergyBlock = 256;

__device__ inline void sum_energy_parts(double (&e)[3], double (*s)[kEnergyBlock], double* out) {
  const int t = threadIdx.x;
  for (int k = 0; k < 3; ++k) s[k][t] = e[k];
  __syncthreads();
  for (int width = kEnergyBlock / 2; width > 0; width /= 2) {
    if (t < width)
      for (int k = 0; k < 3; ++k) s[k][t] += s[k][t + width];
    __syncthreads();
  }
  if (t == 0)
    for (int k = 0; k < 3; ++k) out[k] = s[k][0];
}

template <class Real>
__global__ void energy_parts_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies,
                                    Vec3d g, bool gravity, double* block_sums) {
  __shared__ double s[3][kEnergyBlock];
  const int i = blockIdx.x * kEnergyBlock + threadIdx.x;
  double e[3] = {0, 0, 0};  // as particle_energy (particle_kernels.hpp) computes them
  if (i < p.count) {
    const BodyProperties<Real>& body = bodies[p.template_id[i]];
    e[0] = 0.5 * double(body.mass) * norm2(Vec3d(p.velocity.get(i)));
    if (p.angular_velocity.present()) {
      const Vec3d w(p.angular_velocity.get(i));  // body frame, with the principal moments
      const Vec3d inertia(body.inertia);
      e[1] = 0.5 * (inertia.x * w.x * w.x + inertia.y * w.y * w.y + inertia.z * w.z * w.z);
    }
    if (gravity) e[2] = -(double(body.mass) * dot(g, Vec3d(p.position.get(i))));
  }
  sum_energy_parts(e, s, block_sums + 3 * blockIdx.x);
}

__global__ void energy_total_kernel(const double* block_sums, int blocks, double* total) {
  __shared__ double s[3][kEnergyBlock];
  double e[3] = {0, 0, 0};
  for (int b = threadIdx.x; b < blocks; b += kEnergyBlock)
    for (int k = 0; k < 3; ++k) e[k] += block_sums[3 * b + k];
  sum_energy_parts(e, s, total);
}

// The bed_height probe on the device (CudaStep::bed_height): each block of kEnergyBlock threads
// takes the highest of its particles' tops (particle_top, as the host loop), one block the
// highest of the blocks'; one number comes back. A maximum does not depend on the order it is
// taken in, so the result is the host loop's for the same tops.
__device__ inline void highest_in_block(double top, double* s, double* out) {
  const int t = threadIdx.x;
  s[t] = top;
  __syncthreads();
  for (int width = kEnergyBlock / 2; width > 0; width /= 2) {
    if (t < width && s[t + width] > s[t]) s[t] = s[t + width];
    __syncthreads();
  }
  if (t == 0) *out = s[0];
}

template <class Real>
__global__ void top_by_block_kernel(ParticleView<Real> p, const BodyProperties<Real>* bodies,
                                    Vec3d up, double* block_tops) {
  __shared__ double s[kEnergyBlock];
  const int i = blockIdx.x * kEnergyBlock + threadIdx.x;
  const double top = i < p.count ? particle_top(p, bodies[p.template_id[i]], i, up) : -HUGE_VAL;
  highest_in_block(top, s, block_tops + blockIdx.x);
}

__global__ void highest_top_kernel(const double* block_tops, int blocks, double* highest) {
  __shared__ double s[kEnergyBlock];
  double top = -HUGE_VAL;
  for (int b = threadIdx.x; b < blocks; b += kEnergyBlock)
    top = block_tops[b] > top ? block_tops[b] : top;
  highest_in_block(top, s, highest);
}

}  // namespace

}  // namespace talus
