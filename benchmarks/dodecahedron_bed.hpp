// The bed the step benchmarks run: side^3 dodecahedra of 10 mm on a cubic lattice of 8.2 mm with
// random orientations (they overlap from the first step: about 3 pair contacts per particle,
// the density of a settled bed), optionally inside a closed box wall, with the given effects.
// The loader's lattice keeps bounding spheres apart, so the particles are set explicitly.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "solver/scene/scene_loader.hpp"

namespace talus_bench {

// `effects`: the YAML lines under `effects:` (each indented by two spaces).
inline talus::Scene dodecahedron_bed(int side, const std::string& effects, bool walls) {
  const double spacing = 0.0082, extent = spacing * side;
  std::string yaml = R"(time: {step: 1.0e-6, end: 1.0}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: "dodecahedron:0.01", material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0]}
)";
  if (walls) {
    const std::string lo = std::to_string(-0.0005), hi = std::to_string(extent + 0.0005);
    yaml += "walls:\n  - box: {min: [" + lo + ", " + lo + ", " + lo + "], max: [" + hi + ", " + hi +
            ", " + hi + "], material: glass}\n";
  }
  yaml += "effects:\n" + effects;
  talus::Scene scene = talus::parse_scene(yaml, "dodecahedron_bed.yaml", ".");
  // The particles themselves are set here rather than parsed: a million YAML entries would
  // take the loader longer than the benchmark.
  const talus::ParticleState model = scene.particles.front();
  scene.particles.clear();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  const long long count = static_cast<long long>(side) * side * side;
  scene.particles.reserve(count);
  for (long long i = 0; i < count; ++i) {
    talus::ParticleState p = model;
    p.position = talus::Vec3d(spacing * (0.5 + i % side), spacing * (0.5 + (i / side) % side),
                              spacing * (0.5 + i / (static_cast<long long>(side) * side)));
    double w = unit(rng), x = unit(rng), y = unit(rng), z = unit(rng);
    const double norm = std::sqrt(w * w + x * x + y * y + z * z);
    if (norm > 0) p.orientation = talus::Quatd(w / norm, x / norm, y / norm, z / norm);
    scene.particles.push_back(p);
  }
  return scene;
}

// The scene's particles in a random order (seeded): a poured bed's particles are numbered in
// the order they were fed, not by where they came to rest, so neighbours lie far apart in memory.
inline void shuffle_particles(talus::Scene& scene, std::uint64_t seed = 17) {
  std::mt19937_64 rng(seed);
  std::shuffle(scene.particles.begin(), scene.particles.end(), rng);
}

// Gravity, the volume model, friction and rotation.
inline const std::string kAllEffects =
    "  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n  rotation: true\n";

}  // namespace talus_bench
