// GPU batch of overlap_polyhedra (see overlap_batch.hpp).
#include "solver/geometry/overlap_batch.hpp"

#include <stdexcept>

#include "solver/core/device_buffer.hpp"
#include "solver/geometry/device_shape.cuh"
#include "solver/geometry/overlap_polyhedra.hpp"

namespace talus {

bool cuda_device_available(std::string* reason) {
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess || count == 0) {
    if (reason)
      *reason = status != cudaSuccess
                    ? std::string("no usable CUDA device: ") + cudaGetErrorString(status)
                    : std::string("no CUDA device present");
    cudaGetLastError();  // clear the sticky error of a failed query
    return false;
  }
  return true;
}

namespace {

template <class Real, int Capacity>
__global__ void overlap_kernel(ConvexView<Real> a, ConvexView<Real> b,
                               const Vec3<Real>* __restrict__ position_a,
                               const Quat<Real>* __restrict__ orientation_a,
                               const Vec3<Real>* __restrict__ position_b,
                               const Quat<Real>* __restrict__ orientation_b, int count,
                               OverlapOptions options, OverlapResult<Real>* __restrict__ out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
  const Pose<Real> pose_a{position_a[i], orientation_a[i]};
  const Pose<Real> pose_b{position_b[i], orientation_b[i]};
  out[i] = overlap_polyhedra(a, pose_a, b, pose_b, workspace, options);
}

}  // namespace

template <class Real>
struct OverlapBatchGpu<Real>::Impl {
  DeviceShape<Real> a, b;
  DeviceBuffer<Vec3<Real>> position_a, position_b;
  DeviceBuffer<Quat<Real>> orientation_a, orientation_b;
  DeviceBuffer<OverlapResult<Real>> results;
  int capacity;

  Impl(const ConvexView<Real>& host_a, const ConvexView<Real>& host_b)
      : a(host_a), b(host_b), capacity(overlap_capacity_for(host_a.n_faces + host_b.n_faces)) {
    if (host_a.n_faces + host_b.n_faces > 256)
      throw std::invalid_argument("overlap batch: the two templates have " +
                                  std::to_string(host_a.n_faces + host_b.n_faces) +
                                  " faces together; at most 256 are supported");
  }

  template <int Capacity>
  void launch(OverlapOptions options) {
    const int count = static_cast<int>(results.size());
    const int block = 128;
    const int grid = (count + block - 1) / block;
    overlap_kernel<Real, Capacity>
        <<<grid, block>>>(a.view, b.view, position_a.data(), orientation_a.data(),
                          position_b.data(), orientation_b.data(), count, options, results.data());
    TALUS_CUDA_LAUNCH_CHECK();
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
double OverlapBatchGpu<Real>::run(OverlapOptions options) {
  if (impl_->results.size() == 0) return 0.0;
  cudaEvent_t start, stop;
  TALUS_CUDA_CHECK(cudaEventCreate(&start));
  TALUS_CUDA_CHECK(cudaEventCreate(&stop));
  TALUS_CUDA_CHECK(cudaEventRecord(start));
  switch (impl_->capacity) {
    case 32:
      impl_->template launch<32>(options);
      break;
    case 64:
      impl_->template launch<64>(options);
      break;
    case 128:
      impl_->template launch<128>(options);
      break;
    default:
      impl_->template launch<256>(options);
      break;
  }
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
