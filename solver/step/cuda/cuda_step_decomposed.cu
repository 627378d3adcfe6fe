// The CUDA step's decomposed step and its exchange's numbers (cuda_step.hpp; docs/parallel.md,
// "On the GPU"): a rank's step with its ghosts' update between integrate_begin and the rest,
// the update overlapping the inner slots. The rest of the step is cuda_step.cu's.
#include <array>
#include <exception>

#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/cuda/cuda_step_impl.cuh"

namespace talus {

template <class Real>
void CudaStep<Real>::Impl::decomposed_step() {
  const Communicator& comm = decomposition->comm();
  const auto agreed = [&](auto&& body) {
    std::exception_ptr failure;
    try {
      body();
    } catch (...) {
      failure = std::current_exception();
    }
    agree_on_failure(comm, failure);
  };
  if (walls) walls->open_outlets(time);
  if (!feeding.empty()) feed();  // collectives: the feeds' gathering
  time += scene.time_step;
  ++steps;
  agreed([&] {
    shared.abort = AbortCheck{};
    shared.flags.reset(shared.stream);
    enqueue_integrate_begin();
    report_and_wait();
    check_rotation(shared.flags.read(failed_rotation));
  });
  // The ghosts' states travel while the device computes what needs no ghost: the body forces
  // and the pairs of two own particles (the inner region's work, method paper §2.6); the pairs
  // with a ghost, the walls and the rest follow their arrival. A rebuild exchanges whole
  // particles first. TALUS_HALO_OVERLAP=0: the exchange, then the stages (to measure the gain).
  const bool pending = decomposition->begin_exchange(false);
  std::exception_ptr inner_failure;
  if (pending && overlap_halo()) {
    try {
      run_force_stages_with_energy(dt, ForcePart::inner);
    } catch (...) {
      inner_failure = std::current_exception();  // after the messages: the others wait for them
    }
    decomposition->finish_exchange();
  } else if (pending) {
    decomposition->finish_exchange();
  }
  const ForcePart rest = pending && overlap_halo() ? ForcePart::outer : ForcePart::whole;
  agreed([&] {
    if (inner_failure) std::rethrow_exception(inner_failure);
    run_force_stages_with_energy(dt, rest);
    finish_enqueue();
    report_and_wait();
    const std::array<int, flags> all = report_flags();
    check_flags(all);
    take_energy(false);
    remove_outside(all[outside_particles]);
  });
}

template <class Real>
double CudaStep<Real>::exchange_seconds() const {
  return impl_->decomposition ? impl_->decomposition->exchange_seconds() : 0.0;
}
template <class Real>
double CudaStep<Real>::exchange_vote_seconds() const {
  return impl_->decomposition ? impl_->decomposition->vote_seconds() : 0.0;
}

template <class Real>
double CudaStep<Real>::exchange_rebuild_seconds() const {
  return impl_->decomposition ? impl_->decomposition->rebuild_seconds() : 0.0;
}

template <class Real>
double CudaStep<Real>::exchange_bytes() const {
  return impl_->decomposition ? impl_->decomposition->bytes_sent() : 0.0;
}
template <class Real>
long long CudaStep<Real>::rebalances() const {
  return impl_->decomposition ? impl_->decomposition->rebalances() : 0;
}
template void CudaStep<double>::Impl::decomposed_step();
template void CudaStep<float>::Impl::decomposed_step();
template double CudaStep<double>::exchange_seconds() const;
template double CudaStep<float>::exchange_seconds() const;
template double CudaStep<double>::exchange_vote_seconds() const;
template double CudaStep<float>::exchange_vote_seconds() const;
template double CudaStep<double>::exchange_rebuild_seconds() const;
template double CudaStep<float>::exchange_rebuild_seconds() const;
template double CudaStep<double>::exchange_bytes() const;
template double CudaStep<float>::exchange_bytes() const;
template long long CudaStep<double>::rebalances() const;
template long long CudaStep<float>::rebalances() const;

}  // namespace talus
