#include "solver/step/gathered_state.hpp"

#include <algorithm>

namespace talus {

template <class Real>
void sorted_store(std::vector<KeyedHistory<Real>>& in, std::vector<PairKey>& keys,
                  std::vector<ContactHistoryData<Real>>& histories) {
  std::stable_sort(in.begin(), in.end(),
                   [](const auto& a, const auto& b) { return key_less(a.key, b.key); });
  in.erase(std::unique(in.begin(), in.end(),
                       [](const auto& a, const auto& b) { return key_equal(a.key, b.key); }),
           in.end());
  keys.clear();
  histories.clear();
  for (const auto& e : in) keys.push_back(e.key), histories.push_back(e.history);
}

void gather_positions(const Communicator& comm, const std::vector<Vec3d>& own_positions,
                      const std::vector<int>& own_templates, std::vector<Vec3d>& positions,
                      std::vector<int>& templates) {
  Bytes mine;
  ByteWriter w(mine);
  for (std::size_t i = 0; i < own_positions.size(); ++i) {
    w.put(own_positions[i]);
    w.put(own_templates.at(i));
  }
  positions.clear();
  templates.clear();
  for (const Bytes& b : comm.all_gather(mine)) {
    ByteReader r(b);
    while (!r.done()) {
      positions.push_back(r.get<Vec3d>());
      templates.push_back(r.get<int>());
    }
  }
}

template <class Real>
std::vector<std::vector<KeyedHistory<Real>>> histories_by_destination(
    const std::vector<PairKey>& keys, const std::vector<ContactHistoryData<Real>>& histories,
    const std::vector<std::pair<long long, int>>& leaving, bool pair, int ranks) {
  const auto destination = [&](long long id) {
    const auto it = std::lower_bound(leaving.begin(), leaving.end(), std::make_pair(id, -1));
    return it != leaving.end() && it->first == id ? it->second : -1;
  };
  std::vector<std::vector<KeyedHistory<Real>>> out(ranks);
  for (std::size_t k = 0; k < keys.size() && !leaving.empty(); ++k) {
    const int d_low = destination(keys[k].low);
    const int d_high = pair ? destination(keys[k].high) : -1;
    if (d_low >= 0) out[d_low].push_back({keys[k], histories[k]});
    if (d_high >= 0 && d_high != d_low) out[d_high].push_back({keys[k], histories[k]});
  }
  return out;
}

template <class Real>
StepState<Real> gather_step_states(const Communicator& comm, const StepState<Real>& mine) {
  Bytes bytes;
  ByteWriter w(bytes);
  w.put(static_cast<long long>(mine.count));
  for (int i = 0; i < mine.count; ++i) {
    w.put(mine.global_ids[i]);
    w.put(mine.template_ids[i]);
    w.put(mine.material_ids[i]);
    for (const auto& entry : mine.arrays) w.put(entry.second[i]);
  }
  const auto put_store = [&](const std::vector<PairKey>& keys,
                             const std::vector<ContactHistoryData<Real>>& histories) {
    std::vector<KeyedHistory<Real>> all;
    for (std::size_t k = 0; k < keys.size(); ++k) all.push_back({keys[k], histories[k]});
    w.put_vector(all);
  };
  put_store(mine.pair_keys, mine.pair_histories);
  put_store(mine.wall_keys, mine.wall_histories);
  w.put(mine.ledger);
  w.put(mine.removed);
  struct Row {
    long long id;
    int rank, index;
  };
  StepState<Real> s;
  std::vector<Row> rows;
  const std::vector<Bytes> all = comm.all_gather(bytes);
  const std::size_t arrays = mine.arrays.size();
  std::vector<std::vector<int>> templates(all.size()), materials(all.size());
  std::vector<std::vector<Real>> values(all.size());  // row-major, `arrays` numbers a particle
  std::vector<KeyedHistory<Real>> pairs, walls;
  for (std::size_t r = 0; r < all.size(); ++r) {
    ByteReader in(all[r]);
    const long long n = in.get<long long>();
    for (long long i = 0; i < n; ++i) {
      const long long id = in.get<long long>();
      templates[r].push_back(in.get<int>());
      materials[r].push_back(in.get<int>());
      for (std::size_t a = 0; a < arrays; ++a) values[r].push_back(in.get<Real>());
      rows.push_back({id, static_cast<int>(r), static_cast<int>(i)});
    }
    const auto p = in.get_vector<KeyedHistory<Real>>();
    const auto q = in.get_vector<KeyedHistory<Real>>();
    pairs.insert(pairs.end(), p.begin(), p.end());
    walls.insert(walls.end(), q.begin(), q.end());
    const EnergyLedger l = in.get<EnergyLedger>();
    s.ledger.dissipated += l.dissipated;
    s.ledger.wall_work += l.wall_work;
    s.ledger.fed += l.fed;
    s.ledger.removed += l.removed;
    s.ledger.dissipation_rate += l.dissipation_rate;
    s.ledger.wall_power += l.wall_power;
    s.ledger.spring_energy += l.spring_energy;
    s.removed += in.get<long long>();
  }
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.id < b.id; });
  s.time = mine.time;
  s.steps = mine.steps;
  s.forces_ready = mine.forces_ready;
  s.count = static_cast<int>(rows.size());
  for (std::size_t a = 0; a < arrays; ++a) {
    s.arrays.emplace_back(mine.arrays[a].first, std::vector<Real>());
    s.arrays.back().second.reserve(rows.size());
    for (const Row& row : rows)
      s.arrays.back().second.push_back(values[row.rank][row.index * arrays + a]);
  }
  for (const Row& row : rows) {
    s.global_ids.push_back(row.id);
    s.template_ids.push_back(templates[row.rank][row.index]);
    s.material_ids.push_back(materials[row.rank][row.index]);
  }
  s.next_id = mine.next_id;
  s.list_stale = true;  // the list is the ranks'; a resumed run builds its own
  sorted_store(pairs, s.pair_keys, s.pair_histories);
  sorted_store(walls, s.wall_keys, s.wall_histories);
  s.feed_states = mine.feed_states;
  return s;
}

#define TALUS_INSTANTIATE_GATHERED_STATE(Real)                                              \
  template void sorted_store(std::vector<KeyedHistory<Real>>&, std::vector<PairKey>&,       \
                             std::vector<ContactHistoryData<Real>>&);                       \
  template StepState<Real> gather_step_states(const Communicator&, const StepState<Real>&); \
  template std::vector<std::vector<KeyedHistory<Real>>> histories_by_destination(           \
      const std::vector<PairKey>&, const std::vector<ContactHistoryData<Real>>&,            \
      const std::vector<std::pair<long long, int>>&, bool, int);
TALUS_INSTANTIATE_GATHERED_STATE(double)
TALUS_INSTANTIATE_GATHERED_STATE(float)
#undef TALUS_INSTANTIATE_GATHERED_STATE

}  // namespace talus
