// The phased GPU overlap between its kernels, written once for its two users: the step's pair
// stage (solver/step/cuda/cuda_pair_stage_impl.cuh) and the overlap batch
// (benchmarks/overlap_batch/overlap_batch_kernels.cuh). Their kernels differ (the step reads its
// particles and applies the contact law; the batch reads pose arrays and writes OverlapResult);
// around them the phases are the same: a culling kernel writes per pair the mask of its kept
// planes, its key (0: decided by the culling; m + 1: m kept planes) and its index as its place
// in the order, and counts the keys; PhasedOverlapScratch sorts the order by key and cuts the
// sorted pairs into one range per workspace size (8, 16, 32, 64 planes) for the caller's
// polytope kernels, which append what their workspace cannot hold to a deferral list for the
// whole overlap. Also the enumeration's planes in shared memory (shared_enumeration_planes).
// Included only from .cu files (docs/geometry.md, "Workspace and the GPU batch").
#pragma once

#include <cub/device/device_radix_sort.cuh>

#include <cstddef>

#include "solver/core/cub_call.cuh"
#include "solver/core/device_buffer.hpp"
#include "solver/geometry/vertex_enumeration.hpp"

namespace talus {

// A pair's kept planes are the bits of a 64-bit mask, so the phased path takes at most 64 planes
// in all; the keys it counts are 0 .. kMaxPhasedPlanes + 1.
constexpr int kMaxPhasedPlanes = 64;
constexpr int kPhasedKeys = kMaxPhasedPlanes + 2;
// The workspace sizes of phase 2: 8 << s planes for s = 0 .. kPhasedSizes - 1, from the vertex
// enumeration's (kEnumerationPlanes) up to the mask's.
constexpr int kPhasedSizes = 4;
static_assert((kEnumerationPlanes << (kPhasedSizes - 1)) == kMaxPhasedPlanes,
              "8, 16, 32, 64 planes");

// A range of the sorted pairs: order positions [begin, begin + count).
struct PhasedRange {
  int begin = 0;
  int count = 0;
};

// The sorted pairs cut by key: first those the culling decided (key 0), then size[s], the pairs
// whose kept planes the workspace of 8 << s planes holds and that of the size before does not
// (size[0] from no plane to 8). Keys above kPhasedKeys - 1 (a pair the caller leaves to another
// path) sort after them all and are in none.
struct PhasedBuckets {
  PhasedRange settled;
  PhasedRange size[kPhasedSizes];

  // The range of the workspace of `planes` (8, 16, 32 or 64) planes.
  __host__ __device__ const PhasedRange& workspace(int planes) const {
    int s = 0;
    while ((kEnumerationPlanes << s) < planes) ++s;
    return size[s];
  }
};

// The histogram of the keys (kPhasedKeys counts) cut into the ranges of the sorted pairs.
__host__ __device__ inline PhasedBuckets phased_buckets_from(const int* counts) {
  PhasedBuckets b;
  b.settled = {0, counts[0]};
  int begin = counts[0];
  for (int s = 0, m = 0; s < kPhasedSizes; ++s) {  // m kept planes: key m + 1
    int count = 0;
    for (; m <= (kEnumerationPlanes << s); ++m) count += counts[m + 1];
    b.size[s] = {begin, count};
    begin += count;
  }
  return b;
}

// The buckets on the device, for launches sized by their capacity (a graph step). A template, so
// that every .cu file including this header may instantiate it.
template <class Buckets>
__global__ void phased_buckets_kernel(const int* __restrict__ counts, Buckets* buckets) {
  if (blockIdx.x == 0 && threadIdx.x == 0) *buckets = phased_buckets_from(counts);
}

// The per-pair arrays of the phases and their counters, on the device, grown to the most pairs
// asked for and kept between calls. The culling kernel fills masks(), keys(), order() and
// histogram(); the polytope kernels read sorted_order() and masks() and append to deferred(),
// counting in deferred_counter().
class PhasedOverlapScratch {
 public:
  // Room for n pairs, and the histogram and deferral count zeroed (one memset on `stream`).
  void prepare(int n, cudaStream_t stream = 0) {
    masks_.grow_to(n), keys_.grow_to(n), sorted_keys_.grow_to(n);
    order_.grow_to(n), sorted_order_.grow_to(n), deferred_.grow_to(n);
    counters_.grow_to(kPhasedKeys + 1);
    device_buckets_.grow_to(1);
    TALUS_CUDA_CHECK(cudaMemsetAsync(counters_.data(), 0, (kPhasedKeys + 1) * sizeof(int), stream));
  }

  // The order of the first n pairs sorted by key (keys at most max_key; only the bits that can
  // be set are sorted), on the default stream. Stable: the pairs of one key stay in order, so
  // each range of sorted_order() is in pair order.
  void sort(int n, int max_key, DeviceBuffer<unsigned char>& temp, cudaStream_t stream = 0) {
    int bits = 1;
    while ((1 << bits) <= max_key) ++bits;
    cub_call(temp, [&](void* storage, std::size_t& bytes) {
      return cub::DeviceRadixSort::SortPairs(storage, bytes, keys_.data(), sorted_keys_.data(),
                                             order_.data(), sorted_order_.data(), n, 0, bits,
                                             stream);
    });
  }

  // The histogram, downloaded (this waits for the culling kernel), cut into the ranges of the
  // sorted pairs.
  PhasedBuckets buckets() const {
    int counts[kPhasedKeys];
    TALUS_CUDA_CHECK(cudaMemcpy(counts, histogram(), sizeof(counts), cudaMemcpyDeviceToHost));
    return phased_buckets_from(counts);
  }
  // The same cut on the device, into device_buckets() (nothing waits).
  void buckets_on_device(cudaStream_t stream) {
    phased_buckets_kernel<PhasedBuckets><<<1, 1, 0, stream>>>(histogram(), device_buckets_.data());
    TALUS_CUDA_LAUNCH_CHECK();
  }
  const PhasedBuckets* device_buckets() const { return device_buckets_.data(); }

  // The pairs the polytope kernels deferred, downloaded (this waits for them).
  int deferred_count() const {
    int count = 0;
    TALUS_CUDA_CHECK(
        cudaMemcpy(&count, counters_.data() + kPhasedKeys, sizeof(int), cudaMemcpyDeviceToHost));
    return count;
  }

  unsigned long long* masks() { return masks_.data(); }
  unsigned char* keys() { return keys_.data(); }
  int* order() { return order_.data(); }
  int* histogram() { return counters_.data(); }  // kPhasedKeys entries, one per key
  const int* histogram() const { return counters_.data(); }
  const int* sorted_order() const { return sorted_order_.data(); }
  int* deferred() { return deferred_.data(); }
  int* deferred_counter() { return counters_.data() + kPhasedKeys; }

  std::size_t bytes() const {
    return (order_.size() + sorted_order_.size() + deferred_.size() + counters_.size()) *
               sizeof(int) +
           masks_.size() * sizeof(unsigned long long) + keys_.size() + sorted_keys_.size() +
           device_buckets_.size() * sizeof(PhasedBuckets);
  }

 private:
  DeviceBuffer<unsigned long long> masks_;
  DeviceBuffer<unsigned char> keys_, sorted_keys_;
  DeviceBuffer<int> order_, sorted_order_, deferred_;
  DeviceBuffer<int> counters_;  // [key]: the histogram; [kPhasedKeys]: the deferred pairs
  DeviceBuffer<PhasedBuckets> device_buckets_;
};

// The vertex enumeration's planes of the calling thread in a block of Block threads, in shared
// memory rather than in the thread's local memory: thread t's plane q at planes[q * Block + t]
// (pass Block as overlap_enumerate_from_mask's stride), so that a warp reads one plane of 32
// threads from consecutive addresses. Raw bytes: a __shared__ array may not have a constructor,
// which EnumerationPlane's Vec3 has.
template <class Real, int Block>
__device__ overlap_detail::EnumerationPlane<Real>* shared_enumeration_planes() {
  using Plane = overlap_detail::EnumerationPlane<Real>;
  __shared__ __align__(
      alignof(Plane)) unsigned char bytes[kEnumerationPlanes * Block * sizeof(Plane)];
  return reinterpret_cast<Plane*>(bytes) + threadIdx.x;
}

}  // namespace talus
