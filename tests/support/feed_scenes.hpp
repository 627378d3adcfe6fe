// Scene text shared by the host and GPU feeding tests (ProductionVsReference.FeedIntoABoxLinear
// and FeedGpu.FeedIntoABoxLinearMatchesHost run the same scene).
#pragma once

#include <string>

namespace talus::testing {

// One ball on the floor of a box, then 2000 balls per second for 10 ms (20, one every 100 steps
// of 5 us) thrown down at 0.5 m/s, the linear model with friction and rotation. The caller adds
// the time line and the `glass` material.
inline constexpr const char* kBallFeedScene = R"(
templates:
  ball: {sphere: 0.003, material: glass}
walls:
  - box: {min: [-0.02, -0.02, 0], max: [0.02, 0.02, 0.04], material: glass}
particles:
  - explicit:
      - {template: ball, position: [0, 0, 0.0031]}
  - feed:
      template: ball
      region: {box: {min: [-0.016, -0.016, 0.006], max: [0.016, 0.016, 0.03]}}
      rate: 2000
      start: 0
      stop: 0.01
      velocity: [0, 0, -0.5]
      seed: 7
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)";

// 20 balls in 10 ms (2000 a second) thrown down at 1 m/s into a box, from a region low over its
// floor, the linear model with friction and rotation, 5 us steps, ending at `end` (s): the feeding
// scene of the host's restart and pair-list tests (tests/step/test_restart.cpp,
// test_host_pair_list.cpp).
inline std::string thrown_feed_scene(const std::string& end) {
  return "time: {step: 5.0e-6, end: " + end + R"(}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  ball: {sphere: 0.003, material: glass}
walls:
  - box: {min: [-0.02, -0.02, 0], max: [0.02, 0.02, 0.04], material: glass}
particles:
  - feed:
      template: ball
      region: {box: {min: [-0.016, -0.016, 0.004], max: [0.016, 0.016, 0.02]}}
      rate: 2000
      stop: 0.01
      velocity: [0, 0, -1]
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
)";
}

}  // namespace talus::testing
