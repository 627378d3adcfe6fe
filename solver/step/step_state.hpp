// What a production step (host_step.hpp, cuda_step.hpp) needs to go on exactly from where it is
// (restart): the time and step count, every particle array it holds (by name: positions,
// velocities, orientations, body-frame angular velocities, the forces and torques of the last
// evaluation, which the next integrate_begin turns into the step-start terms, ...), the ids, and
// the tangential histories of the touching pairs and (particle, wall) contacts keyed by global
// ids, sorted by key (the store the next evaluation looks its histories up in). The walls'
// positions and open outlets follow from the time (scene/wall_motion.hpp), so they need no state.
// Host code, no CUDA types: the CUDA step downloads into it and uploads from it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/contact/force_law.hpp"
#include "solver/contact/tangential_history.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/step/energy.hpp"

namespace talus {

template <class Real>
struct StepState {
  double time = 0;  // s
  long long steps = 0;
  bool forces_ready = false;  // the force arrays hold the forces at `time`
  int count = 0;
  std::vector<std::pair<std::string, std::vector<Real>>> arrays;  // as allocated_arrays() names
  std::vector<int> template_ids, material_ids;
  std::vector<long long> global_ids;
  long long next_id = -1;  // the id the next inserted particle gets (-1: count, as before removal)
  long long removed = 0;   // particles removed so far
  // The CUDA step's pair list (empty elsewhere): the positions its displacements are measured
  // from (x, then y, then z, per particle) and whether the particles changed since its last
  // build. A resumed run rebuilds its list at once but renumbers by cell only where the
  // uninterrupted run would rebuild (cuda_pair_list.cuh), so that it continues bit for bit.
  std::vector<Real> list_reference;
  bool list_stale = false;
  std::vector<PairKey> pair_keys, wall_keys;  // sorted (key_less)
  std::vector<ContactHistoryData<Real>> pair_histories, wall_histories;
  // The feeds' states (Feeder::save), one per scene feed; empty for a step without feeds.
  std::vector<std::string> feed_states;
  EnergyLedger ledger;  // the energy probe's running totals
};

namespace detail {

// A history store as plain numbers: keys as (low, high) pairs, histories as (elastic tangential
// force x, y, z, approach speed, spring stiffness), so that no struct padding reaches the file.
// A checkpoint written before the spring stiffness was kept has 4 numbers a history (read as 0).
template <class Real>
void put_histories(Checkpoint& c, const std::string& name, const std::vector<PairKey>& keys,
                   const std::vector<ContactHistoryData<Real>>& histories) {
  std::vector<long long> k;
  std::vector<Real> h;
  for (const PairKey& key : keys) k.insert(k.end(), {key.low, key.high});
  for (const ContactHistoryData<Real>& d : histories)
    h.insert(h.end(), {d.elastic_force.x, d.elastic_force.y, d.elastic_force.z, d.approach_speed,
                       d.spring_stiffness, d.rocking_moment.x, d.rocking_moment.y,
                       d.rocking_moment.z, d.rocking_stiffness});
  c.put(name + ".keys", k);
  c.put(name + ".histories", h);
}

template <class Real>
void get_histories(const Checkpoint& c, const std::string& name, std::vector<PairKey>& keys,
                   std::vector<ContactHistoryData<Real>>& histories) {
  const std::vector<long long> k = c.get<long long>(name + ".keys");
  const std::vector<Real> h = c.get<Real>(name + ".histories");
  // 9 numbers a history; 5 before the rocking spring, 4 before the spring's stiffness (the
  // missing ones start at zero).
  std::size_t per = 9;
  for (const std::size_t older : {std::size_t(5), std::size_t(4)})
    if (!k.empty() && h.size() == older * (k.size() / 2)) per = older;
  if (k.size() % 2 != 0 || h.size() != per * (k.size() / 2))
    c.fail(name + ".histories", "expected one history of 9 numbers per key");
  keys.clear();
  histories.clear();
  for (std::size_t e = 0; e < k.size() / 2; ++e) {
    keys.push_back({k[2 * e], k[2 * e + 1]});
    ContactHistoryData<Real> d;
    d.elastic_force = Vec3<Real>(h[per * e], h[per * e + 1], h[per * e + 2]);
    d.approach_speed = h[per * e + 3];
    if (per >= 5) d.spring_stiffness = h[per * e + 4];
    if (per == 9) {
      d.rocking_moment = Vec3<Real>(h[per * e + 5], h[per * e + 6], h[per * e + 7]);
      d.rocking_stiffness = h[per * e + 8];
    }
    histories.push_back(d);
  }
}

}  // namespace detail

// Throws CheckpointError unless `s` fits a step of `count` particles whose real arrays are
// `names` (in order) and whose scene has `templates` templates: a checkpoint of another scene.
template <class Real>
void check_state_fits(const StepState<Real>& s, int count, const std::vector<std::string>& names,
                      int templates) {
  const auto refuse = [](const std::string& what) {
    throw CheckpointError("the checkpoint does not fit the scene: " + what);
  };
  if (s.count != count)
    refuse(std::to_string(s.count) + " particles, the scene has " + std::to_string(count));
  std::vector<std::string> held;
  for (const auto& entry : s.arrays) held.push_back(entry.first);
  if (held != names) refuse("its particle arrays are not those of the scene's effects");
  for (const int t : s.template_ids)
    if (t < 0 || t >= templates) refuse("template id " + std::to_string(t) + " out of range");
  if (s.pair_keys.size() != s.pair_histories.size() ||
      s.wall_keys.size() != s.wall_histories.size())
    refuse("history keys and values differ in number");
}

// The state as checkpoint sections "step.*", "particles.<array>", "pairs.*", "walls.*",
// "feeds.states".
template <class Real>
void put_step_state(Checkpoint& c, const StepState<Real>& s) {
  c.put_value<std::uint32_t>("step.real_size", sizeof(Real));
  c.put_value("step.time", s.time);
  c.put_value("step.steps", s.steps);
  c.put_value<std::uint8_t>("step.forces_ready", s.forces_ready ? 1 : 0);
  c.put_value("step.count", s.count);
  std::string names;
  for (const auto& [name, values] : s.arrays) {
    names += name + "\n";
    c.put("particles." + name, values);
  }
  c.put_text("step.arrays", names);
  c.put("particles.template_id", s.template_ids);
  c.put("particles.material_id", s.material_ids);
  c.put("particles.global_id", s.global_ids);
  detail::put_histories(c, "pairs", s.pair_keys, s.pair_histories);
  detail::put_histories(c, "walls", s.wall_keys, s.wall_histories);
  std::string feeds;  // one line per feed (a saved state is one line)
  for (const std::string& state : s.feed_states) feeds += state + "\n";
  c.put_text("feeds.states", feeds);
  const EnergyLedger& e = s.ledger;
  c.put("step.energy", std::vector<double>{e.dissipated, e.wall_work, e.fed, e.dissipation_rate,
                                           e.wall_power, e.spring_energy, e.removed});
  c.put("step.ids", std::vector<long long>{s.next_id, s.removed});
  if (!s.list_reference.empty()) {
    c.put("pairs.reference", s.list_reference);
    c.put_value<std::uint8_t>("pairs.stale", s.list_stale ? 1 : 0);
  }
}

// The state back from put_step_state's sections. CheckpointError when one is missing, of another
// precision (`step.real_size`) or of the wrong length.
template <class Real>
StepState<Real> get_step_state(const Checkpoint& c) {
  const auto real_size = c.get_value<std::uint32_t>("step.real_size");
  if (real_size != sizeof(Real))
    c.fail("step.real_size", "written in " + std::string(real_size == 4 ? "float" : "double") +
                                 ", read in " + (sizeof(Real) == 4 ? "float" : "double"));
  StepState<Real> s;
  s.time = c.get_value<double>("step.time");
  s.steps = c.get_value<long long>("step.steps");
  s.forces_ready = c.get_value<std::uint8_t>("step.forces_ready") != 0;
  s.count = c.get_value<int>("step.count");
  if (c.has("step.energy")) {  // absent from checkpoints written before the energy probe
    const std::vector<double> e = c.get<double>("step.energy");
    // 5 numbers before the springs' energy was kept, 6 before removal (the rest start at zero).
    if (e.size() < 5 || e.size() > 7) c.fail("step.energy", "expected 7 numbers");
    s.ledger.dissipated = e[0], s.ledger.wall_work = e[1], s.ledger.fed = e[2];
    s.ledger.dissipation_rate = e[3], s.ledger.wall_power = e[4];
    s.ledger.spring_energy = e.size() >= 6 ? e[5] : 0.0;
    s.ledger.removed = e.size() == 7 ? e[6] : 0.0;
  }
  if (c.has("step.ids")) {  // absent from checkpoints written before particles were removed
    const std::vector<long long> ids = c.get<long long>("step.ids");
    if (ids.size() != 2) c.fail("step.ids", "expected 2 numbers (next id, removed)");
    s.next_id = ids[0], s.removed = ids[1];
  }
  if (c.has("pairs.reference")) {  // a CUDA step's, since it renumbers particles by cell
    s.list_reference = c.get<Real>("pairs.reference");
    if (s.list_reference.size() != 3 * static_cast<std::size_t>(s.count))
      c.fail("pairs.reference", "expected 3 values per particle");
    s.list_stale = c.get_value<std::uint8_t>("pairs.stale") != 0;
  }
  const std::string names = c.text("step.arrays");
  const auto check = [&](const std::string& name, std::size_t size) {
    if (size != static_cast<std::size_t>(s.count))
      c.fail(name, "expected " + std::to_string(s.count) + " values, got " + std::to_string(size));
  };
  for (std::size_t at = 0, end; (end = names.find('\n', at)) != std::string::npos; at = end + 1) {
    const std::string name = names.substr(at, end - at);
    s.arrays.emplace_back(name, c.get<Real>("particles." + name));
    check("particles." + name, s.arrays.back().second.size());
  }
  s.template_ids = c.get<int>("particles.template_id");
  s.material_ids = c.get<int>("particles.material_id");
  s.global_ids = c.get<long long>("particles.global_id");
  check("particles.template_id", s.template_ids.size());
  check("particles.material_id", s.material_ids.size());
  check("particles.global_id", s.global_ids.size());
  detail::get_histories(c, "pairs", s.pair_keys, s.pair_histories);
  detail::get_histories(c, "walls", s.wall_keys, s.wall_histories);
  const std::string feeds = c.text("feeds.states");
  for (std::size_t at = 0, end; (end = feeds.find('\n', at)) != std::string::npos; at = end + 1)
    s.feed_states.push_back(feeds.substr(at, end - at));
  return s;
}

}  // namespace talus
