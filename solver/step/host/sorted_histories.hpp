// Host side of the tangential history (solver/contact/tangential_history.hpp): what a contact
// stage keeps for its next evaluation.
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

#include "solver/contact/force_law.hpp"
#include "solver/contact/tangential_history.hpp"

namespace talus {

// The touching contacts' keys and histories, sorted by key (find_pair_key's binary search needs
// that order). Record: a contact record with `key` and `history` (pair or wall).
template <class Record, class Real>
void sort_histories_by_key(const std::vector<Record>& contacts, std::vector<PairKey>& keys,
                           std::vector<ContactHistoryData<Real>>& histories) {
  std::vector<int> order(contacts.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int x, int y) { return key_less(contacts[x].key, contacts[y].key); });
  keys.resize(order.size());
  histories.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    keys[k] = contacts[order[k]].key;
    histories[k] = contacts[order[k]].history;
  }
}

}  // namespace talus
