// What a production step (host_step.hpp, cuda_step.hpp) needs to go on exactly from where it is
// (restart): the time and step count, every particle array it holds (by name: positions,
// velocities, orientations, body-frame angular velocities, the forces and torques of the last
// evaluation, which the next integrate_begin turns into the step-start terms, ...), the ids, and
// the tangential histories of the touching pairs and (particle, wall) contacts keyed by global
// ids, sorted by key (the store the next evaluation looks its histories up in). The walls'
// positions and open outlets follow from the time (scene/wall_motion.hpp), so they need no state.
// Host code, no CUDA types: the CUDA step downloads into it and uploads from it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/contact/force_law.hpp"
#include "solver/contact/tangential_history.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/scene/scene.hpp"
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
  // The pair list's (either step's; empty without a skin or before a build): the positions its
  // displacements are measured from (x, then y, then z, per particle) and whether the particles
  // changed since its last build. A resumed run renumbers by cell only where the uninterrupted
  // run would rebuild (cuda_pair_list.cuh, contact_stage.hpp), so it continues bit for bit.
  std::vector<Real> list_reference;
  bool list_stale = false;
  std::vector<PairKey> pair_keys, wall_keys;  // sorted (key_less)
  std::vector<ContactHistoryData<Real>> pair_histories, wall_histories;
  // The feeds' states (Feeder::save), one per scene feed; empty for a step without feeds.
  std::vector<std::string> feed_states;
  EnergyLedger ledger;  // the energy probe's running totals
  // The checkpoint file the state was read from (get_step_state), for the messages of
  // check_state_fits; empty for a state made in memory.
  std::string source;
};

// How far a restored orientation's norm may be from 1: the integrator renormalizes every step
// (dynamics/integrator.hpp) and a unit quaternion rounded to Real is within a few epsilon of
// norm 1, so 1000 epsilon (1.2e-4 in float, 2.2e-13 in double) never refuses a written state
// and still refuses any quaternion that was not a rotation.
template <class Real>
constexpr double kOrientationNormTolerance = 1000.0 * std::numeric_limits<Real>::epsilon();

namespace detail {

// A history store as plain numbers: keys as (low, high) pairs, histories as (elastic tangential
// force x, y, z, approach speed, spring stiffness), so that no struct padding reaches the file.
// A checkpoint written before the spring stiffness was kept has 4 numbers a history (read as 0).
// The histories' numbers in that order, 9 a history.
template <class Real>
std::vector<Real> history_numbers(const std::vector<ContactHistoryData<Real>>& histories) {
  std::vector<Real> h;
  for (const ContactHistoryData<Real>& d : histories)
    h.insert(h.end(), {d.elastic_force.x, d.elastic_force.y, d.elastic_force.z, d.approach_speed,
                       d.spring_stiffness, d.rocking_moment.x, d.rocking_moment.y,
                       d.rocking_moment.z, d.rocking_stiffness});
  return h;
}

template <class Real>
void put_histories(Checkpoint& c, const std::string& name, const std::vector<PairKey>& keys,
                   const std::vector<ContactHistoryData<Real>>& histories) {
  std::vector<long long> k;
  for (const PairKey& key : keys) k.insert(k.end(), {key.low, key.high});
  c.put(name + ".keys", k);
  c.put(name + ".histories", history_numbers(histories));
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

// A number as %.17g: the bits of a refused value are in the message.
inline std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// Particle i as a message names it.
inline std::string particle_text(const std::vector<long long>& global_ids, std::size_t i) {
  return "particle " + std::to_string(i) +
         (i < global_ids.size() ? " (global id " + std::to_string(global_ids[i]) + ")" : "");
}

// The first of `values` that is not finite, as "<what> k has <value>" (k counting groups of `per`),
// or empty.
template <class T>
std::string first_not_finite(const std::vector<T>& values, const std::string& what,
                             std::size_t per = 1) {
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(static_cast<double>(values[k])))
      return what + " " + std::to_string(k / per) + " has " + number_text(values[k]);
  return "";
}

// A history store's keys: sorted, each once, and naming what exists: for pairs two particle
// ids low < high, below `next_id` (a particle removed since may still be named: the store drops
// its entries at the next evaluation); for walls a particle id and a wall index below `walls`.
inline std::string bad_history_key(const std::vector<PairKey>& keys, long long next_id, int walls) {
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const PairKey& key = keys[k];
    const std::string at = "key " + std::to_string(k) + " (" + std::to_string(key.low) + ", " +
                           std::to_string(key.high) + ")";
    if (key.low < 0 || key.low >= next_id)
      return at + ": particle id " + std::to_string(key.low) + " is not one of the ids 0 to " +
             std::to_string(next_id - 1) + " given so far";
    if (walls < 0 && (key.high <= key.low || key.high >= next_id))
      return at + ": expected a second particle id above the first and below " +
             std::to_string(next_id);
    if (walls >= 0 && (key.high < 0 || key.high >= walls))
      return at + ": wall " + std::to_string(key.high) + ", the scene has " +
             std::to_string(walls) + " walls";
    if (k > 0 && !key_less(keys[k - 1], key))
      return at + ": the keys are not sorted in increasing order, each once";
  }
  return "";
}

}  // namespace detail

// Whether a checkpoint of `count` particles can continue a run of `scene` whose step started with
// `initial` (its own plus the scene's left_out_particles): as many, more where feeds insert
// (`feeding`), fewer where the domain box removes, any count on several ranks (`decomposed`: each
// rank holds a share). Where it cannot, check_state_fits with `initial` refuses it.
inline bool checkpoint_count_fits(long long count, long long initial, const Scene& scene,
                                  bool feeding, bool decomposed) {
  return count == initial || (feeding && count > initial) || (scene.domain && count < initial) ||
         decomposed;
}

// Throws CheckpointError unless `s` fits a step of `count` particles whose real arrays are
// `names` (in order) made from `scene` (a checkpoint of another scene), and unless every value
// it holds is one the step can go on from: a checkpoint is read from a file, and a value no run
// writes (a material id beyond the scene's, a NaN position, a duplicated id, unsorted history
// keys) would otherwise be used as an index or reach the contact laws. The message names the
// file (`s.source`), the section and the value.
template <class Real>
void check_state_fits(const StepState<Real>& s, const Scene& scene, int count,
                      const std::vector<std::string>& names) {
  const auto refuse = [&](const std::string& section, const std::string& what) {
    throw_checkpoint_error(s.source, section, what);
  };
  const auto refuse_unless_empty = [&](const std::string& section, const std::string& what) {
    if (!what.empty()) refuse(section, what);
  };
  const std::string no_fit = "the checkpoint does not fit the scene: ";
  if (s.count != count)
    refuse("step.count",
           no_fit + std::to_string(s.count) + " particles, the scene has " + std::to_string(count));
  std::vector<std::string> held;
  for (const auto& entry : s.arrays) held.push_back(entry.first);
  if (held != names)
    refuse("step.arrays", no_fit + "its particle arrays are not those of the scene's effects");
  const std::size_t n = static_cast<std::size_t>(count);
  if (s.template_ids.size() != n || s.material_ids.size() != n || s.global_ids.size() != n)
    refuse("particles.global_id", "expected " + std::to_string(n) + " ids of each kind");

  // The clock: steps of the scene's dt summed one by one (host_step.cpp, cuda_step.cu), so
  // time is steps * dt up to the sum's round-off, at most steps^2 / 2 half-ulps of steps * dt;
  // steps (steps + 1) epsilon dt bounds it with room to spare.
  if (s.steps < 0)
    refuse("step.steps", "expected a step count >= 0, got " + std::to_string(s.steps));
  const double dt = scene.time_step, steps = static_cast<double>(s.steps);
  const double slack = steps * (steps + 1) * std::numeric_limits<double>::epsilon() * dt;
  if (!std::isfinite(s.time) || !(std::abs(s.time - steps * dt) <= slack))
    refuse("step.time", detail::number_text(s.time) + " s after " + std::to_string(s.steps) +
                            " steps of " + detail::number_text(dt) + " s; expected " +
                            detail::number_text(steps * dt) + " s within the sum's round-off " +
                            detail::number_text(slack) + " s");

  // Ids: each particle's unique, from 0 up to the next id to be given (as many as the particles
  // when an older checkpoint has no step.ids).
  if (s.next_id < -1)
    refuse("step.ids", "next id " + std::to_string(s.next_id) + "; expected >= 0");
  if (s.removed < 0)
    refuse("step.ids", "removed " + std::to_string(s.removed) + " particles; expected >= 0");
  const long long next_id = s.next_id >= 0 ? s.next_id : s.count;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string who = detail::particle_text(s.global_ids, i);
    if (s.global_ids[i] < 0 || s.global_ids[i] >= next_id)
      refuse("particles.global_id", who + ": expected an id from 0 to " +
                                        std::to_string(next_id - 1) + " (the next id is " +
                                        std::to_string(next_id) + ")");
    const int t = s.template_ids[i], m = s.material_ids[i];
    if (t < 0 || t >= static_cast<int>(scene.templates.size()))
      refuse("particles.template_id", who + " has template id " + std::to_string(t) +
                                          "; the scene has " +
                                          std::to_string(scene.templates.size()) + " templates");
    if (m < 0 || m >= static_cast<int>(scene.materials.size()))
      refuse("particles.material_id", who + " has material id " + std::to_string(m) +
                                          "; the scene has " +
                                          std::to_string(scene.materials.size()) + " materials");
  }
  std::vector<long long> sorted_ids = s.global_ids;
  std::sort(sorted_ids.begin(), sorted_ids.end());
  const auto twin = std::adjacent_find(sorted_ids.begin(), sorted_ids.end());
  if (twin != sorted_ids.end())
    refuse("particles.global_id",
           "global id " + std::to_string(*twin) + " is held by two particles");

  // The particle arrays: finite, bounding radii their templates', orientations of unit norm.
  for (const auto& [name, values] : s.arrays)
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        refuse("particles." + name,
               detail::particle_text(s.global_ids, i) + " has " + detail::number_text(values[i]));
  // Each bounding radius is its template's (HostStep::set_particle, the CUDA particles'): the
  // broad phase sizes its cells by them. In Real, the template's radius is rounded and grown to
  // cover its rounded vertices (shape_arrays.hpp), a few float epsilons at most: a relative 1e-5
  // leaves room for that and refuses any other radius.
  for (const auto& [name, values] : s.arrays) {
    if (name != "bounding_radius") continue;
    for (std::size_t i = 0; i < n; ++i) {
      const double expected = scene.templates[s.template_ids[i]].bounding_radius;
      if (!(std::abs(values[i] - expected) <= 1e-5 * expected))
        refuse("particles.bounding_radius",
               detail::particle_text(s.global_ids, i) + " has " + detail::number_text(values[i]) +
                   " m; its template '" + scene.templates[s.template_ids[i]].name + "' has " +
                   detail::number_text(expected) + " m");
    }
  }
  const std::vector<Real>* q[4] = {};
  const char* parts[4] = {"orientation.w", "orientation.x", "orientation.y", "orientation.z"};
  for (const auto& [name, values] : s.arrays)
    for (int c = 0; c < 4; ++c)
      if (name == parts[c]) q[c] = &values;
  if (q[0] && q[1] && q[2] && q[3]) {
    for (std::size_t i = 0; i < n; ++i) {
      const double w = (*q[0])[i], x = (*q[1])[i], y = (*q[2])[i], z = (*q[3])[i];
      const double norm = std::sqrt(w * w + x * x + y * y + z * z);
      if (!(std::abs(norm - 1) <= kOrientationNormTolerance<Real>))
        refuse("particles.orientation.*", detail::particle_text(s.global_ids, i) +
                                              " has an orientation of norm " +
                                              detail::number_text(norm) + "; expected 1 within " +
                                              detail::number_text(kOrientationNormTolerance<Real>));
    }
  }

  // The history stores and the pair list's reference.
  if (s.pair_keys.size() != s.pair_histories.size() ||
      s.wall_keys.size() != s.wall_histories.size())
    refuse("pairs.histories", "history keys and values differ in number");
  refuse_unless_empty("pairs.keys", detail::bad_history_key(s.pair_keys, next_id, -1));
  refuse_unless_empty("walls.keys", detail::bad_history_key(s.wall_keys, next_id,
                                                            static_cast<int>(scene.walls.size())));
  refuse_unless_empty(
      "pairs.histories",
      detail::first_not_finite(detail::history_numbers(s.pair_histories), "history", 9));
  refuse_unless_empty(
      "walls.histories",
      detail::first_not_finite(detail::history_numbers(s.wall_histories), "history", 9));
  if (!s.list_reference.empty() && s.list_reference.size() != 3 * n)
    refuse("pairs.reference", "expected 3 values per particle, got " +
                                  std::to_string(s.list_reference.size()) + " for " +
                                  std::to_string(n) + " particles");
  refuse_unless_empty("pairs.reference",
                      detail::first_not_finite(s.list_reference, "reference of particle", 3));

  // The energy ledger.
  const EnergyLedger& e = s.ledger;
  refuse_unless_empty("step.energy",
                      detail::first_not_finite(
                          std::vector<double>{e.dissipated, e.wall_work, e.fed, e.dissipation_rate,
                                              e.wall_power, e.spring_energy, e.removed},
                          "number"));
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
  s.source = c.path();
  s.time = c.get_value<double>("step.time");
  s.steps = c.get_value<long long>("step.steps");
  s.forces_ready = c.get_value<std::uint8_t>("step.forces_ready") != 0;
  s.count = c.get_value<int>("step.count");
  if (s.count < 0)
    c.fail("step.count", "expected a particle count >= 0, got " + std::to_string(s.count));
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
  if (c.has("pairs.reference")) {  // absent where the list had none, and in older checkpoints
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
