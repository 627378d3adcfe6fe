// A decomposed step's state as one process's (docs/parallel.md): each rank's share (its own
// particles, the histories it holds, its part of the energy ledger and of the removed count)
// gathered on every rank into the state a run on any number of ranks restarts from. Shared by
// the host step (host_decomposition.cpp) and the CUDA step (cuda_decomposition.cu).
#pragma once

#include <vector>

#include "solver/domain/communicator.hpp"
#include "solver/step/step_state.hpp"

namespace talus {

// A history with its key, as a decomposed step sends it (plain bytes).
template <class Real>
struct KeyedHistory {
  PairKey key;
  ContactHistoryData<Real> history;
};

// `in` sorted by key, one entry a key (the first of equal keys: two ranks that computed a pair
// hold the same history), into a store's keys and histories.
template <class Real>
void sorted_store(std::vector<KeyedHistory<Real>>& in, std::vector<PairKey>& keys,
                  std::vector<ContactHistoryData<Real>>& histories);

// `mine`: this rank's share (time, steps, forces_ready, next_id and the feeds' states as every
// rank has them; count, arrays and ids of its own particles in any order; the histories it
// holds; its ledger and removed count). Returns on every rank the whole run's state: the
// particles in global-id order, the histories merged, the ledgers and removed counts summed in
// rank order, list_stale set (a resumed run builds its own list). A collective.
template <class Real>
StepState<Real> gather_step_states(const Communicator& comm, const StepState<Real>& mine);

}  // namespace talus
