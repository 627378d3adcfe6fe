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

// Where a template's arrays sit in the block's shared memory (byte offsets; -1: not staged). Only
// what the overlap reads is staged: vertices, face planes and face loops.
struct SharedShapeLayout {
  int vertices = -1, face_normals = -1, face_offsets = -1, loop_offsets = -1, loop_vertices = -1;
  int loop_entries = 0;
  int bytes = 0;
};

template <class Real>
SharedShapeLayout shared_layout_for(const ConvexView<Real>& shape, int begin) {
  SharedShapeLayout layout;
  int at = begin;
  auto take = [&at](int bytes) {
    const int offset = at;
    at += (bytes + 15) / 16 * 16;
    return offset;
  };
  layout.vertices = take(shape.n_vertices * int(sizeof(Vec3<Real>)));
  layout.face_normals = take(shape.n_faces * int(sizeof(Vec3<Real>)));
  layout.face_offsets = take(shape.n_faces * int(sizeof(Real)));
  if (shape.face_loop_offsets) {
    layout.loop_offsets = take((shape.n_faces + 1) * int(sizeof(int)));
    layout.loop_entries = shape.face_loop_offsets[shape.n_faces];
    layout.loop_vertices = take(layout.loop_entries * int(sizeof(int)));
  }
  layout.bytes = at - begin;
  return layout;
}

template <class T>
__device__ void copy_to_shared(T* to, const T* from, int count) {
  for (int k = threadIdx.x; k < count; k += blockDim.x) to[k] = from[k];
}

// Copies the overlap's arrays of `shape` (device global memory) into shared memory and returns
// the view of the copies. Every thread of the block must call it; __syncthreads follows.
template <class Real>
__device__ ConvexView<Real> stage_shape(const ConvexView<Real>& shape, char* shared,
                                        const SharedShapeLayout& layout) {
  ConvexView<Real> view = shape;
  auto* vertices = reinterpret_cast<Vec3<Real>*>(shared + layout.vertices);
  auto* normals = reinterpret_cast<Vec3<Real>*>(shared + layout.face_normals);
  auto* offsets = reinterpret_cast<Real*>(shared + layout.face_offsets);
  copy_to_shared(vertices, shape.vertices, shape.n_vertices);
  copy_to_shared(normals, shape.face_normals, shape.n_faces);
  copy_to_shared(offsets, shape.face_offsets, shape.n_faces);
  view.vertices = vertices;
  view.face_normals = normals;
  view.face_offsets = offsets;
  if (layout.loop_offsets >= 0) {
    auto* loop_offsets = reinterpret_cast<int*>(shared + layout.loop_offsets);
    auto* loop_vertices = reinterpret_cast<int*>(shared + layout.loop_vertices);
    copy_to_shared(loop_offsets, shape.face_loop_offsets, shape.n_faces + 1);
    copy_to_shared(loop_vertices, shape.face_loop_vertices, layout.loop_entries);
    view.face_loop_offsets = loop_offsets;
    view.face_loop_vertices = loop_vertices;
  }
  return view;
}

struct KernelArgs {
  int count;
  OverlapOptions options;
  SharedShapeLayout layout_a, layout_b;  // used when the templates are staged
};

// One thread per pair. Staged: the templates are first copied into shared memory, where every
// thread reads them without competing with the workspaces for the L1 cache. Small > 0: the pair
// is first computed with a workspace of Small planes, and again with Capacity planes only when
// more planes than Small survive the culling (the culling does not depend on the capacity).
template <class Real, int Capacity, int Small, bool Staged>
__global__ void overlap_kernel(ConvexView<Real> a, ConvexView<Real> b,
                               const Vec3<Real>* __restrict__ position_a,
                               const Quat<Real>* __restrict__ orientation_a,
                               const Vec3<Real>* __restrict__ position_b,
                               const Quat<Real>* __restrict__ orientation_b, KernelArgs args,
                               OverlapResult<Real>* __restrict__ out) {
  extern __shared__ __align__(16) char shared[];
  if (Staged) {
    a = stage_shape(a, shared, args.layout_a);
    b = stage_shape(b, shared, args.layout_b);
    __syncthreads();
  }
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= args.count) return;
  const Pose<Real> pose_a{position_a[i], orientation_a[i]};
  const Pose<Real> pose_b{position_b[i], orientation_b[i]};
  if constexpr (Small > 0) {
    OverlapWorkspace<Real, Small> small;  // per-thread local memory
    const OverlapResult<Real> result = overlap_polyhedra(a, pose_a, b, pose_b, small, args.options);
    if (!result.workspace_overrun) {
      out[i] = result;
      return;
    }
  }
  OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
  out[i] = overlap_polyhedra(a, pose_a, b, pose_b, workspace, args.options);
}

// The smaller workspace of the small_workspace kernel: 3/8 of the full one (12 planes for two
// dodecahedra). Culling leaves few planes on shallow contacts: of 4096 shallow pairs of the
// benchmark, no dodecahedron pair kept more than 10 planes and no cylinder80 pair more than 16.
// A pair with more computes again with the full workspace; since its warp then waits for it,
// the small capacity is chosen so that this stays rare.
constexpr int small_capacity_for(int capacity) {
  return 3 * capacity / 8;
}

// Shared memory a block may take for the staged templates without an opt-in.
constexpr int kSharedTemplateLimit = 48 * 1024;

}  // namespace

template <class Real>
struct OverlapBatchGpu<Real>::Impl {
  DeviceShape<Real> a, b;
  DeviceBuffer<Vec3<Real>> position_a, position_b;
  DeviceBuffer<Quat<Real>> orientation_a, orientation_b;
  DeviceBuffer<OverlapResult<Real>> results;
  int capacity;
  SharedShapeLayout layout_a, layout_b;

  Impl(const ConvexView<Real>& host_a, const ConvexView<Real>& host_b)
      : a(host_a), b(host_b), capacity(overlap_capacity_for(host_a.n_faces + host_b.n_faces)) {
    if (host_a.n_faces + host_b.n_faces > 256)
      throw std::invalid_argument("overlap batch: the two templates have " +
                                  std::to_string(host_a.n_faces + host_b.n_faces) +
                                  " faces together; at most 256 are supported");
    layout_a = shared_layout_for(host_a, 0);
    layout_b = shared_layout_for(host_b, layout_a.bytes);
  }

  bool can_stage() const { return layout_a.bytes + layout_b.bytes <= kSharedTemplateLimit; }

  template <int Capacity, int Small, bool Staged>
  void launch(OverlapOptions options) {
    const int count = static_cast<int>(results.size());
    const int block = 128;
    const int grid = (count + block - 1) / block;
    const KernelArgs args{count, options, layout_a, layout_b};
    const std::size_t shared = Staged ? std::size_t(layout_a.bytes + layout_b.bytes) : 0;
    overlap_kernel<Real, Capacity, Small, Staged>
        <<<grid, block, shared>>>(a.view, b.view, position_a.data(), orientation_a.data(),
                                  position_b.data(), orientation_b.data(), args, results.data());
    TALUS_CUDA_LAUNCH_CHECK();
  }

  // The small workspace pays only when culling leaves few planes: with the face test. Without
  // it (planes, naive) many shallow pairs keep more planes than it holds, and the warp of each
  // such pair would wait for its second computation, so the full workspace is used at once.
  template <int Capacity>
  void launch_kernel(OverlapOptions options, OverlapBatchKernel kernel) {
    if (kernel == OverlapBatchKernel::global_templates || !can_stage())
      launch<Capacity, 0, false>(options);
    else if (kernel == OverlapBatchKernel::small_workspace && options.cull_planes &&
             options.cull_faces)
      launch<Capacity, small_capacity_for(Capacity), true>(options);
    else
      launch<Capacity, 0, true>(options);
  }

  void dispatch(OverlapOptions options, OverlapBatchKernel kernel) {
    switch (capacity) {
      case 32:
        launch_kernel<32>(options, kernel);
        break;
      case 64:
        launch_kernel<64>(options, kernel);
        break;
      case 128:
        launch_kernel<128>(options, kernel);
        break;
      default:
        launch_kernel<256>(options, kernel);
        break;
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
double OverlapBatchGpu<Real>::run(OverlapOptions options, OverlapBatchKernel kernel) {
  if (impl_->results.size() == 0) return 0.0;
  cudaEvent_t start, stop;
  TALUS_CUDA_CHECK(cudaEventCreate(&start));
  TALUS_CUDA_CHECK(cudaEventCreate(&stop));
  TALUS_CUDA_CHECK(cudaEventRecord(start));
  impl_->dispatch(options, kernel);
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
int OverlapBatchGpu<Real>::small_workspace_capacity() const {
  return small_capacity_for(impl_->capacity);
}

template <class Real>
std::size_t OverlapBatchGpu<Real>::small_workspace_bytes() const {
  switch (impl_->capacity) {
    case 32:
      return sizeof(OverlapWorkspace<Real, small_capacity_for(32)>);
    case 64:
      return sizeof(OverlapWorkspace<Real, small_capacity_for(64)>);
    case 128:
      return sizeof(OverlapWorkspace<Real, small_capacity_for(128)>);
    default:
      return sizeof(OverlapWorkspace<Real, small_capacity_for(256)>);
  }
}

template <class Real>
std::size_t OverlapBatchGpu<Real>::pair_count() const {
  return impl_->results.size();
}

template class OverlapBatchGpu<float>;
template class OverlapBatchGpu<double>;

}  // namespace talus
