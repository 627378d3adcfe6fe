// The production step on the host backend (solver/step/host_step): the same bed of dodecahedra
// with each effect taken away in turn, so that what an effect costs is the difference (DESIGN.md:
// an absent effect has no stage). The bed: a 10 x 10 x 10 cubic lattice of 10 mm dodecahedra at
// a spacing of 8.2 mm with random orientations (particles overlap neighbours from the first
// step), in a closed box wall.
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "solver/scene/scene_loader.hpp"
#include "solver/step/host_step.hpp"

namespace {

// The scene with the named effects (YAML lines under `effects:`), walls when `walls` is set.
talus::Scene bed_scene(const std::string& effects, bool walls) {
  std::string yaml = R"(time: {step: 1.0e-6, end: 1.0}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: "dodecahedron:0.01", material: glass}
particles:
  - explicit:
)";
  // The lattice by hand: the loader's lattice keeps bounding spheres apart, this bed overlaps.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const double x = 0.0041 + 0.0082 * (i % 10), y = 0.0041 + 0.0082 * ((i / 10) % 10);
    const double z = 0.0041 + 0.0082 * (i / 100);
    yaml += "      - {template: grain, position: [" + std::to_string(x) + ", " + std::to_string(y) +
            ", " + std::to_string(z) + "], orientation: {axis: [" + std::to_string(unit(rng)) +
            ", " + std::to_string(unit(rng)) + ", " + std::to_string(unit(rng) + 1.5) +
            "], degrees: " + std::to_string(180 * unit(rng)) + "}}\n";
  }
  if (walls) {
    yaml += R"(walls:
  - box: {min: [-0.0005, -0.0005, -0.0005], max: [0.0825, 0.0825, 0.0825], material: glass}
)";
  }
  yaml += "effects:\n" + effects;
  return talus::parse_scene(yaml, "bench_step_cpu.yaml", ".");
}

void host_step(benchmark::State& state, const std::string& effects, bool walls) {
  const talus::Scene scene = bed_scene(effects, walls);
  talus::HostStep<double> step(scene);
  step.step();  // the first step evaluates the forces at t = 0 too
  double contacts = 0;
  long long steps = 0;
  for (auto _ : state) {
    step.step();
    contacts += double(step.pair_contact_count() + step.wall_contact_count());
    ++steps;
  }
  const double particles = step.particle_count();
  state.counters["particle_steps/s"] =
      benchmark::Counter(particles, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["contacts_per_step"] = steps > 0 ? contacts / double(steps) : 0;
  state.counters["particles"] = particles;
}

const std::string kAll =
    "  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n  rotation: true\n";

}  // namespace

BENCHMARK_CAPTURE(host_step, all_effects, kAll, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_step, no_walls, kAll, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_step, no_friction,
                  "  gravity: [0, 0, -9.81]\n  contact: volume\n  rotation: true\n", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_step, no_rotation,
                  "  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_step, with_drag, kAll + "  drag: {alpha: 1.0e-4}\n", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_step, linear_model,
                  "  gravity: [0, 0, -9.81]\n  contact: {model: linear, stiffness: 1.0e4, "
                  "damping: 0.5, tangential_damping: 1.0}\n  friction: true\n  rotation: true\n",
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(host_step, gravity_only, "  gravity: [0, 0, -9.81]\n", false)
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
