// The step assembled from the scene's effects: an absent effect has no stage and no array.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "solver/step/host/host_step.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

using talus_test::scene_from;

const char* const kHead = R"(time: {step: 1.0e-4, end: 1.0e-3}
materials:
  stone: {density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.5,
          restitution: 0.5}
templates:
  ball: {sphere: 0.05, material: stone}
  cube: {shape: "cube:0.1", material: stone}
particles:
  - explicit:
      - {template: ball, position: [0, 0, 0]}
      - {template: cube, position: [1, 0, 0]}
)";

bool has_array(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::vector<std::string> stage_names(const StepPlan& plan) {
  std::vector<std::string> names;
  for (const Stage s : plan.stages) names.push_back(to_string(s));
  return names;
}

// No effect at all: the particles coast; no force, no torque, no angular velocity, no broad phase.
TEST(StepPlan, NoEffectsMeansOnlyTheIntegrator) {
  const Scene scene = scene_from(std::string(kHead) + "effects: {}\n");
  HostStep<double> step(scene);
  EXPECT_EQ(stage_names(step.plan()),
            (std::vector<std::string>{"integrate_begin", "integrate_end"}));
  const std::vector<std::string> arrays = step.allocated_arrays();
  EXPECT_FALSE(has_array(arrays, "force.x"));
  EXPECT_FALSE(has_array(arrays, "angular_velocity.x"));
  EXPECT_FALSE(has_array(arrays, "torque.x"));
  EXPECT_FALSE(has_array(arrays, "bounding_radius"));
  EXPECT_TRUE(has_array(arrays, "position.z"));
  EXPECT_TRUE(has_array(arrays, "global_id"));
  // 2 particles x (3 position + 3 velocity + 4 orientation) doubles + 2 ints and a long long.
  EXPECT_EQ(step.allocated_bytes(), 2u * (10 * sizeof(double) + 2 * sizeof(int) + 8));
  EXPECT_EQ(step.particles().force.x, nullptr);
}

// Gravity and drag: their stages and the force arrays, nothing of contacts or rotation.
TEST(StepPlan, GravityAndDragAddTheirStagesAndTheForceArrays) {
  const Scene scene =
      scene_from(std::string(kHead) + "effects: {gravity: [0, 0, -9.81], drag: {alpha: 0.5}}\n");
  HostStep<double> step(scene);
  EXPECT_EQ(stage_names(step.plan()),
            (std::vector<std::string>{"integrate_begin", "clear_forces", "gravity", "drag",
                                      "integrate_end"}));
  const std::vector<std::string> arrays = step.allocated_arrays();
  EXPECT_TRUE(has_array(arrays, "force.x"));
  EXPECT_TRUE(has_array(arrays, "step_start_acceleration.z"));
  EXPECT_FALSE(has_array(arrays, "torque.x"));
  EXPECT_FALSE(has_array(arrays, "angular_velocity.x"));
  EXPECT_FALSE(has_array(arrays, "bounding_radius"));
  EXPECT_EQ(step.particles().torque.x, nullptr);
}

// Contacts with rotation: the broad phase, the pair stage and the accumulation, the torques and
// the bounding radii. Without rotation the torque arrays stay absent.
TEST(StepPlan, ContactsAndRotationAddPairStagesAndTorques) {
  const Scene rotating = scene_from(std::string(kHead) +
                                    "effects: {contact: {model: linear, stiffness: 1.0e4, "
                                    "damping: 0}, rotation: true}\n");
  HostStep<double> step(rotating);
  EXPECT_EQ(stage_names(step.plan()),
            (std::vector<std::string>{"integrate_begin", "clear_forces", "candidate_pairs",
                                      "pair_contacts", "accumulate", "integrate_end"}));
  const std::vector<std::string> arrays = step.allocated_arrays();
  EXPECT_TRUE(has_array(arrays, "torque.x"));
  EXPECT_TRUE(has_array(arrays, "angular_velocity.x"));
  EXPECT_TRUE(has_array(arrays, "bounding_radius"));

  const Scene sliding = scene_from(std::string(kHead) +
                                   "effects: {contact: {model: linear, stiffness: 1.0e4, "
                                   "damping: 0}}\n");
  HostStep<double> no_rotation(sliding);
  EXPECT_FALSE(has_array(no_rotation.allocated_arrays(), "torque.x"));
  EXPECT_FALSE(has_array(no_rotation.allocated_arrays(), "angular_velocity.x"));
}

// Walls act through contacts (the loader refuses walls without a contact model): the wall stage
// runs after the pair stage and before the accumulation.
TEST(StepPlan, WallStageRunsAfterThePairs) {
  const std::string walls =
      "walls:\n  - plane: {point: [0, 0, -1], normal: [0, 0, 1], size: 4, material: stone}\n";
  const Scene touching = scene_from(std::string(kHead) + walls +
                                    "effects: {contact: {model: linear, stiffness: 1.0e4, "
                                    "damping: 0}}\n");
  const StepPlan plan = plan_step(touching);
  ASSERT_TRUE(plan.has(Stage::wall_contacts));
  EXPECT_EQ(plan.stages[3], Stage::pair_contacts);
  EXPECT_EQ(plan.stages[4], Stage::wall_contacts);
}

// What the production step cannot do yet is refused at setup, naming the scene item.
TEST(StepPlan, VolumeModelRefusesSpheresWithPolyhedra) {
  const Scene scene = scene_from(std::string(kHead) + "effects: {contact: volume}\n");
  try {
    HostStep<double> step(scene);
    FAIL() << "expected StepNotSupported";
  } catch (const StepNotSupported& e) {
    EXPECT_NE(std::string(e.what()).find("sphere-polyhedron"), std::string::npos) << e.what();
  }
}

// A feed: the plan says so (both backends run feeds; tests/gpu/test_feed_gpu.cpp has the CUDA
// step's), and the host step's arrays grow with the inserted particles, capacity doubling.
TEST(StepPlan, FeedRunsOnTheHostStep) {
  const Scene scene =
      scene_from(std::string(kHead) +
                 "  - feed: {template: ball, region: {box: {min: [-1, -1, 1], "
                 "max: [1, 1, 2]}}, rate: 5000}\neffects: {gravity: [0, 0, -9.81]}\n");
  EXPECT_TRUE(plan_step(scene).feed);
  EXPECT_FALSE(
      plan_step(scene_from(std::string(kHead) + "effects: {gravity: [0, 0, -9.81]}\n")).feed);
  HostStep<double> step(scene, 1);
  EXPECT_TRUE(step.plan().feed);
  const std::size_t bytes = step.allocated_bytes();
  for (int k = 0; k < 10; ++k) step.step();
  // floor(5000 * 9e-4) = 4 at the last step's start, ids after the two explicit particles.
  ASSERT_EQ(step.particle_count(), 2 + 4);
  EXPECT_GT(step.allocated_bytes(), bytes);
  const std::vector<TrajectoryRow> rows = step.trajectory_rows();
  for (int i = 0; i < 6; ++i) EXPECT_EQ(rows[i].id, i);
  for (int i = 2; i < 6; ++i) {
    EXPECT_GE(rows[i].position.z, 1.0 - 0.01);  // placed in the region, then falling
    EXPECT_LT(rows[i].velocity.z, 0.0);         // under gravity from their first step
  }
}

}  // namespace
}  // namespace talus
