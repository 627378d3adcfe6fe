// What the host step's and the CUDA step's decompositions share (host_decomposition.cpp,
// cuda_decomposition.cu; docs/parallel.md): every rank's positions gathered, a migration's
// histories sorted by destination, and a decomposed step's state as one process's (each rank's
// share gathered on every rank into the state a run on any number of ranks restarts from).
#pragma once

#include <utility>
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

// Every rank's particle positions and templates on every rank, in rank order (a feed's inputs, a
// new bisection): `own_positions`, `own_templates` this rank's. A collective.
void gather_positions(const Communicator& comm, const std::vector<Vec3d>& own_positions,
                      const std::vector<int>& own_templates, std::vector<Vec3d>& positions,
                      std::vector<int>& templates);

// A migration's history entries by destination: the entries of `keys` (with `histories`) that
// name a leaving particle, for the rank it goes to. `leaving`: (global id, destination rank),
// sorted. Pair keys go to the destinations of both their particles; wall keys (`pair` false) name
// the particle in `low`.
template <class Real>
std::vector<std::vector<KeyedHistory<Real>>> histories_by_destination(
    const std::vector<PairKey>& keys, const std::vector<ContactHistoryData<Real>>& histories,
    const std::vector<std::pair<long long, int>>& leaving, bool pair, int ranks);

// `mine`: this rank's share (time, steps, forces_ready, next_id and the feeds' states as every
// rank has them; count, arrays and ids of its own particles in any order; the histories it
// holds; its ledger and removed count). Returns on every rank the whole run's state: the
// particles in global-id order, the histories merged, the ledgers and removed counts summed in
// rank order, list_stale set (a resumed run builds its own list). A collective.
template <class Real>
StepState<Real> gather_step_states(const Communicator& comm, const StepState<Real>& mine);

}  // namespace talus
