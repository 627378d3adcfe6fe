// The wall benchmarks' scene: a drum (axis +y, centred at the origin, rotating at 30 rpm) of
// `segments` sides — 2 x segments side strips and 2 x segments cap triangles (fans), 4 x segments
// facets — filled with 10 mm dodecahedra on a cubic lattice of 8.2 mm with random orientations
// (about 3 pair contacts per particle, as dodecahedron_bed.hpp), every lattice point whose centre
// is at least 4 mm inside the wall, so that the outer layer touches the side; the length is
// 2 (layers x 8.2 mm + 4 mm), so that the layers at y = +-layers x 8.2 mm touch the caps.
// Gravity, the volume model, friction and rotation; double.
#pragma once

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>

#include "solver/scene/scene_loader.hpp"
#include "solver/step/step_plan.hpp"

namespace talus_bench {

inline talus::Scene drum_bed(int segments, double radius, int layers) {
  const double spacing = 0.0082, inside = 0.004;
  const double length = 2 * (layers * spacing + inside);
  const std::string yaml = R"(time: {step: 1.0e-6, end: 1.0}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: "dodecahedron:0.01", material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0]}
walls:
  - drum: {center: [0, 0, 0], axis: [0, 1, 0], radius: )" +
                           std::to_string(radius) + ", length: " + std::to_string(length) +
                           ", segments: " + std::to_string(segments) + R"(, material: glass,
           motion: {rotation: {axis: [0, 1, 0], point: [0, 0, 0], rpm: 30}}}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)";
  talus::Scene scene = talus::parse_scene(yaml, "drum_bed.yaml", ".");
  const talus::ParticleState model = scene.particles.front();
  scene.particles.clear();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  const int half = static_cast<int>(radius / spacing) + 1;
  for (int k = -half; k <= half; ++k) {
    for (int j = -half; j <= half; ++j) {
      for (int i = -half; i <= half; ++i) {
        const talus::Vec3d p(spacing * i, spacing * j, spacing * k);
        if (std::hypot(p.x, p.z) > radius - inside || std::abs(j) > layers) {
          continue;
        }
        talus::ParticleState s = model;
        s.position = p;
        double w = unit(rng), x = unit(rng), y = unit(rng), z = unit(rng);
        const double norm = std::sqrt(w * w + x * x + y * y + z * z);
        if (norm > 0) s.orientation = talus::Quatd(w / norm, x / norm, y / norm, z / norm);
        scene.particles.push_back(s);
      }
    }
  }
  return scene;
}

// The wall benchmarks' loop, for the host and the CUDA step alike: one step per iteration after a
// first one; counters ms_wall_contacts (the wall stage's share of a step), wall contacts per step,
// facets (4 x segments) and particles.
template <class Step>
void time_wall_stage(benchmark::State& state, Step& step, int segments) {
  step.step();
  const int stage = static_cast<int>(talus::Stage::wall_contacts);
  const double before = step.stage_seconds()[stage];
  double wall_contacts = 0;
  long long steps = 0;
  for (auto _ : state) {
    step.step();
    wall_contacts += double(step.wall_contact_count());
    ++steps;
  }
  const double per_step = steps > 0 ? 1.0 / double(steps) : 0;
  state.counters["ms_wall_contacts"] = 1e3 * (step.stage_seconds()[stage] - before) * per_step;
  state.counters["wall_contacts_per_step"] = wall_contacts * per_step;
  state.counters["facets"] = 4.0 * segments;
  state.counters["particles"] = step.particle_count();
}

}  // namespace talus_bench
