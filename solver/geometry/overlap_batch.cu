// GPU batch of overlap_polyhedra (see overlap_batch.hpp).
#include "solver/geometry/overlap_batch.hpp"

#include <stdexcept>

#include <cub/cub.cuh>

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
// The phased kernel keeps a pair's planes as the bits of a 64-bit mask.
constexpr int kMaxPhasedPlanes = 64;

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
  // The pairs to compute: order[0..count) when given, else 0..count.
  const int* order = nullptr;
  // Deferred pairs (a workspace too small): appended here, computed by a later launch.
  int* overflow = nullptr;
  int* overflow_count = nullptr;
};

template <class Real, bool Staged>
__device__ void stage_both(ConvexView<Real>& a, ConvexView<Real>& b, const KernelArgs& args) {
  extern __shared__ __align__(16) char shared[];
  if (Staged) {
    a = stage_shape(a, shared, args.layout_a);
    b = stage_shape(b, shared, args.layout_b);
    __syncthreads();
  }
}

__device__ void defer_pair(const KernelArgs& args, int i) {
  args.overflow[atomicAdd(args.overflow_count, 1)] = i;
}

// One thread per pair. Staged: the templates are first copied into shared memory, where every
// thread reads them without competing with the workspaces for the L1 cache. Small > 0: the pair
// is first computed with a workspace of Small planes; when more planes than Small survive the
// culling (the culling does not depend on the capacity) it is computed again with Capacity
// planes, in the same thread, or (Defer) by a second launch over the deferred pairs, so that
// this kernel holds one copy of the overlap.
template <class Real, int Capacity, int Small, bool Staged, bool Defer>
__global__ void overlap_kernel(ConvexView<Real> a, ConvexView<Real> b,
                               const Vec3<Real>* __restrict__ position_a,
                               const Quat<Real>* __restrict__ orientation_a,
                               const Vec3<Real>* __restrict__ position_b,
                               const Quat<Real>* __restrict__ orientation_b, KernelArgs args,
                               OverlapResult<Real>* __restrict__ out) {
  stage_both<Real, Staged>(a, b, args);
  int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= args.count) return;
  if (args.order) i = args.order[i];
  const Pose<Real> pose_a{position_a[i], orientation_a[i]};
  const Pose<Real> pose_b{position_b[i], orientation_b[i]};
  if constexpr (Small > 0) {
    OverlapWorkspace<Real, Small> small;  // per-thread local memory
    const OverlapResult<Real> result = overlap_polyhedra(a, pose_a, b, pose_b, small, args.options);
    if (!result.workspace_overrun) {
      out[i] = result;
      return;
    }
    if constexpr (Defer) {
      defer_pair(args, i);
      return;
    }
  }
  if constexpr (!Defer || Small == 0) {
    OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
    out[i] = overlap_polyhedra(a, pose_a, b, pose_b, workspace, args.options);
  }
}

// Phase 1 of the phased kernel: the culling alone (overlap_cull_mask), one thread per pair. A
// pair decided here (bounding spheres apart, a separating plane) has its result written and key
// 0; the others keep their mask of kept planes and key m + 1 (m kept planes). `histogram`
// counts the keys (one atomic per block and key).
template <class Real, bool Staged>
__global__ void cull_kernel(ConvexView<Real> a, ConvexView<Real> b,
                            const Vec3<Real>* __restrict__ position_a,
                            const Quat<Real>* __restrict__ orientation_a,
                            const Vec3<Real>* __restrict__ position_b,
                            const Quat<Real>* __restrict__ orientation_b, KernelArgs args,
                            unsigned long long* __restrict__ masks,
                            unsigned char* __restrict__ keys, int* __restrict__ order,
                            int* __restrict__ histogram, OverlapResult<Real>* __restrict__ out) {
  stage_both<Real, Staged>(a, b, args);
  __shared__ int block_histogram[kMaxPhasedPlanes + 2];
  const int bins = a.n_faces + b.n_faces + 2;
  for (int k = threadIdx.x; k < bins; k += blockDim.x) block_histogram[k] = 0;
  __syncthreads();
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < args.count) {
    const Pose<Real> pose_a{position_a[i], orientation_a[i]};
    const Pose<Real> pose_b{position_b[i], orientation_b[i]};
    OverlapResult<Real> result;
    unsigned long long mask = 0;
    const int kept = overlap_cull_mask(a, pose_a, b, pose_b, args.options, mask, result);
    if (kept < 0) out[i] = result;
    masks[i] = mask;
    keys[i] = static_cast<unsigned char>(kept + 1);
    order[i] = i;
    atomicAdd(&block_histogram[kept + 1], 1);
  }
  __syncthreads();
  for (int k = threadIdx.x; k < bins; k += blockDim.x)
    if (block_histogram[k] > 0) atomicAdd(&histogram[k], block_histogram[k]);
}

// Phase 2 of the phased kernel: steps 3-5 (overlap_from_mask) of the pairs order[begin..end)
// with a workspace of Capacity planes; a pair it cannot hold is deferred. With `keys`, pairs of
// key 0 (decided by the culling) are skipped.
template <class Real, int Capacity, bool Staged>
__global__ void polytope_kernel(ConvexView<Real> a, ConvexView<Real> b,
                                const Vec3<Real>* __restrict__ position_a,
                                const Quat<Real>* __restrict__ orientation_a,
                                const Vec3<Real>* __restrict__ position_b,
                                const Quat<Real>* __restrict__ orientation_b, KernelArgs args,
                                int begin, const unsigned long long* __restrict__ masks,
                                const unsigned char* __restrict__ keys,
                                OverlapResult<Real>* __restrict__ out) {
  stage_both<Real, Staged>(a, b, args);
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= args.count) return;
  const int i = args.order ? args.order[begin + j] : begin + j;
  if (keys && keys[i] == 0) return;
  const Pose<Real> pose_a{position_a[i], orientation_a[i]};
  const Pose<Real> pose_b{position_b[i], orientation_b[i]};
  if constexpr (Capacity == kEnumerationPlanes) {
    // The fewest planes: the vertex enumeration alone, with no workspace; what it declines goes
    // to the deferred launch, which runs the whole overlap (and declines there too).
    if (args.options.enumerate && args.overflow) {
      OverlapResult<Real> result;
      if (overlap_enumerate_from_mask(a, pose_a, b, pose_b, masks[i], result))
        out[i] = result;
      else
        defer_pair(args, i);
      return;
    }
  }
  OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
  const OverlapResult<Real> result =
      overlap_from_mask(a, pose_a, b, pose_b, masks[i], workspace, args.options);
  if (result.workspace_overrun && args.overflow) {
    defer_pair(args, i);
    return;
  }
  out[i] = result;
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

  // Scratch of the deferred and phased kernels, sized on first use.
  DeviceBuffer<unsigned long long> masks;
  DeviceBuffer<unsigned char> keys, keys_sorted;
  DeviceBuffer<int> order, order_sorted, overflow;
  DeviceBuffer<int> counters;  // [0]: deferred pairs; [1 + k]: pairs of key k (cull_kernel)
  DeviceBuffer<char> cub_temp;

  int planes() const { return a.view.n_faces + b.view.n_faces; }
  int count() const { return static_cast<int>(results.size()); }
  std::size_t shared_bytes(bool staged) const {
    return staged ? std::size_t(layout_a.bytes + layout_b.bytes) : 0;
  }
  KernelArgs args_for(int pairs, OverlapOptions options) const {
    KernelArgs args;
    args.count = pairs;
    args.options = options;
    args.layout_a = layout_a;
    args.layout_b = layout_b;
    return args;
  }

  // Launches `kernel` (any of the kernels above) over args.count threads.
  template <class... Params, class... Extra>
  void launch_over(void (*kernel)(ConvexView<Real>, ConvexView<Real>, const Vec3<Real>*,
                                  const Quat<Real>*, const Vec3<Real>*, const Quat<Real>*,
                                  KernelArgs, Params...),
                   bool staged, const KernelArgs& args, Extra... extra) {
    if (args.count <= 0) return;
    const int block = 128;
    const int grid = (args.count + block - 1) / block;
    kernel<<<grid, block, shared_bytes(staged)>>>(a.view, b.view, position_a.data(),
                                                  orientation_a.data(), position_b.data(),
                                                  orientation_b.data(), args, extra...);
    TALUS_CUDA_LAUNCH_CHECK();
  }

  template <int Capacity, int Small, bool Staged>
  void launch(OverlapOptions options) {
    launch_over(overlap_kernel<Real, Capacity, Small, Staged, false>, Staged,
                args_for(count(), options), results.data());
  }

  void ensure_scratch() {
    const std::size_t n = results.size();
    if (order.size() != n) {
      masks.resize(n);
      keys.resize(n);
      keys_sorted.resize(n);
      order.resize(n);
      order_sorted.resize(n);
      overflow.resize(n);
    }
    counters.resize(kMaxPhasedPlanes + 3);
    TALUS_CUDA_CHECK(cudaMemset(counters.data(), 0, counters.size() * sizeof(int)));
  }

  int deferred_count() const {
    int deferred = 0;
    TALUS_CUDA_CHECK(cudaMemcpy(&deferred, counters.data(), sizeof(int), cudaMemcpyDeviceToHost));
    return deferred;
  }

  // The pairs deferred by the launches before, computed with the full workspace.
  template <int Capacity>
  void launch_deferred(OverlapOptions options) {
    KernelArgs args = args_for(deferred_count(), options);
    args.order = overflow.data();
    launch_over(overlap_kernel<Real, Capacity, 0, true, false>, true, args, results.data());
  }

  // deferred_overflow: the small workspace, and the pairs it cannot hold in a second launch.
  template <int Capacity>
  void launch_split(OverlapOptions options) {
    ensure_scratch();
    KernelArgs args = args_for(count(), options);
    args.overflow = overflow.data();
    args.overflow_count = counters.data();
    launch_over(overlap_kernel<Real, Capacity, small_capacity_for(Capacity), true, true>, true,
                args, results.data());
    launch_deferred<Capacity>(options);
  }

  // Phase 2 of phased_sorted: one launch per workspace size Cap = 8, 16, ..., Capacity over the
  // sorted pairs whose kept planes fit it and not the size before.
  template <int Cap, int Capacity>
  void launch_buckets(OverlapOptions options, const std::vector<int>& histogram, int begin,
                      int below) {
    int end = begin;
    for (int m = below + 1; m <= Cap && m + 1 < int(histogram.size()); ++m) end += histogram[m + 1];
    KernelArgs args = args_for(end - begin, options);
    args.order = order_sorted.data();
    args.overflow = overflow.data();
    args.overflow_count = counters.data();
    launch_over(polytope_kernel<Real, Cap, true>, true, args, begin, masks.data(),
                static_cast<const unsigned char*>(nullptr), results.data());
    if constexpr (Cap < Capacity) launch_buckets<Cap * 2, Capacity>(options, histogram, end, Cap);
  }

  template <int Capacity>
  void launch_phased(OverlapOptions options, bool sorted) {
    ensure_scratch();
    const int n = count();
    launch_over(cull_kernel<Real, true>, true, args_for(n, options), masks.data(), keys.data(),
                order.data(), counters.data() + 1, results.data());
    if (!sorted) {
      KernelArgs args = args_for(n, options);
      args.overflow = overflow.data();
      args.overflow_count = counters.data();
      constexpr int small = small_capacity_for(Capacity);
      launch_over(polytope_kernel<Real, small, true>, true, args, 0, masks.data(),
                  static_cast<const unsigned char*>(keys.data()), results.data());
    } else {
      std::vector<int> histogram(planes() + 2);
      TALUS_CUDA_CHECK(cudaMemcpy(histogram.data(), counters.data() + 1,
                                  histogram.size() * sizeof(int), cudaMemcpyDeviceToHost));
      int end_bit = 1;
      while ((1 << end_bit) < planes() + 2) ++end_bit;
      std::size_t temp_bytes = 0;
      TALUS_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, temp_bytes, keys.data(),
                                                       keys_sorted.data(), order.data(),
                                                       order_sorted.data(), n, 0, end_bit));
      if (cub_temp.size() < temp_bytes) cub_temp.resize(temp_bytes);
      TALUS_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(cub_temp.data(), temp_bytes, keys.data(),
                                                       keys_sorted.data(), order.data(),
                                                       order_sorted.data(), n, 0, end_bit));
      // Key 0 (decided by the culling) sorts first and is skipped.
      launch_buckets<8, Capacity>(options, histogram, histogram[0], -1);
    }
    launch_deferred<Capacity>(options);
  }

  // The small workspace pays only when culling leaves few planes: with the face test. Without
  // it (planes, naive) many shallow pairs keep more planes than it holds, and the warp of each
  // such pair would wait for its second computation, so the full workspace is used at once.
  // The phased kernels need staged templates and at most 64 planes in all (a 64-bit mask).
  template <int Capacity>
  void launch_kernel(OverlapOptions options, OverlapBatchKernel kernel) {
    const bool faces = options.cull_planes && options.cull_faces;
    if constexpr (Capacity <= kMaxPhasedPlanes) {
      if (can_stage() && kernel == OverlapBatchKernel::phased_sorted)
        return launch_phased<Capacity>(options, true);
      if (can_stage() && faces && kernel == OverlapBatchKernel::phased)
        return launch_phased<Capacity>(options, false);
    }
    if (can_stage() && faces && kernel == OverlapBatchKernel::deferred_overflow)
      return launch_split<Capacity>(options);
    if (kernel == OverlapBatchKernel::global_templates || !can_stage())
      launch<Capacity, 0, false>(options);
    else if (kernel != OverlapBatchKernel::shared_templates && faces)
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
