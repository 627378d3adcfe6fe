// The built-in scene of `talus run` with no scene (paper §3.3): the compiled-in text is the
// validation file, it loads with the paper's numbers, its plan runs the physics it names, and a
// short run starts as a free fall.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "solver/run/production_run.hpp"
#include "solver/scene/builtin_scene.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/step_plan.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

const std::string kSceneFile =
    std::string(TALUS_SOURCE_DIR) + "/validation/dodecahedron_packing/scene.yaml";

Scene builtin_scene() {
  return parse_scene(builtin_scene_text(), kBuiltinSceneFileName, ".");
}

TEST(BuiltinScene, IsTheValidationFileCompiledIn) {
  EXPECT_EQ(builtin_scene_text(), talus_test::read_text(kSceneFile));
}

TEST(BuiltinScene, HoldsThePapersPackingSetup) {
  const Scene scene = builtin_scene();
  ASSERT_EQ(scene.templates.size(), 1u);
  // A regular dodecahedron of 30 mm circumscribed diameter: bounding radius 15 mm, volume
  // 2.785 R^3 = 9.40e-6 m^3 (edge a = 0.7136 R, V = (15 + 7 sqrt 5) / 4 a^3).
  EXPECT_NEAR(scene.templates[0].bounding_radius, 0.015, 1e-12);
  EXPECT_NEAR(scene.templates[0].volume, 9.40e-6, 0.01e-6);
  ASSERT_EQ(scene.random_fills.size(), 1u);
  EXPECT_EQ(scene.random_fills[0].count, 63);  // sixty-three particles
  ASSERT_EQ(scene.walls.size(), 1u);
  const auto& cylinder = std::get<CylinderWall>(scene.walls[0].shape);
  EXPECT_EQ(cylinder.radius, 0.05);  // inner diameter 10 cm
  EXPECT_TRUE(cylinder.bottom_cap);
  // §3.3 takes §3.2's parameters (Table 2).
  const Material& m = scene.materials.at(0);
  EXPECT_EQ(m.density, 1500);
  EXPECT_EQ(m.youngs_modulus, 1e6);
  EXPECT_EQ(m.poisson_ratio, 0.1);
  EXPECT_EQ(m.restitution, 0.1);
  ASSERT_TRUE(scene.effects.gravity);
  EXPECT_EQ(scene.effects.gravity->z, -9.81);
  const StepPlan plan = plan_step(scene);
  EXPECT_TRUE(plan.gravity && plan.contacts && plan.rotation && plan.walls);
  EXPECT_TRUE(plan.has(Stage::pair_contacts));
  EXPECT_TRUE(plan.has(Stage::wall_contacts));
}

// The first 20 ms: the random fill keeps every bounding sphere off the others and off the
// walls, and all fall together, so a particle more than 5 mm above its bounding sphere's floor
// contact touches nothing (it falls 2 mm) and follows v = -g t, z = z0 - g t^2 / 2 exactly but
// for rounding: velocity Verlet is exact for a constant force, 1000 steps of additions err by
// ~1e-13.
TEST(BuiltinScene, ShortRunStartsAsAFreeFall) {
  Scene scene = builtin_scene();
  const double t = 0.02, g = 9.81;
  scene.end_time = t;
  scene.outputs = {};
  ProductionSettings settings;
  settings.host_threads = 1;
  ProductionRunner runner(scene, settings);
  const std::vector<TrajectoryRow> start = runner.rows();
  ASSERT_EQ(start.size(), 63u);
  while (!runner.done()) runner.advance();
  const std::vector<TrajectoryRow> end = runner.rows();
  int free = 0;
  for (std::size_t k = 0; k < start.size(); ++k) {
    EXPECT_LE(std::hypot(start[k].position.x, start[k].position.y), 0.05 - 0.015 + 1e-12);
    if (start[k].position.z < 0.015 + 0.005) continue;
    ++free;
    EXPECT_NEAR(end[k].velocity.z, -g * t, 1e-9) << k;
    EXPECT_NEAR(end[k].position.z, start[k].position.z - 0.5 * g * t * t, 1e-9) << k;
  }
  EXPECT_GT(free, 50);
}

}  // namespace
}  // namespace talus
