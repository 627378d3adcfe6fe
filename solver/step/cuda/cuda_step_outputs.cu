// What the CUDA step reports of its particles (cuda_step.hpp), as host_step_outputs.cpp does for
// the host step: the trajectory rows from a host copy; the energy terms and the bed height
// computed on the device (cuda_particle_kernels.cuh: three numbers and one come back).
#include <array>
#include <stdexcept>
#include <vector>

#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/cuda/cuda_step_impl.cuh"
#include "solver/step/host/host_step.hpp"
#include "solver/step/particle_kernels.hpp"

namespace talus {

template <class Real>
std::vector<TrajectoryRow> CudaStep<Real>::trajectory_rows() const {
  return particle_rows(impl_->particles->host_copy(impl_->own_count()).view);
}

template <class Real>
std::array<double, 3> CudaStep<Real>::Impl::energy_parts() const {
  const int n = own_count();
  if (n == 0) return {0, 0, 0};
  const int blocks = (n + kEnergyBlock - 1) / kEnergyBlock;
  energy_sums_by_block.grow_to(3 * std::size_t(blocks));
  energy_total.grow_to(3);
  ParticleView<Real> own = shared.view;
  own.count = n;
  const bool gravity = scene.effects.gravity.has_value();
  const Vec3d g = gravity ? *scene.effects.gravity : Vec3d();
  energy_parts_kernel<<<blocks, kEnergyBlock, 0, shared.stream>>>(own, bodies.data(), g, gravity,
                                                                  energy_sums_by_block.data());
  TALUS_CUDA_LAUNCH_CHECK();
  energy_total_kernel<<<1, kEnergyBlock, 0, shared.stream>>>(energy_sums_by_block.data(), blocks,
                                                             energy_total.data());
  TALUS_CUDA_LAUNCH_CHECK();
  TALUS_CUDA_CHECK(cudaStreamSynchronize(shared.stream));
  const std::vector<double> total = download(energy_total.data(), 3);
  return {total[0], total[1], total[2]};
}

template <class Real>
double CudaStep<Real>::kinetic_energy() const {
  const std::array<double, 3> e = impl_->energy_parts();
  return e[0] + e[1];
}

template <class Real>
EnergyTerms CudaStep<Real>::energy() const {
  const Impl& m = *impl_;
  EnergyTerms terms;
  const std::array<double, 3> e = m.energy_parts();  // translational, rotational, gravitational
  terms.kinetic_translational = e[0];
  terms.kinetic_rotational = e[1];
  terms.gravitational = e[2];
  terms.elastic_normal = m.energy_sums[sum_normal];
  terms.elastic_tangential = m.energy_sums[sum_tangential];
  terms.ledger = m.ledger;
  return terms;
}

// As particle_bed_height (host_step_outputs.cpp), on the device: one number comes back instead of
// every particle's state (at five million particles the copy and the host's loop took about a
// second, once for the last step's probe and once for the run's summary).
template <class Real>
double CudaStep<Real>::bed_height(const Vec3d& gravity) const {
  const Impl& m = *impl_;
  const double g = norm(gravity);
  if (!(g > 0)) throw std::invalid_argument("bed_height needs a non-zero gravity");
  const int n = m.own_count();
  if (n == 0) return 0;  // as the host loop
  const Vec3d up = gravity * (-1 / g);
  const int blocks = (n + kEnergyBlock - 1) / kEnergyBlock;
  m.energy_sums_by_block.grow_to(std::size_t(blocks));
  m.energy_total.grow_to(1);
  ParticleView<Real> own = m.shared.view;
  own.count = n;
  top_by_block_kernel<<<blocks, kEnergyBlock, 0, m.shared.stream>>>(own, m.bodies.data(), up,
                                                                    m.energy_sums_by_block.data());
  TALUS_CUDA_LAUNCH_CHECK();
  highest_top_kernel<<<1, kEnergyBlock, 0, m.shared.stream>>>(m.energy_sums_by_block.data(), blocks,
                                                              m.energy_total.data());
  TALUS_CUDA_LAUNCH_CHECK();
  TALUS_CUDA_CHECK(cudaStreamSynchronize(m.shared.stream));
  return download(m.energy_total.data(), 1)[0];
}

template std::vector<TrajectoryRow> CudaStep<double>::trajectory_rows() const;
template std::vector<TrajectoryRow> CudaStep<float>::trajectory_rows() const;
template double CudaStep<double>::kinetic_energy() const;
template double CudaStep<float>::kinetic_energy() const;
template EnergyTerms CudaStep<double>::energy() const;
template EnergyTerms CudaStep<float>::energy() const;
template double CudaStep<double>::bed_height(const Vec3d&) const;
template double CudaStep<float>::bed_height(const Vec3d&) const;

}  // namespace talus
