// Feeds: the count inserted follows floor(rate (t - start)) without drift, inserted particles
// keep off everything, a full region defers particles and makes the feed wait longer each time,
// and a saved and restored feeder continues bit for bit like the original, its wait included.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>

#include "solver/scene/feeder.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/wall_motion.hpp"
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

const std::string kScene = R"(time: {step: 1.0e-4, end: 0.5}
seed: 2024
materials:
  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3, friction: 0.3, restitution: 0.9}
templates:
  ball: {sphere: 0.004, material: steel}
particles:
  - random:
      template: ball
      region: {box: {min: [-0.02, -0.02, 0.04], max: [0.02, 0.02, 0.06]}}
      count: 5
  - feed:
      template: ball
      region: {box: {min: [-0.02, -0.02, 0.09], max: [0.02, 0.02, 0.1]}}
      rate: 400
      start: 0.1
      stop: 0.3
      velocity: [0, 0, -0.5]
walls:
  - drum: {center: [0, 0, 0.05], axis: [1, 0, 0], radius: 0.1, length: 0.12, material: steel,
           motion: {rotation: {axis: [1, 0, 0], point: [0, 0, 0.05], rpm: 30}}}
effects: {contact: volume}
)";

// A toy run: particles fall at their velocity each step (no contacts), the drum turns, and the
// feeder inserts at every step. Returns every particle inserted, in order.
struct ToyRun {
  const Scene& scene;
  Feeder feeder;
  std::vector<Vec3d> positions, velocities;
  std::vector<double> radii;
  std::vector<ParticleState> inserted;

  ToyRun(const Scene& s) : scene(s), feeder(s, 0) {
    for (const ParticleState& p : initial_particles(s)) add(p);
  }
  void add(const ParticleState& p) {
    positions.push_back(p.position);
    velocities.push_back(p.velocity);
    radii.push_back(scene.templates[p.template_index].bounding_radius);
  }
  void step(long long n) {
    const double t = n * scene.time_step;
    std::vector<TriangleMesh> walls;
    for (std::size_t w = 0; w < scene.walls.size(); ++w)
      walls.push_back(transformed(make_wall_mesh(scene.walls[w]).mesh,
                                  wall_transform(scene.walls[w].motion, t)));
    for (const ParticleState& p : feeder.insert(t, positions, radii, walls)) {
      add(p);
      inserted.push_back(p);
    }
    for (std::size_t i = 0; i < positions.size(); ++i)
      positions[i] += velocities[i] * scene.time_step;
  }
};

bool same_bits(const ParticleState& a, const ParticleState& b) {
  return std::memcmp(&a.position, &b.position, sizeof a.position) == 0 &&
         std::memcmp(&a.orientation, &b.orientation, sizeof a.orientation) == 0;
}

TEST(Feeder, CountFollowsTheRateWithoutDrift) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  ToyRun run(scene);
  const FeedRequest& feed = scene.feeds[0];
  for (long long n = 0; n <= 5000; ++n) {  // to t = 0.5 s, past stop
    run.step(n);
    const double t = n * scene.time_step;
    const long long expected =
        t > feed.start ? (long long)std::floor(feed.rate * (std::min(t, feed.stop) - feed.start))
                       : 0;
    ASSERT_EQ(run.feeder.inserted(), expected) << "step " << n;
  }
  // 400 per second for 0.2 s: 80, up to the one the round-off of 0.3 - 0.1 may take away.
  EXPECT_GE(run.feeder.inserted(), 79);
  EXPECT_LE(run.feeder.inserted(), 80);
  EXPECT_TRUE(run.feeder.finished());
  for (const ParticleState& p : run.inserted) {
    EXPECT_EQ(p.velocity.z, -0.5);
    EXPECT_NEAR(p.orientation.norm(), 1, 1e-15);  // one normalisation
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(p.position[k] - 0.004, feed.region.box_min[k]);
      EXPECT_LE(p.position[k] + 0.004, feed.region.box_max[k]);
    }
  }
}

TEST(Feeder, InsertedParticlesKeepOffParticlesAndWalls) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  Feeder feeder(scene, 0);
  // Given spheres in and around the region, and a wall triangle cutting a wedge of it (y < -5 mm
  // near x = 0): five balls (centres 8 mm apart in a 32 x 32 mm patch) still find room.
  PlacementRandom random(9);
  std::vector<Vec3d> positions;
  std::vector<double> radii;
  for (int i = 0; i < 12; ++i) {
    positions.push_back(
        {random.uniform(-0.03, 0.03), random.uniform(-0.03, 0.03), random.uniform(0.08, 0.11)});
    radii.push_back(random.uniform(0.001, 0.003));
  }
  TriangleMesh wall;
  wall.vertices = {{-0.1, -0.1, 0.095}, {0.1, -0.1, 0.095}, {0.0, -0.005, 0.095}};
  wall.triangles = {{0, 1, 2}};
  // 400 (0.113 - 0.1) = 5.2 floors to 5, far from round-off trouble.
  const std::vector<ParticleState> added = feeder.insert(0.113, positions, radii, {wall});
  ASSERT_EQ(added.size(), 5u);
  for (std::size_t i = 0; i < added.size(); ++i) {
    const Vec3d& p = added[i].position;
    for (std::size_t j = 0; j < positions.size(); ++j)
      EXPECT_GE(norm(p - positions[j]), 0.004 + radii[j]);
    for (std::size_t j = 0; j < i; ++j) EXPECT_GE(norm(p - added[j].position), 0.008);
    EXPECT_GE(point_triangle_distance2(p, wall.vertices[0], wall.vertices[1], wall.vertices[2]),
              0.004 * 0.004);
  }
}

// A full region defers the due particles, and the feed waits before it tries again
// (kFeedMaxWaitSteps): 2 steps after the first call that placed none, then 4, 8, 16, 32 and 32; a
// call while it waits places nothing, even into a free region. The first try after the wait
// brings the whole backlog, and then the feed waits for nothing: it is ready at the next step a
// particle falls due (25 steps apart at 400 a second), sooner than the last wait.
TEST(Feeder, AFullRegionDefersParticlesAndWaitsLongerEachTime) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  const double dt = scene.time_step;
  Feeder feeder(scene, 0);
  // One big sphere covers the whole region: nothing can go in.
  const std::vector<Vec3d> blocked = {{0, 0, 0.095}};
  double t = 0.113;
  EXPECT_TRUE(feeder.insert(t, blocked, {0.05}, {}).empty());
  EXPECT_EQ(feeder.inserted(), 0);
  EXPECT_EQ(feeder.due(t), 5);  // floor(400 * 0.013), still owed
  for (const int wait : {2, 4, 8, 16, 32, 32}) {
    EXPECT_FALSE(feeder.ready(t + (wait - 1) * dt)) << wait;
    EXPECT_TRUE(feeder.insert(t + (wait - 1) * dt, {}, {}, {}).empty()) << wait;
    t += wait * dt;
    EXPECT_TRUE(feeder.ready(t)) << wait;
    EXPECT_TRUE(feeder.insert(t, blocked, {0.05}, {}).empty()) << wait;
  }
  t += 32 * dt;
  const long long owed = feeder.due(t);
  EXPECT_EQ(owed, 10);  // floor(400 (0.113 + 126 dt - 0.1)) = floor(10.24)
  EXPECT_EQ(static_cast<long long>(feeder.insert(t, {}, {}, {}).size()), owed);
  EXPECT_EQ(feeder.inserted(), owed);
  int next = 1;
  while (feeder.due(t + next * dt) == owed) ++next;
  ASSERT_LT(next, 32);
  EXPECT_FALSE(feeder.ready(t + (next - 1) * dt));  // nothing due
  EXPECT_TRUE(feeder.ready(t + next * dt));
}

// A waiting feed's wait is part of its saved state; a state saved before the waits (v1) restores
// with none.
TEST(Feeder, RestoredFeederKeepsItsWait) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  const double dt = scene.time_step;
  Feeder waiting(scene, 0);
  EXPECT_TRUE(waiting.insert(0.113, {{0, 0, 0.095}}, {0.05}, {}).empty());
  Feeder restored(scene, 0);
  restored.restore(waiting.save());
  EXPECT_EQ(restored.save(), waiting.save());
  EXPECT_FALSE(restored.ready(0.113 + dt));
  EXPECT_TRUE(restored.ready(0.113 + 2 * dt));
  // The same state as talus wrote it before the waits: the count, then the generator.
  const std::string saved = waiting.save();
  std::istringstream fields(saved);
  std::string tag, inserted, wait, next;
  fields >> tag >> inserted >> wait >> next;
  std::string engine;
  std::getline(fields, engine);
  Feeder old(scene, 0);
  old.restore("talus-feeder-v1 " + inserted + engine);
  EXPECT_EQ(old.inserted(), 0);
  EXPECT_TRUE(old.ready(0.113 + dt));
}

// A caller whose walls stand still keeps the walls' placement grid (Feeding does, for a silo's
// feed due at most steps): inserting with it places the same particles, to the bit, as cutting
// the walls into a new grid at each call. The drum at t = 0 and a triangle across the region.
TEST(Feeder, WallsGivenAsAGridPlaceTheSameBits) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  std::vector<TriangleMesh> walls = {make_wall_mesh(scene.walls[0]).mesh, TriangleMesh()};
  walls[1].vertices = {{-0.1, -0.1, 0.095}, {0.1, -0.1, 0.095}, {0.0, -0.005, 0.095}};
  walls[1].triangles = {{0, 1, 2}};
  Feeder cut(scene, 0), kept(scene, 0);
  const PlacementGrid grid = kept.walls_grid(walls);
  std::vector<Vec3d> positions = {{0.01, 0.01, 0.095}, {-0.012, 0.0, 0.092}};
  std::vector<double> radii = {0.006, 0.003};
  long long placed = 0;
  for (long long n = 1000; n < 3500; ++n) {  // t = 0.1 to 0.35: the whole feed, and past it
    const double t = n * scene.time_step;
    const std::vector<ParticleState> a = cut.insert(t, positions, radii, walls);
    const std::vector<ParticleState> b = kept.insert(t, positions, radii, grid);
    ASSERT_EQ(a.size(), b.size()) << "step " << n;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_TRUE(same_bits(a[i], b[i])) << "step " << n;
      positions.push_back(a[i].position);
      radii.push_back(0.004);
    }
    placed += static_cast<long long>(a.size());
    for (Vec3d& p : positions) p.z -= 5e-5;  // 0.5 m/s, as the feed throws them
  }
  EXPECT_GE(placed, 79);  // the feed's count: the grid changed no particle's fate
  EXPECT_EQ(cut.inserted(), kept.inserted());
  // A grid of another box cannot lend its triangles.
  PlacementGrid other(Vec3d(0, 0, 0), Vec3d(1, 1, 1), 0.004, 0);
  EXPECT_THROW(other.take_triangles_of(grid), std::invalid_argument);
}

TEST(Feeder, RestoredFeederContinuesIdentically) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  ToyRun original(scene);
  for (long long n = 0; n < 1500; ++n) original.step(n);
  const std::string saved = original.feeder.save();
  ASSERT_GT(original.feeder.inserted(), 0);

  // A second run restarts from the saved state with the same particles, then both go on.
  ToyRun restarted(scene);
  restarted.positions = original.positions;
  restarted.velocities = original.velocities;
  restarted.radii = original.radii;
  restarted.feeder.restore(saved);
  EXPECT_EQ(restarted.feeder.inserted(), original.feeder.inserted());
  EXPECT_EQ(restarted.feeder.save(), saved);
  const std::size_t before = original.inserted.size();
  for (long long n = 1500; n < 3500; ++n) {
    original.step(n);
    restarted.step(n);
  }
  ASSERT_EQ(restarted.inserted.size(), original.inserted.size() - before);
  ASSERT_GT(restarted.inserted.size(), 0u);
  for (std::size_t i = 0; i < restarted.inserted.size(); ++i)
    EXPECT_TRUE(same_bits(restarted.inserted[i], original.inserted[before + i])) << i;
  // The restored feeder went on from its saved generator, not from the seed again.
  EXPECT_FALSE(same_bits(restarted.inserted[0], original.inserted[0]));
}

TEST(Feeder, RestoreRejectsWhatIsNotASavedState) {
  const Scene scene = parse_scene(kScene, "feed.yaml", scene_data_dir());
  Feeder feeder(scene, 0);
  for (const std::string bad : {"", "talus-feeder-v1 3", "something else", "talus-feeder-v1 -1 5",
                                "talus-feeder-v2 3 40 0 5", "talus-feeder-v2 3"})
    try {
      feeder.restore(bad);
      ADD_FAILURE() << "no error for '" << bad << "'";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("feed.yaml:13:7: particles[1].feed: expected a saved "
                                            "feed state",
                                            0),
                0u)
          << e.what();
    }
}

}  // namespace
}  // namespace talus
