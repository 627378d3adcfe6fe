// The broad phase of contact_pairs.hpp on the GPU: the same per-particle steps, one thread per
// particle, with CUB for the reductions, the sort by bucket and the exclusive scan. Host-facing
// (no CUDA types); implemented in contact_pairs_gpu.cu, CUDA builds only.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "solver/neighbor/contact_pairs.hpp"

namespace talus {

template <class Real>
class ContactPairsGpu {
 public:
  ContactPairsGpu();
  ~ContactPairsGpu();
  ContactPairsGpu(const ContactPairsGpu&) = delete;
  ContactPairsGpu& operator=(const ContactPairsGpu&) = delete;

  // Copies the particles (host arrays) to the device, where they stay for repeated builds.
  void set_particles(const NeighborInput<Real>& host_input);
  // Uses particles that already live on the device (`device_input`'s arrays are device pointers,
  // owned by the caller and read by every later build(): the production step's own arrays, with
  // no copy through the host).
  void set_device_particles(const NeighborInput<Real>& device_input);
  // Builds the pair list on the device from the resident particles (the grid as
  // make_neighbor_grid makes it: the same cells, buckets and, after the per-particle sort, the
  // same list as build_candidate_pairs). Returns the time in milliseconds (CUDA events), from
  // the reductions to the last write. Throws std::invalid_argument for a non-finite particle.
  double build(Real min_cell = 0);
  // The resident particles' indices in the order of their cells' Morton keys, into
  // `device_order` (count entries, device memory): cell_order of contact_pairs.hpp on the device,
  // the same order. Throws std::invalid_argument for a non-finite particle.
  void cell_order(int* device_order);
  // The list of the last build, downloaded.
  std::vector<ContactPair> pairs() const;
  long long pair_count() const;
  // The list of the last build in device memory (pair_count() entries, sorted by (a, b)); valid
  // until the next build.
  const ContactPair* device_pairs() const;
  // Device bytes held (the pair list, the binning and scan arrays, CUB's scratch).
  std::size_t allocated_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace talus
