// The broad phase on the GPU (see contact_pairs_gpu.hpp): reductions for the grid, bucket per
// particle, CUB radix sort by bucket, bucket ranges, count per particle, CUB exclusive scan,
// write and per-segment sort. Every step is the host driver's, in the same order.
#include "solver/neighbor/contact_pairs_gpu.hpp"

#include <cub/cub.cuh>

#include <algorithm>

#include <climits>
#include <cmath>
#include <stdexcept>
#include <string>

#include "solver/core/cub_call.cuh"
#include "solver/core/device_buffer.hpp"

namespace talus {

namespace {

constexpr int kBlock = 256;

int blocks_for(int n) {
  return (n + kBlock - 1) / kBlock;
}

// Index of the first particle with a non-finite position or a negative or non-finite radius.
template <class Real>
__global__ void find_bad_particle(NeighborInput<Real> in, int* first_bad) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.count) return;
  const bool bad = !is_finite(in.x[i]) || !is_finite(in.y[i]) || !is_finite(in.z[i]) ||
                   !is_finite(in.radius[i]) || in.radius[i] < 0;
  if (bad) atomicMin(first_bad, i);
}

template <class Real>
__global__ void bucket_particles(NeighborInput<Real> in, NeighborGrid<Real> grid,
                                 std::uint32_t* bucket_of, int* index) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.count) return;
  bucket_of[i] = particle_bucket(in, grid, i);
  index[i] = i;
}

// begin[b], end[b]: the range of bucket b in the sorted order (both 0 when b is empty).
__global__ void bucket_ranges(const std::uint32_t* sorted_bucket, int n, int* begin, int* end) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n) return;
  const std::uint32_t b = sorted_bucket[s];
  if (s == 0 || sorted_bucket[s - 1] != b) begin[b] = s;
  if (s == n - 1 || sorted_bucket[s + 1] != b) end[b] = s + 1;
}

template <class Real>
__global__ void count_partners(NeighborInput<Real> in, NeighborGrid<Real> grid, const int* begin,
                               const int* end, const int* sorted, int* counts) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.count) return;
  int count = 0;
  for_each_partner(in, grid, begin, end, sorted, i, [&](int) { ++count; });
  counts[i] = count;
}

template <class Real>
__global__ void write_partners(NeighborInput<Real> in, NeighborGrid<Real> grid, const int* begin,
                               const int* end, const int* sorted, const int* first,
                               ContactPair* pairs) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.count) return;
  int slot = first[i];
  for_each_partner(in, grid, begin, end, sorted, i, [&](int j) {
    pairs[slot++] = ContactPair{i, j};
  });
  sort_segment_by_partner(pairs, first[i], first[i + 1]);
}

// Each particle's Morton cell key (particle_cell_key) and its index, for the sort by cell.
template <class Real>
__global__ void cell_keys(NeighborInput<Real> in, NeighborGrid<Real> grid, std::uint64_t* key,
                          int* index) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.count) return;
  key[i] = particle_cell_key(in, grid, i);
  index[i] = i;
}

// Reduction functors (CUB's Min/Max operators changed names across versions).
struct MinOp {
  template <class T>
  __device__ T operator()(const T& a, const T& b) const {
    return b < a ? b : a;
  }
};
struct MaxOp {
  template <class T>
  __device__ T operator()(const T& a, const T& b) const {
    return a < b ? b : a;
  }
};

}  // namespace

template <class Real>
struct ContactPairsGpu<Real>::Impl {
  int count = 0;
  Real skin = 0;
  DeviceBuffer<Real> x, y, z, radius;
  NeighborInput<Real> external;  // set_device_particles: the caller's arrays (x null: none)
  DeviceBuffer<std::uint32_t> bucket_of, sorted_bucket;
  DeviceBuffer<int> index, sorted, begin, end, counts, first, scratch_int;
  DeviceBuffer<Real> reduced;  // origin x, y, z and r_max
  DeviceBuffer<unsigned char> temp;
  DeviceBuffer<ContactPair> pairs;
  DeviceBuffer<std::uint64_t> cell_key, sorted_cell_key;  // cell_order's
  long long pair_count = 0;

  // Throws std::invalid_argument for a non-finite particle (the reductions below would carry a
  // NaN into the grid).
  void check_particles(const NeighborInput<Real>& in);
  // The grid as make_neighbor_grid makes it (origin at the lowest coordinates, or the input's
  // fixed origin; cells of 2 r_max + skin); `bits`: the bucket table's log2 size.
  NeighborGrid<Real> make_grid(const NeighborInput<Real>& in, Real min_cell, int& bits);

  NeighborInput<Real> input() const {
    if (external.x) return external;
    NeighborInput<Real> in;
    in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = radius.data();
    in.count = count;
    in.skin = skin;
    return in;
  }
};

template <class Real>
ContactPairsGpu<Real>::ContactPairsGpu() : impl_(std::make_unique<Impl>()) {}

template <class Real>
ContactPairsGpu<Real>::~ContactPairsGpu() = default;

template <class Real>
void ContactPairsGpu<Real>::set_particles(const NeighborInput<Real>& host) {
  Impl& m = *impl_;
  m.external = NeighborInput<Real>();
  m.count = host.count;
  m.skin = host.skin;
  m.x.upload(host.x, host.count);
  m.y.upload(host.y, host.count);
  m.z.upload(host.z, host.count);
  m.radius.upload(host.radius, host.count);
}

template <class Real>
void ContactPairsGpu<Real>::set_device_particles(const NeighborInput<Real>& device_input) {
  Impl& m = *impl_;
  m.external = device_input;
  m.count = device_input.count;
  m.skin = device_input.skin;
}

template <class Real>
void ContactPairsGpu<Real>::Impl::check_particles(const NeighborInput<Real>& in) {
  scratch_int.resize(1);
  const int none = INT_MAX;
  scratch_int.upload(&none, 1);
  find_bad_particle<<<blocks_for(in.count), kBlock>>>(in, scratch_int.data());
  TALUS_CUDA_LAUNCH_CHECK();
  int first_bad = INT_MAX;
  TALUS_CUDA_CHECK(cudaMemcpy(&first_bad, scratch_int.data(), sizeof(int), cudaMemcpyDeviceToHost));
  if (first_bad != INT_MAX) {
    throw std::invalid_argument("neighbour search: particle " + std::to_string(first_bad) +
                                " has a non-finite position or a bad bounding radius");
  }
}

template <class Real>
NeighborGrid<Real> ContactPairsGpu<Real>::Impl::make_grid(const NeighborInput<Real>& in,
                                                          Real min_cell, int& bits) {
  const int n = in.count;
  // A fixed origin (the local domain's reach box) needs only r_max.
  reduced.resize(4);
  const Real* sources[4] = {in.x, in.y, in.z, in.radius};
  for (int k = in.fixed_origin ? 3 : 0; k < 4; ++k) {
    Real* out = reduced.data() + k;
    const Real initial = k < 3 ? Real(HUGE_VAL) : Real(0);
    if (k < 3) {
      cub_call(temp, [&](void* t, std::size_t& b) {
        return cub::DeviceReduce::Reduce(t, b, sources[k], out, n, MinOp(), initial);
      });
    } else {
      cub_call(temp, [&](void* t, std::size_t& b) {
        return cub::DeviceReduce::Reduce(t, b, sources[k], out, n, MaxOp(), initial);
      });
    }
  }
  std::vector<Real> values;
  reduced.download(values);
  NeighborGrid<Real> grid;
  for (int k = 0; k < 3; ++k) grid.origin[k] = in.fixed_origin ? in.origin[k] : values[k];
  grid.cell_size = max_of(min_cell, Real(2) * values[3] + skin);
  if (!(grid.cell_size > 0)) grid.cell_size = 1;
  std::uint32_t size = 64;
  bits = 6;
  while (size < 2u * static_cast<std::uint32_t>(n) && size < (1u << 30)) size *= 2, ++bits;
  grid.bucket_mask = size - 1;
  return grid;
}

template <class Real>
double ContactPairsGpu<Real>::build(Real min_cell) {
  Impl& m = *impl_;
  const int n = m.count;
  m.pair_count = 0;
  if (n == 0) return 0;
  const NeighborInput<Real> in = m.input();

  m.check_particles(in);

  cudaEvent_t start, stop;
  TALUS_CUDA_CHECK(cudaEventCreate(&start));
  TALUS_CUDA_CHECK(cudaEventCreate(&stop));
  TALUS_CUDA_CHECK(cudaEventRecord(start));

  int bits = 6;
  const NeighborGrid<Real> grid = m.make_grid(in, min_cell, bits);
  const std::uint32_t size = grid.bucket_mask + 1;

  // Bin and sort by bucket (radix sort is stable: indices ascend within a bucket). The scratch
  // is sized exactly at first and then only grows, by half again when a feeding run outgrows it:
  // an exact resize at every insertion would free and allocate (a device synchronisation) each
  // time, while a fixed scene keeps its exact footprint.
  const auto room = [](auto& buffer, std::size_t count) {
    if (buffer.size() < count)
      buffer.resize(buffer.size() == 0 ? count : std::max(count, buffer.size() * 3 / 2));
  };
  const std::size_t count = static_cast<std::size_t>(n);
  room(m.bucket_of, count), room(m.sorted_bucket, count), room(m.index, count);
  room(m.sorted, count);
  bucket_particles<<<blocks_for(n), kBlock>>>(in, grid, m.bucket_of.data(), m.index.data());
  TALUS_CUDA_LAUNCH_CHECK();
  cub_call(m.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceRadixSort::SortPairs(t, b, m.bucket_of.data(), m.sorted_bucket.data(),
                                           m.index.data(), m.sorted.data(), n, 0, bits);
  });
  room(m.begin, size), room(m.end, size);
  TALUS_CUDA_CHECK(cudaMemset(m.begin.data(), 0, size * sizeof(int)));
  TALUS_CUDA_CHECK(cudaMemset(m.end.data(), 0, size * sizeof(int)));
  bucket_ranges<<<blocks_for(n), kBlock>>>(m.sorted_bucket.data(), n, m.begin.data(), m.end.data());
  TALUS_CUDA_LAUNCH_CHECK();

  // Count, exclusive scan, write (paper Fig. 3c).
  room(m.counts, count + 1), room(m.first, count + 1);
  TALUS_CUDA_CHECK(cudaMemset(m.counts.data() + n, 0, sizeof(int)));
  count_partners<<<blocks_for(n), kBlock>>>(in, grid, m.begin.data(), m.end.data(), m.sorted.data(),
                                            m.counts.data());
  TALUS_CUDA_LAUNCH_CHECK();
  cub_call(m.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceScan::ExclusiveSum(t, b, m.counts.data(), m.first.data(), n + 1);
  });
  int total = 0;
  TALUS_CUDA_CHECK(cudaMemcpy(&total, m.first.data() + n, sizeof(int), cudaMemcpyDeviceToHost));
  // Grow-only: a step rebuilds the list every step, and its length changes a little each time.
  m.pairs.grow_to(static_cast<std::size_t>(total));
  if (total > 0) {
    write_partners<<<blocks_for(n), kBlock>>>(in, grid, m.begin.data(), m.end.data(),
                                              m.sorted.data(), m.first.data(), m.pairs.data());
    TALUS_CUDA_LAUNCH_CHECK();
  }
  m.pair_count = total;
  TALUS_CUDA_CHECK(cudaEventRecord(stop));
  TALUS_CUDA_CHECK(cudaEventSynchronize(stop));
  float ms = 0;
  TALUS_CUDA_CHECK(cudaEventElapsedTime(&ms, start, stop));
  TALUS_CUDA_CHECK(cudaEventDestroy(start));
  TALUS_CUDA_CHECK(cudaEventDestroy(stop));
  return ms;
}

template <class Real>
void ContactPairsGpu<Real>::cell_order(int* device_order) {
  Impl& m = *impl_;
  const int n = m.count;
  if (n == 0) return;
  const NeighborInput<Real> in = m.input();
  m.check_particles(in);
  int bits = 6;
  const NeighborGrid<Real> grid = m.make_grid(in, Real(0), bits);
  m.cell_key.grow_to(n), m.sorted_cell_key.grow_to(n), m.index.grow_to(n);
  cell_keys<<<blocks_for(n), kBlock>>>(in, grid, m.cell_key.data(), m.index.data());
  TALUS_CUDA_LAUNCH_CHECK();
  // Stable: the particles of one cell keep their order. Keys have 63 bits (21 per axis).
  cub_call(m.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceRadixSort::SortPairs(t, b, m.cell_key.data(), m.sorted_cell_key.data(),
                                           m.index.data(), device_order, n, 0, 63);
  });
}

template <class Real>
std::vector<ContactPair> ContactPairsGpu<Real>::pairs() const {
  std::vector<ContactPair> out(impl_->pair_count);
  if (!out.empty()) {
    TALUS_CUDA_CHECK(cudaMemcpy(out.data(), impl_->pairs.data(), out.size() * sizeof(ContactPair),
                                cudaMemcpyDeviceToHost));
  }
  return out;
}

template <class Real>
long long ContactPairsGpu<Real>::pair_count() const {
  return impl_->pair_count;
}

template <class Real>
const ContactPair* ContactPairsGpu<Real>::device_pairs() const {
  return impl_->pairs.data();
}

template <class Real>
std::size_t ContactPairsGpu<Real>::allocated_bytes() const {
  const Impl& m = *impl_;
  return (m.x.size() + m.y.size() + m.z.size() + m.radius.size() + m.reduced.size()) *
             sizeof(Real) +
         (m.bucket_of.size() + m.sorted_bucket.size()) * sizeof(std::uint32_t) +
         (m.index.size() + m.sorted.size() + m.begin.size() + m.end.size() + m.counts.size() +
          m.first.size() + m.scratch_int.size()) *
             sizeof(int) +
         (m.cell_key.size() + m.sorted_cell_key.size()) * sizeof(std::uint64_t) + m.temp.size() +
         m.pairs.size() * sizeof(ContactPair);
}

template class ContactPairsGpu<float>;
template class ContactPairsGpu<double>;

}  // namespace talus
