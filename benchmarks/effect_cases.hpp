// The effect-cost table's scene and its variants (bench_effects.cpp; issue 20): one scene file with
// every effect and every output on (benchmarks/scenes/effects.yaml), and the same scene with each
// taken away in turn, made by editing the loaded Scene. tests/scene/test_benchmark_scenes.cpp
// checks that each variant lacks exactly what its name says.
//
// Every variant starts from the same settled state: a checkpoint of the whole scene, which
// checkpoint_for_variant() turns into one the variant's step accepts (the step refuses a
// checkpoint whose arrays, walls or feeds are not the scene's, step_state.hpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "benchmarks/scene_cases.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/step_plan.hpp"

namespace talus_bench {

// Settled for 12,000 steps (0.24 s: the bed has fallen together and turns with the drum), where
// the scene's feed begins; each timed window holds at least one of every output (each written
// every 100 steps at most, benchmarks/scenes/effects.yaml). The host's window is a few seconds on
// the 2-core development host.
inline constexpr SceneCase kEffectsCase{
    "effects", "benchmarks/scenes/effects.yaml", 12000, 50, 2500, 100, false};

struct EffectVariant {
  std::string name;                              // "all", "without_drag", ...
  std::function<void(talus::Scene&)> take_away;  // does nothing for "all"
};

inline void drop_probe(talus::Scene& scene, talus::Probe probe) {
  if (!scene.outputs.probes) return;
  std::vector<talus::Probe>& q = scene.outputs.probes->quantities;
  q.erase(std::remove(q.begin(), q.end(), probe), q.end());
  if (q.empty()) scene.outputs.probes.reset();
}

// "all", then without_<effect> for each effect, then without_output_<output> for each output the
// scene writes (probe quantities as probe_<quantity>, and the probe file as a whole as probes).
inline std::vector<EffectVariant> effect_variants(const talus::Scene& all) {
  using talus::Scene;
  std::vector<EffectVariant> v;
  v.push_back({"all", [](Scene&) {}});
  // bed_height is measured along -g, so the runner refuses it without gravity: this variant also
  // lacks that probe, whose own cost is without_output_probe_bed_height's.
  v.push_back({"without_gravity", [](Scene& s) {
                 s.effects.gravity.reset();
                 drop_probe(s, talus::Probe::bed_height);
               }});
  v.push_back({"without_friction", [](Scene& s) { s.effects.friction = false; }});
  v.push_back({"without_rotation", [](Scene& s) { s.effects.rotation = false; }});
  v.push_back({"without_walls", [](Scene& s) {
                 const auto fixed = [](const talus::WallSpec& w) {
                   return w.motion.kind == talus::WallMotion::Kind::none;
                 };
                 s.walls.erase(std::remove_if(s.walls.begin(), s.walls.end(), fixed),
                               s.walls.end());
                 s.effects.walls = !s.walls.empty();
               }});
  // The drum held still, not taken away: its motion is the effect.
  v.push_back({"without_moving_walls", [](Scene& s) {
                 for (talus::WallSpec& w : s.walls) w.motion = talus::WallMotion{};
                 s.effects.moving_walls = false;
               }});
  v.push_back({"without_drag", [](Scene& s) { s.effects.drag_alpha.reset(); }});
  v.push_back({"without_feed", [](Scene& s) {
                 s.feeds.clear();
                 s.effects.feed = false;
               }});
  const talus::Outputs& o = all.outputs;
  if (o.trajectories)
    v.push_back({"without_output_trajectories", [](Scene& s) { s.outputs.trajectories.reset(); }});
  if (o.vtk) v.push_back({"without_output_vtk", [](Scene& s) { s.outputs.vtk.reset(); }});
  if (o.checkpoint)
    v.push_back({"without_output_checkpoint", [](Scene& s) { s.outputs.checkpoint.reset(); }});
  if (o.probes) {
    v.push_back({"without_output_probes", [](Scene& s) { s.outputs.probes.reset(); }});
    for (const talus::Probe probe : o.probes->quantities)
      v.push_back({std::string("without_output_probe_") + talus::to_string(probe),
                   [probe](Scene& s) { drop_probe(s, probe); }});
  }
  return v;
}

inline talus::Scene make_variant(const talus::Scene& all, const EffectVariant& variant) {
  talus::Scene scene = all;
  variant.take_away(scene);
  return scene;
}

// A checkpoint of `all` (a whole run's, production_run.cpp) as one of `variant`, a copy of it
// with some effects or outputs taken away: the particle arrays those of the variant's plan, the
// (particle, wall) histories of the walls it keeps renumbered to their places in its list, the
// feeds' states dropped with the feeds, and the probe file's record dropped (the variant's probe
// file has other columns: its runner is given one with the header alone). The particles and
// their pair histories are the same. std::invalid_argument for a variant that keeps some feeds.
inline talus::Checkpoint checkpoint_for_variant(const talus::Checkpoint& settled,
                                                const talus::Scene& all,
                                                const talus::Scene& variant) {
  talus::Checkpoint c;
  c.set_path(settled.path());
  for (const talus::CheckpointSection& s : settled.sections())
    if (s.name != "outputs.probes") c.put_bytes(s.name, s.element_size, s.bytes);

  std::string arrays;
  for (const std::string& name : talus::particle_array_names(talus::plan_step(variant).arrays))
    arrays += name + "\n";
  c.put_text("step.arrays", arrays);

  // Keys are (particle id, wall index) pairs; the kept walls keep their order, so the renumbered
  // keys stay sorted.
  std::vector<long long> wall_at(all.walls.size(), -1);
  for (std::size_t w = 0; w < all.walls.size(); ++w)
    for (std::size_t k = 0; k < variant.walls.size(); ++k)
      if (variant.walls[k].name == all.walls[w].name) wall_at[w] = static_cast<long long>(k);
  const std::vector<long long> keys = settled.get<long long>("walls.keys");
  const talus::CheckpointSection* histories = nullptr;
  for (const talus::CheckpointSection& s : settled.sections())
    if (s.name == "walls.histories") histories = &s;
  if (!histories) settled.fail("walls.histories", "missing");
  const std::size_t entries = keys.size() / 2;
  const std::size_t bytes_each = entries ? histories->bytes.size() / entries : 0;
  std::vector<long long> kept_keys;
  std::string kept_histories;
  for (std::size_t e = 0; e < entries; ++e) {
    const long long wall = keys[2 * e + 1];
    if (wall < 0 || wall >= static_cast<long long>(wall_at.size()) || wall_at[wall] < 0) continue;
    kept_keys.insert(kept_keys.end(), {keys[2 * e], wall_at[wall]});
    kept_histories += histories->bytes.substr(e * bytes_each, bytes_each);
  }
  c.put("walls.keys", kept_keys);
  c.put_bytes("walls.histories", histories->element_size, kept_histories);

  if (variant.feeds.empty())
    c.put_text("feeds.states", "");
  else if (variant.feeds.size() != all.feeds.size())
    throw std::invalid_argument("checkpoint_for_variant: a variant keeps all feeds or none");
  return c;
}

}  // namespace talus_bench
