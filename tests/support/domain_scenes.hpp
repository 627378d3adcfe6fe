// Scenes shared by the host and GPU tests of the domain box and the renumbering by cell
// (tests/step/test_domain_step.cpp, tests/gpu/test_domain_gpu.cpp).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <utility>

#include "solver/step/step_state.hpp"

namespace talus::testing {

// 24 dodecahedra of 10 mm poured into an open box (a random fill, group A: they land and touch,
// with friction and rotation, so their contacts carry tangential histories) and, when `rain` is
// true, 8 more (a 2 x 2 x 2 lattice, group B, listed first: ids 0-7) beside the box and far from
// it, thrown down at 2 m/s with nothing under them. `domain` adds a domain box whose floor is 20
// mm under the box's, so that group B leaves it (and is removed) after about 10 ms; `reorder`
// renumbers the particles by cell at every build. The time step is the advisor's.
inline std::string pour_scene(bool rain, bool domain, bool reorder, double end = 0.03) {
  std::string yaml = "time: {step: auto, end: " + std::to_string(end) + R"(}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e6, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: "dodecahedron:0.01", material: glass}
walls:
  - box: {min: [0, 0, 0], max: [0.05, 0.05, 0.1], material: glass, open_top: true}
particles:
)";
  if (rain)
    yaml += R"(  - lattice:
      template: grain
      region: {box: {min: [0.1, 0, 0], max: [0.121, 0.021, 0.021]}}
      spacing: 0.0105
      velocity: [0, 0, -2]
      random_orientation: true
      seed: 3
)";
  yaml += R"(  - random:
      template: grain
      region: {box: {min: [0.002, 0.002, 0.002], max: [0.048, 0.048, 0.04]}}
      count: 24
      seed: 5
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)";
  if (domain) yaml += "domain: {min: [-0.01, -0.01, -0.02], max: [0.2, 0.1, 0.2]}\n";
  if (reorder) yaml += "reorder: true\n";
  return yaml;
}

// A step state's pair histories by key (the pairs' global ids, low then high).
template <class Real>
std::map<std::pair<long long, long long>, talus::ContactHistoryData<Real>> histories_by_key(
    const talus::StepState<Real>& s) {
  std::map<std::pair<long long, long long>, talus::ContactHistoryData<Real>> h;
  for (std::size_t k = 0; k < s.pair_keys.size(); ++k)
    h[{s.pair_keys[k].low, s.pair_keys[k].high}] = s.pair_histories[k];
  return h;
}

}  // namespace talus::testing
