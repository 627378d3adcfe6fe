// The store of contact histories (tangential spring, approach speed) keyed by the global ids of
// the two particles, so that a history survives a rebuild of the pair list, a reordering of the
// particles and (later) a migration between ranks. The keys are kept sorted; a pair finds its
// previous history by binary search (TALUS_HD: one thread per pair on the GPU), and the next
// store is the touching pairs' keys and histories, sorted: contacts that ended are dropped.
#pragma once

#include "solver/contact/force_law.hpp"

namespace talus {

// A pair of global ids, low first. The spring is stored as seen from `low` as body A.
struct PairKey {
  long long low = 0, high = 0;
};

TALUS_HD inline PairKey make_pair_key(long long id_a, long long id_b) {
  return id_a < id_b ? PairKey{id_a, id_b} : PairKey{id_b, id_a};
}

TALUS_HD inline bool key_less(const PairKey& p, const PairKey& q) {
  return p.low < q.low || (p.low == q.low && p.high < q.high);
}

TALUS_HD inline bool key_equal(const PairKey& p, const PairKey& q) {
  return p.low == q.low && p.high == q.high;
}

// Index of `key` in keys[0 .. count) (sorted ascending), or -1.
TALUS_HD inline int find_pair_key(const PairKey* keys, int count, const PairKey& key) {
  int lo = 0, hi = count;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (key_less(keys[mid], key)) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo < count && key_equal(keys[lo], key) ? lo : -1;
}

}  // namespace talus
