// The scene of the restart tests (tests/step/test_restart.cpp on the host step,
// tests/gpu/test_restart_gpu.cpp on the CUDA step): two layers of icosahedra thrown down into a
// turning drum under a lid that moves down, with gravity, the volume model, friction and rotation,
// so that pair and wall histories (a moving wall's among them) are there when a checkpoint is
// written; every output every step or few, checkpoints every 40 of its 120 steps. No feed
// (test_restart.cpp and tests/gpu/test_feed_gpu.cpp have feeding runs of their own).
// And the comparison of two steps' states, to the bit.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "solver/scene/scene_loader.hpp"
#include "solver/step/step_state.hpp"

namespace talus_test {

inline std::string restart_scene_yaml(const std::string& precision = "double") {
  return "time: {step: 2.0e-5, end: 2.4e-3}\nprecision: " + precision + R"(
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  ico: {shape: "icosahedron:0.009", material: glass}
particles:
  - lattice: {template: ico, spacing: 0.0093, random_orientation: true, velocity: [0, 0, -0.6],
              region: {box: {min: [-0.014, -0.0095, -0.0302], max: [0.014, 0.0095, -0.0208]}}}
  - lattice: {template: ico, spacing: 0.0093, random_orientation: true, velocity: [0.2, 0, -1.5],
              region: {box: {min: [-0.014, -0.0095, -0.0208], max: [0.014, 0.0095, -0.0114]}}}
walls:
  - drum: {center: [0, 0, 0], axis: [0, 1, 0], radius: 0.03, length: 0.024, segments: 48,
           material: glass, motion: {rotation: {axis: [0, 1, 0], point: [0, 0, 0], rpm: 600}}}
  - plane: {name: lid, point: [0, 0, -0.0105], normal: [0, 0, -1], size: 0.05, material: glass,
            motion: {translation: {velocity: [0, 0, -2.0]}}}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
outputs:
  trajectories: {every: 1, directory: frames}
  probes: {every: 1, file: probes.csv, quantities: [kinetic_energy, contact_count, wall_forces]}
  vtk: {every: 10, directory: paraview, particles: points}
  checkpoint: {every: 40, keep: 5}
)";
}

// The scene written to `directory`/scene.yaml and loaded from there (checkpoints record the
// scene file and its hash).
inline talus::Scene write_restart_scene(const std::string& directory,
                                        const std::string& precision = "double") {
  std::filesystem::create_directories(directory);
  const std::string path = directory + "/scene.yaml";
  std::ofstream(path) << restart_scene_yaml(precision);
  return talus::load_scene(path);
}

// The same time (bits), step count, arrays (bits), ids and history stores (keys and bits).
template <class Real>
void expect_same_state(const talus::StepState<Real>& a, const talus::StepState<Real>& b) {
  EXPECT_EQ(std::memcmp(&a.time, &b.time, sizeof(double)), 0);
  EXPECT_EQ(a.steps, b.steps);
  ASSERT_EQ(a.arrays.size(), b.arrays.size());
  for (std::size_t k = 0; k < a.arrays.size(); ++k) {
    EXPECT_EQ(a.arrays[k].first, b.arrays[k].first);
    ASSERT_EQ(a.arrays[k].second.size(), b.arrays[k].second.size());
    EXPECT_EQ(std::memcmp(a.arrays[k].second.data(), b.arrays[k].second.data(),
                          a.arrays[k].second.size() * sizeof(Real)),
              0)
        << a.arrays[k].first;
  }
  EXPECT_EQ(a.global_ids, b.global_ids);
  EXPECT_EQ(a.template_ids, b.template_ids);
  for (const auto& [x, y] : {std::pair{&a.pair_histories, &b.pair_histories},
                             std::pair{&a.wall_histories, &b.wall_histories}}) {
    ASSERT_EQ(x->size(), y->size());
    EXPECT_EQ(
        std::memcmp(x->data(), y->data(), x->size() * sizeof(talus::ContactHistoryData<Real>)), 0);
  }
  for (const auto& [x, y] :
       {std::pair{&a.pair_keys, &b.pair_keys}, std::pair{&a.wall_keys, &b.wall_keys}}) {
    ASSERT_EQ(x->size(), y->size());
    for (std::size_t k = 0; k < x->size(); ++k) EXPECT_TRUE(talus::key_equal((*x)[k], (*y)[k]));
  }
}

}  // namespace talus_test
