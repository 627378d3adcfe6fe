// A decomposed CUDA run's rebuild (cuda_decomposition.cu, migrate): the history entries of the
// particles that leave for other ranks, chosen on the device from a sorted store so that only
// they come to the host. Shared by the pair list's store (a pair key names two particles) and
// the wall stage's (a wall key names its particle in `low`). Included only from .cu files.
#pragma once

#include <cub/cub.cuh>

#include <vector>

#include "solver/contact/tangential_history.hpp"
#include "solver/core/cub_call.cuh"
#include "solver/core/device_buffer.hpp"
#include "solver/step/cuda/cuda_step_common.cuh"

namespace talus {

// flags[k]: whether store entry k names a particle among ids[0 .. n) (sorted): either of a pair
// key's two ids (`Either`), or a wall key's `low`.
template <bool Either>
__global__ void flag_keys_with(const PairKey* __restrict__ keys, int count,
                               const long long* __restrict__ ids, int n,
                               unsigned char* __restrict__ flags) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  const auto holds = [&](long long id) {
    int lo = 0, hi = n;
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      if (ids[mid] < id) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    return lo < n && ids[lo] == id;
  };
  flags[k] = holds(keys[k].low) || (Either && holds(keys[k].high));
}

// The entries of the store (`keys`, `values`: `stored` entries, sorted) that name a particle
// among `ids` (sorted global ids), in store order, downloaded into `out_keys`/`out_values`
// (`s`: the buffers, HistorySelection in cuda_step_common.cuh).
template <bool Either, class Real>
void select_histories_with(const PairKey* keys, const ContactHistoryData<Real>* values, int stored,
                           const std::vector<long long>& ids, HistorySelection<Real>& s,
                           DeviceBuffer<unsigned char>& temp, std::vector<PairKey>& out_keys,
                           std::vector<ContactHistoryData<Real>>& out_values) {
  out_keys.clear();
  out_values.clear();
  if (stored == 0 || ids.empty()) return;
  s.ids.upload(ids);
  s.flags.grow_to(stored), s.keys.grow_to(stored), s.histories.grow_to(stored);
  s.count.grow_to(1);
  flag_keys_with<Either><<<blocks_for(stored), kBlock>>>(
      keys, stored, s.ids.data(), static_cast<int>(ids.size()), s.flags.data());
  TALUS_CUDA_LAUNCH_CHECK();
  cub_call(temp, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::Flagged(t, b, keys, s.flags.data(), s.keys.data(), s.count.data(),
                                      stored);
  });
  cub_call(temp, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::Flagged(t, b, values, s.flags.data(), s.histories.data(),
                                      s.count.data(), stored);
  });
  const int n = download(s.count.data(), 1).at(0);
  out_keys = download(s.keys.data(), n);
  out_values = download(s.histories.data(), n);
}

}  // namespace talus
