// A scene whose only pair has no contact geometry, for the tests of the degenerate-pair message
// on both backends (tests/step/test_degenerate_report.cpp, tests/gpu/...): two balls with one
// centre (one sphere inside the other has no contact circle), at a position whose 0.1 is not a
// binary fraction, so the message's 17 digits are seen.
#pragma once

namespace talus_test {

inline const char* degenerate_pair_scene() {
  return R"(time: {step: 1.0e-5, end: 1.0e-4}
materials:
  stone: {density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.5,
          restitution: 0.5}
templates:
  ball: {sphere: 0.005, material: stone}
effects: {contact: volume}
particles:
  - explicit:
      - {template: ball, position: [0.1, -0.25, 0.0625]}
      - {template: ball, position: [0.1, -0.25, 0.0625]}
)";
}

// The part of the message naming particle 1 and its pose (17 significant digits give 0.1 back).
inline const char* degenerate_pair_pose() {
  return "particle 1 (template 'ball') at (0.10000000000000001, -0.25, 0.0625), "
         "orientation (1, 0, 0, 0)";
}

}  // namespace talus_test
