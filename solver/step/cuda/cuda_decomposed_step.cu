// `mpirun -np N talus run --backend cuda` (docs/parallel.md): the decomposed run's command loop
// (parallel/decomposed_step_impl.hpp) over the CUDA step, one GPU per local rank.
#include <memory>

#include "solver/parallel/decomposed_step_impl.hpp"
#include "solver/step/cuda/cuda_step.hpp"

namespace talus {

namespace {

template <class Real>
std::function<std::unique_ptr<CudaStep<Real>>()> cuda_maker(
    const Scene& scene, const std::shared_ptr<const Communicator>& comm) {
  return
      [&scene, comm] { return std::make_unique<CudaStep<Real>>(scene, CudaStepOptions(), comm); };
}

}  // namespace

std::unique_ptr<AnyStep> make_decomposed_cuda_step(const Scene& scene,
                                                   std::shared_ptr<const Communicator> comm) {
  using decomposed_detail::DecomposedStep;
  if (scene.precision == Precision::float32)
    return std::make_unique<DecomposedStep<CudaStep<float>>>(
        scene, comm, cuda_maker<float>(scene, comm), "cuda");
  return std::make_unique<DecomposedStep<CudaStep<double>>>(
      scene, comm, cuda_maker<double>(scene, comm), "cuda");
}

void serve_decomposed_cuda_step(const Scene& scene, std::shared_ptr<const Communicator> comm) {
  if (scene.precision == Precision::float32)
    return decomposed_detail::serve<CudaStep<float>>(scene, comm, cuda_maker<float>(scene, comm));
  decomposed_detail::serve<CudaStep<double>>(scene, comm, cuda_maker<double>(scene, comm));
}

}  // namespace talus
