// GPU batch of overlap_polyhedra (see overlap_batch.hpp): the class. Its kernels and launches are
// in overlap_batch_kernels.cuh, compiled in generated files, one per precision and capacity.
#include "benchmarks/overlap_batch/overlap_batch.hpp"

#include "benchmarks/overlap_batch/overlap_batch_kernels.cuh"

namespace talus {

template <class Real>
struct OverlapBatchGpu<Real>::Impl : overlap_batch_detail::OverlapBatchImpl<Real> {
  using overlap_batch_detail::OverlapBatchImpl<Real>::OverlapBatchImpl;

  void dispatch(OverlapOptions options, bool whole) {
    using overlap_batch_detail::launch_overlap_batch;
    switch (this->capacity) {
      case 32:
        return launch_overlap_batch<Real, 32>(*this, options, whole);
      case 64:
        return launch_overlap_batch<Real, 64>(*this, options, whole);
      case 128:
        return launch_overlap_batch<Real, 128>(*this, options, whole);
      default:
        return launch_overlap_batch<Real, 256>(*this, options, whole);
    }
  }
};

template <class Real>
OverlapBatchGpu<Real>::OverlapBatchGpu(const ConvexView<Real>& a, const ConvexView<Real>& b)
    : impl_(new Impl(a, b)) {}

template <class Real>
OverlapBatchGpu<Real>::~OverlapBatchGpu() = default;

template <class Real>
void OverlapBatchGpu<Real>::set_poses(const std::vector<Pose<Real>>& poses_a,
                                      const std::vector<Pose<Real>>& poses_b) {
  if (poses_a.size() != poses_b.size())
    throw std::invalid_argument("overlap batch: pose lists of different lengths");
  std::vector<Vec3<Real>> pa, pb;
  std::vector<Quat<Real>> qa, qb;
  for (std::size_t i = 0; i < poses_a.size(); ++i) {
    pa.push_back(poses_a[i].position);
    qa.push_back(poses_a[i].orientation);
    pb.push_back(poses_b[i].position);
    qb.push_back(poses_b[i].orientation);
  }
  impl_->position_a.upload(pa);
  impl_->orientation_a.upload(qa);
  impl_->position_b.upload(pb);
  impl_->orientation_b.upload(qb);
  impl_->results.resize(poses_a.size());
}

template <class Real>
double OverlapBatchGpu<Real>::run(OverlapOptions options, OverlapBatchPath path) {
  if (impl_->results.size() == 0) return 0.0;
  cudaEvent_t start, stop;
  TALUS_CUDA_CHECK(cudaEventCreate(&start));
  TALUS_CUDA_CHECK(cudaEventCreate(&stop));
  TALUS_CUDA_CHECK(cudaEventRecord(start));
  impl_->dispatch(options, path == OverlapBatchPath::whole);
  TALUS_CUDA_CHECK(cudaEventRecord(stop));
  TALUS_CUDA_CHECK(cudaEventSynchronize(stop));
  float ms = 0;
  TALUS_CUDA_CHECK(cudaEventElapsedTime(&ms, start, stop));
  TALUS_CUDA_CHECK(cudaEventDestroy(start));
  TALUS_CUDA_CHECK(cudaEventDestroy(stop));
  return ms;
}

template <class Real>
std::vector<OverlapResult<Real>> OverlapBatchGpu<Real>::results() const {
  std::vector<OverlapResult<Real>> host;
  impl_->results.download(host);
  return host;
}

template <class Real>
int OverlapBatchGpu<Real>::workspace_capacity() const {
  return impl_->capacity;
}

template <class Real>
std::size_t OverlapBatchGpu<Real>::workspace_bytes() const {
  switch (impl_->capacity) {
    case 32:
      return sizeof(OverlapWorkspace<Real, 32>);
    case 64:
      return sizeof(OverlapWorkspace<Real, 64>);
    case 128:
      return sizeof(OverlapWorkspace<Real, 128>);
    default:
      return sizeof(OverlapWorkspace<Real, 256>);
  }
}

template <class Real>
std::size_t OverlapBatchGpu<Real>::pair_count() const {
  return impl_->results.size();
}

template class OverlapBatchGpu<float>;
template class OverlapBatchGpu<double>;

}  // namespace talus
