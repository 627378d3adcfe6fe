// The overlap batch's kernels and their launches (overlap_batch.hpp), shared by the files that
// compile them: overlap_batch.cu (the class, no kernel of its own) and one generated file per
// precision and workspace capacity (benchmarks/overlap_batch/CMakeLists.txt), each instantiating
// launch_overlap_batch for its pair, so that a parallel build compiles them side by side (one file
// that held every kernel took minutes to compile alone: benchmarks/history/README.md). Included
// only from .cu files.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "benchmarks/overlap_batch/overlap_batch.hpp"
#include "solver/core/device_buffer.hpp"
#include "solver/geometry/device_shape.cuh"
#include "solver/geometry/overlap_polyhedra.hpp"
#include "solver/geometry/phased_overlap.cuh"

namespace talus {

namespace overlap_batch_detail {

// Where a template's arrays sit in the block's shared memory (byte offsets; -1: not staged). Only
// what the overlap reads is staged: vertices, face planes, face loops, vertex records and the
// float vertices.
struct SharedShapeLayout {
  int vertices = -1, face_normals = -1, face_offsets = -1, loop_offsets = -1, loop_vertices = -1,
      vertex_records = -1, filter_vertices = -1;
  int loop_entries = 0;
  int bytes = 0;
};

template <class Real>
SharedShapeLayout shared_layout_for(const ConvexView<Real>& shape, int begin) {
  SharedShapeLayout layout;
  int at = begin;
  auto take = [&at](int bytes) {  // 32-byte aligned, as VertexRecord
    const int offset = at;
    at += (bytes + 31) / 32 * 32;
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
  if (shape.vertex_records)
    layout.vertex_records = take(shape.n_vertices * int(sizeof(VertexRecord<Real>)));
  if (shape.filter_vertices)
    layout.filter_vertices = take(shape.n_vertices * int(sizeof(FilterVertex)));
  layout.bytes = at - begin;
  return layout;
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

// Shared memory a block may take for the staged templates without an opt-in.
constexpr int kSharedTemplateLimit = 48 * 1024;

// Threads per block of every batch kernel.
constexpr int kBatchBlock = 128;
// Blocks per SM that the culling and the enumeration kernels are compiled for (at most 96 and
// 128 registers a thread; 96 for the enumeration in float, at 5 blocks). Without the caps both
// kernels took so many registers that few warps ran per scheduler, and both were latency-bound
// (Nsight Compute). The counts are those that ran the whole batch fastest, or within the noise of
// the fastest, each time the kernels changed (more blocks made the enumeration spill); asking for
// the largest L1 (the least shared memory, cudaSharedmemCarveoutMaxL1) made the batch slower. The
// registers, the warps and the times of every count tried, by session:
// benchmarks/history/README.md.
constexpr int kCullBlocks = 5;
template <class Real>
constexpr int kEnumerateBlocks = sizeof(Real) == 4 ? 5 : 4;

}  // namespace overlap_batch_detail

namespace {

using namespace overlap_batch_detail;

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
  if (layout.vertex_records >= 0) {
    auto* records = reinterpret_cast<VertexRecord<Real>*>(shared + layout.vertex_records);
    copy_to_shared(records, shape.vertex_records, shape.n_vertices);
    view.vertex_records = records;
  }
  if (layout.filter_vertices >= 0) {
    auto* filter = reinterpret_cast<FilterVertex*>(shared + layout.filter_vertices);
    copy_to_shared(filter, shape.filter_vertices, shape.n_vertices);
    view.filter_vertices = filter;
  }
  return view;
}

template <class Real, bool Staged>
__device__ void stage_both(ConvexView<Real>& a, ConvexView<Real>& b, const KernelArgs& args) {
  extern __shared__ __align__(32) char shared[];
  if (Staged) {
    a = stage_shape(a, shared, args.layout_a);
    b = stage_shape(b, shared, args.layout_b);
    __syncthreads();
  }
}

// stage_both, then both views kept once per block in shared memory: a view that a thread passes
// by reference to a function the compiler does not inline (the overlap's steps are large) would
// otherwise be copied into that thread's local memory (two views: 208 bytes a thread in double,
// which with the rest of a thread's frame overflowed the L1 cache into L2 and DRAM; what keeping
// them here gained: benchmarks/history/README.md). Every thread of the block must call it.
template <class Real, bool Staged>
__device__ const ConvexView<Real>* stage_views(ConvexView<Real>& a, ConvexView<Real>& b,
                                               const KernelArgs& args) {
  __shared__ ConvexView<Real> views[2];
  stage_both<Real, Staged>(a, b, args);
  if (threadIdx.x == 0) {
    views[0] = a;
    views[1] = b;
  }
  __syncthreads();
  return views;
}

__device__ void defer_pair(const KernelArgs& args, int i) {
  args.overflow[atomicAdd(args.overflow_count, 1)] = i;
}

// The whole overlap of each pair in one thread (overlap_polyhedra) with a workspace of Capacity
// planes: the path of templates with more than kMaxPhasedPlanes faces together, of templates too
// large to stage, and of the pairs the phased kernels defer. Staged: the templates are first
// copied into shared memory, where every thread reads them without competing with the
// workspaces for the L1 cache. The pairs: args.order[0..count) when given, else 0..count.
template <class Real, int Capacity, bool Staged>
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
  OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
  out[i] = overlap_polyhedra(a, pose_a, b, pose_b, workspace, args.options);
}

// Phase 1 of the phased path: the culling alone (overlap_cull_mask), one thread per pair. A
// pair decided here (bounding spheres apart, a separating plane) has its result written and key
// 0; the others keep their mask of kept planes and key m + 1 (m kept planes). `histogram`
// counts the keys (one atomic per block and key).
template <class Real, bool Staged>
__global__ void __launch_bounds__(kBatchBlock, kCullBlocks)
    cull_kernel(ConvexView<Real> a, ConvexView<Real> b, const Vec3<Real>* __restrict__ position_a,
                const Quat<Real>* __restrict__ orientation_a,
                const Vec3<Real>* __restrict__ position_b,
                const Quat<Real>* __restrict__ orientation_b, KernelArgs args,
                unsigned long long* __restrict__ masks, unsigned char* __restrict__ keys,
                int* __restrict__ order, int* __restrict__ histogram,
                OverlapResult<Real>* __restrict__ out) {
  const ConvexView<Real>* views = stage_views<Real, Staged>(a, b, args);
  __shared__ int block_histogram[kPhasedKeys];
  const int bins = a.n_faces + b.n_faces + 2;
  for (int k = threadIdx.x; k < bins; k += blockDim.x) block_histogram[k] = 0;
  __syncthreads();
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < args.count) {
    const Pose<Real> pose_a{position_a[i], orientation_a[i]};
    const Pose<Real> pose_b{position_b[i], orientation_b[i]};
    OverlapResult<Real> result;
    unsigned long long mask = 0;
    const int kept =
        overlap_cull_mask(views[0], pose_a, views[1], pose_b, args.options, mask, result);
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

// Phase 2 of the phased path: steps 3-5 (overlap_from_mask) of the sorted pairs
// order[begin..begin + count) with a workspace of Capacity planes; a pair it cannot hold is
// deferred.
template <class Real, int Capacity, bool Staged>
__global__ void polytope_kernel(ConvexView<Real> a, ConvexView<Real> b,
                                const Vec3<Real>* __restrict__ position_a,
                                const Quat<Real>* __restrict__ orientation_a,
                                const Vec3<Real>* __restrict__ position_b,
                                const Quat<Real>* __restrict__ orientation_b, KernelArgs args,
                                int begin, const unsigned long long* __restrict__ masks,
                                OverlapResult<Real>* __restrict__ out) {
  stage_both<Real, Staged>(a, b, args);
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= args.count) return;
  const int i = args.order[begin + j];
  const Pose<Real> pose_a{position_a[i], orientation_a[i]};
  const Pose<Real> pose_b{position_b[i], orientation_b[i]};
  OverlapWorkspace<Real, Capacity> workspace;  // per-thread local memory
  const OverlapResult<Real> result =
      overlap_from_mask(a, pose_a, b, pose_b, masks[i], workspace, args.options);
  if (result.workspace_overrun) {
    defer_pair(args, i);
    return;
  }
  out[i] = result;
}

// Phase 2 for the pairs of at most kEnumerationPlanes kept planes, order[begin..begin + count):
// the vertex enumeration alone (overlap_enumerate_from_mask), with no workspace, in a kernel of
// its own so that its registers are not those of the hull; what it declines is deferred to the
// launch that runs the whole overlap (which declines there too and builds the hull). Nothing of
// a pair goes through the thread's local memory: its planes are kept in shared memory
// (shared_enumeration_planes), and the enumeration reads the views (shared) and the poses
// (global) where they lie.
template <class Real>
__global__ void __launch_bounds__(kBatchBlock, kEnumerateBlocks<Real>)
    enumerate_kernel(ConvexView<Real> a, ConvexView<Real> b,
                     const Vec3<Real>* __restrict__ position_a,
                     const Quat<Real>* __restrict__ orientation_a,
                     const Vec3<Real>* __restrict__ position_b,
                     const Quat<Real>* __restrict__ orientation_b, KernelArgs args, int begin,
                     const unsigned long long* __restrict__ masks,
                     OverlapResult<Real>* __restrict__ out) {
  const ConvexView<Real>* views = stage_views<Real, true>(a, b, args);
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= args.count) return;
  const int i = args.order[begin + j];
  const overlap_detail::EnumerationBodies<Real> bodies{
      views[0],      views[1],         position_a[i], orientation_a[i],
      position_b[i], orientation_b[i], Real(0)};
  // The result goes straight to global memory: the enumeration sets every field when it answers
  // and none when it declines.
  if (!overlap_enumerate_from_mask(bodies, masks[i], shared_enumeration_planes<Real, kBatchBlock>(),
                                   kBatchBlock, out[i]))
    defer_pair(args, i);
}

}  // namespace

namespace overlap_batch_detail {

// The batch's device arrays and its launches. The launches are templates, instantiated only by
// launch_overlap_batch's files.
template <class Real>
struct OverlapBatchImpl {
  DeviceShape<Real> a, b;
  DeviceBuffer<Vec3<Real>> position_a, position_b;
  DeviceBuffer<Quat<Real>> orientation_a, orientation_b;
  DeviceBuffer<OverlapResult<Real>> results;
  int capacity;
  SharedShapeLayout layout_a, layout_b;

  OverlapBatchImpl(const ConvexView<Real>& host_a, const ConvexView<Real>& host_b)
      : a(host_a), b(host_b), capacity(overlap_capacity_for(host_a.n_faces + host_b.n_faces)) {
    if (host_a.n_faces + host_b.n_faces > 256)
      throw std::invalid_argument("overlap batch: the two templates have " +
                                  std::to_string(host_a.n_faces + host_b.n_faces) +
                                  " faces together; at most 256 are supported");
    layout_a = shared_layout_for(host_a, 0);
    layout_b = shared_layout_for(host_b, layout_a.bytes);
    TALUS_CUDA_CHECK(cudaStreamCreateWithFlags(&side_stream, cudaStreamNonBlocking));
    TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&fork, cudaEventDisableTiming));
    TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&join, cudaEventDisableTiming));
  }
  ~OverlapBatchImpl() {
    cudaEventDestroy(join);
    cudaEventDestroy(fork);
    cudaStreamDestroy(side_stream);
  }
  OverlapBatchImpl(const OverlapBatchImpl&) = delete;
  OverlapBatchImpl& operator=(const OverlapBatchImpl&) = delete;

  // The launches go to `stream`: the legacy default stream, or side_stream while the buckets of
  // many planes run beside the enumeration's (launch_phased); fork and join order the two.
  cudaStream_t stream = nullptr;
  cudaStream_t side_stream = nullptr;
  cudaEvent_t fork = nullptr, join = nullptr;

  bool can_stage() const { return layout_a.bytes + layout_b.bytes <= kSharedTemplateLimit; }

  // Scratch of the deferred and phased kernels, sized on first use.
  PhasedOverlapScratch scratch;
  DeviceBuffer<unsigned char> cub_temp;

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
    const int block = kBatchBlock;
    const int grid = (args.count + block - 1) / block;
    kernel<<<grid, block, shared_bytes(staged), stream>>>(a.view, b.view, position_a.data(),
                                                          orientation_a.data(), position_b.data(),
                                                          orientation_b.data(), args, extra...);
    TALUS_CUDA_LAUNCH_CHECK();
  }

  // Every pair's whole overlap in one launch (overlap_kernel), the templates staged if they fit.
  template <int Capacity>
  void launch_whole(OverlapOptions options) {
    if (can_stage())
      launch_over(overlap_kernel<Real, Capacity, true>, true, args_for(count(), options),
                  results.data());
    else
      launch_over(overlap_kernel<Real, Capacity, false>, false, args_for(count(), options),
                  results.data());
  }

  // The pairs deferred by the launches before, computed with the full workspace.
  template <int Capacity>
  void launch_deferred(OverlapOptions options) {
    KernelArgs args = args_for(scratch.deferred_count(), options);
    args.order = scratch.deferred();
    launch_over(overlap_kernel<Real, Capacity, true>, true, args, results.data());
  }

  // Phase 2 of the phased path: one launch per workspace size First, 2 First, ..., Last, each
  // over its range of the sorted pairs (the kept planes fit it and not the size before); the
  // bucket of 8 runs the vertex enumeration alone when the options ask for it.
  template <int First, int Last>
  void launch_buckets(OverlapOptions options, const PhasedBuckets& buckets) {
    const PhasedRange range = buckets.workspace(First);
    KernelArgs args = args_for(range.count, options);
    args.order = scratch.sorted_order();
    args.overflow = scratch.deferred();
    args.overflow_count = scratch.deferred_counter();
    if (First == kEnumerationPlanes && options.enumerate) {
      launch_over(enumerate_kernel<Real>, true, args, range.begin, scratch.masks(), results.data());
    } else
      launch_over(polytope_kernel<Real, First, true>, true, args, range.begin, scratch.masks(),
                  results.data());
    if constexpr (First < Last) launch_buckets<First * 2, Last>(options, buckets);
  }

  // The phased path: the culling (cull_kernel), the pairs sorted by their number of kept planes
  // (PhasedOverlapScratch), one polytope launch per workspace size over its range of the sorted
  // pairs (a warp's pairs have the same number of planes), and the deferred pairs whole.
  template <int Capacity>
  void launch_phased(OverlapOptions options) {
    const int n = count();
    scratch.prepare(n);
    launch_over(cull_kernel<Real, true>, true, args_for(n, options), scratch.masks(),
                scratch.keys(), scratch.order(), scratch.histogram(), results.data());
    const PhasedBuckets buckets = scratch.buckets();
    scratch.sort(n, planes() + 1, cub_temp);
    // Key 0 (decided by the culling) sorts first and is skipped. The buckets of more than 8
    // planes are few pairs whose threads run long (the hull): they go first, on the side
    // stream, so that the enumeration's many blocks fill the GPU around them.
    if constexpr (Capacity > kEnumerationPlanes) {
      TALUS_CUDA_CHECK(cudaEventRecord(fork, stream));
      TALUS_CUDA_CHECK(cudaStreamWaitEvent(side_stream, fork, 0));
      std::swap(stream, side_stream);
      launch_buckets<2 * kEnumerationPlanes, Capacity>(options, buckets);
      std::swap(stream, side_stream);
      TALUS_CUDA_CHECK(cudaEventRecord(join, side_stream));
    }
    launch_buckets<kEnumerationPlanes, kEnumerationPlanes>(options, buckets);
    if constexpr (Capacity > kEnumerationPlanes)
      TALUS_CUDA_CHECK(cudaStreamWaitEvent(stream, join, 0));
    launch_deferred<Capacity>(options);
  }

  // The phased path needs staged templates and at most 64 planes in all (a 64-bit mask).
  template <int Capacity>
  void launch_kernel(OverlapOptions options, bool whole) {
    if constexpr (Capacity <= kMaxPhasedPlanes) {
      if (can_stage() && !whole) return launch_phased<Capacity>(options);
    }
    launch_whole<Capacity>(options);
  }
};

// Runs the batch with the workspace of Capacity planes, by the phased path unless `whole` asks for
// overlap_kernel alone (or the templates need it). Each of the eight is instantiated in a
// generated file of its own (benchmarks/overlap_batch/CMakeLists.txt); elsewhere these
// declarations keep the kernels from being compiled again.
template <class Real, int Capacity>
void launch_overlap_batch(OverlapBatchImpl<Real>& batch, OverlapOptions options, bool whole) {
  batch.template launch_kernel<Capacity>(options, whole);
}

#define TALUS_OVERLAP_BATCH_EXTERN(Real, Capacity)                                   \
  extern template void launch_overlap_batch<Real, Capacity>(OverlapBatchImpl<Real>&, \
                                                            OverlapOptions, bool);
TALUS_OVERLAP_BATCH_EXTERN(float, 32)
TALUS_OVERLAP_BATCH_EXTERN(float, 64)
TALUS_OVERLAP_BATCH_EXTERN(float, 128)
TALUS_OVERLAP_BATCH_EXTERN(float, 256)
TALUS_OVERLAP_BATCH_EXTERN(double, 32)
TALUS_OVERLAP_BATCH_EXTERN(double, 64)
TALUS_OVERLAP_BATCH_EXTERN(double, 128)
TALUS_OVERLAP_BATCH_EXTERN(double, 256)
#undef TALUS_OVERLAP_BATCH_EXTERN

}  // namespace overlap_batch_detail

}  // namespace talus
