// Graph steps (solver/step/cuda/cuda_step_impl.cuh, "Graph steps"): a step launched as one captured
// CUDA graph computes the same bits as the same step launched stage by stage
// (CudaStepOptions::graphs false). Each scene is run both ways side by side in deterministic mode
// and every particle's position, velocity, orientation and angular velocity compared bit for bit
// at every step, with the pair and wall contact counts; the graph run must actually have taken
// graph steps (a test of the comparison, not only of its result). Skipped with the reason where
// no GPU is usable.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "solver/core/cuda_device.hpp"
#include "solver/scene/builtin_scene.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/cuda/cuda_step.hpp"
#include "tests/support/domain_scenes.hpp"
#include "tests/support/feed_scenes.hpp"
#include "tests/support/gpu_skip.hpp"
#include "tests/support/walled_scene.hpp"

namespace talus {
namespace {

long long max_steps() {
  const char* cap = std::getenv("TALUS_GPU_TEST_MAX_STEPS");
  return cap ? std::atoll(cap) : -1;
}

struct Comparison {
  long long steps = 0, differing = 0, contact_steps = 0, final_count = 0;
  CudaGraphCounts graphs;
};

bool same_bits(const TrajectoryRow& a, const TrajectoryRow& b) {
  return std::memcmp(&a.position, &b.position, sizeof(Vec3d)) == 0 &&
         std::memcmp(&a.velocity, &b.velocity, sizeof(Vec3d)) == 0 &&
         std::memcmp(&a.orientation, &b.orientation, sizeof(Quatd)) == 0 &&
         std::memcmp(&a.angular_velocity, &b.angular_velocity, sizeof(Vec3d)) == 0;
}

// `steps` steps (capped by TALUS_GPU_TEST_MAX_STEPS) of the scene with graph steps and without.
Comparison compare(const Scene& scene, long long steps) {
  if (max_steps() > 0) steps = std::min(steps, max_steps());
  CudaStepOptions staged;
  staged.graphs = false;
  CudaStep<double> graph(scene), stage_by_stage(scene, staged);
  Comparison c;
  for (long long k = 0; k < steps; ++k) {
    graph.step();
    stage_by_stage.step();
    ++c.steps;
    const std::vector<TrajectoryRow> g = graph.trajectory_rows();
    const std::vector<TrajectoryRow> s = stage_by_stage.trajectory_rows();
    bool same = g.size() == s.size() &&
                graph.pair_contact_count() == stage_by_stage.pair_contact_count() &&
                graph.wall_contact_count() == stage_by_stage.wall_contact_count();
    for (std::size_t i = 0; same && i < g.size(); ++i) same = same_bits(g[i], s[i]);
    c.differing += same ? 0 : 1;
    c.contact_steps += graph.pair_contact_count() + graph.wall_contact_count() > 0 ? 1 : 0;
  }
  c.graphs = graph.graph_counts();
  c.final_count = static_cast<long long>(graph.trajectory_rows().size());
  EXPECT_EQ(stage_by_stage.graph_counts().steps, 0);
  // A capture is updated into the executable graph only when its nodes are the same
  // (graph_node_signature), which the driver then accepts: a refusal is an API error that
  // compute-sanitizer reports (cudaErrorGraphExecUpdateFailure, seen in FeedGpu before the
  // signature). Every capture is either an update or a new executable graph.
  EXPECT_EQ(c.graphs.refused_updates, 0);
  EXPECT_GE(c.graphs.instantiations, c.graphs.captures > 0 ? 1 : 0);
  EXPECT_LE(c.graphs.instantiations, c.graphs.captures);
  std::printf(
      "steps %lld  differing %lld  contact steps %lld  graph steps %lld  captures %lld  "
      "instantiated %lld  refused updates %lld  aborted %lld  list builds %lld\n",
      c.steps, c.differing, c.contact_steps, c.graphs.steps, c.graphs.captures,
      c.graphs.instantiations, c.graphs.refused_updates, c.graphs.aborted,
      graph.pair_list_builds());
  return c;
}

// The built-in scene (the §3.3 pour: dodecahedra into a 64-segment cylinder): pair and wall
// contacts, the volume model's phased pair stage, a static curved wall. Most steps keep the list
// (it is rebuilt a few dozen times in 2,000 steps), and each such step is a graph step: at least
// half of them is far below what the skin allows and far above none.
TEST(GpuGraphStep, BuiltinSceneGivesTheSameBits) {
  SKIP_WITHOUT_GPU();
  const Scene scene = parse_scene(builtin_scene_text(), "builtin.yaml", ".");
  const Comparison c = compare(scene, 2000);
  EXPECT_EQ(c.differing, 0);
  EXPECT_GT(c.graphs.steps, c.steps / 2);
  if (max_steps() <= 0) EXPECT_GT(c.contact_steps, 0);
}

// Moving walls placed on the device from each launch's placements (a drum turning at 3000 rpm,
// a translating plate) and a hopper whose outlet opens at step 50 (its present facets change
// under a captured graph), with friction: the wall stage's history store kept by the graph.
TEST(GpuGraphStep, MovingWallsAndAnOpeningOutletGiveTheSameBits) {
  SKIP_WITHOUT_GPU();
  const Comparison c =
      compare(talus_test::walled_scene("double", "volume", {"cube", "ico"}, 400), 200);
  EXPECT_EQ(c.differing, 0);
  EXPECT_GT(c.graphs.steps, 0);
}

// Twenty cubes in two rows above the bottom of a fine static drum (2,000 segments) fall onto it
// together: the facets within their bounding spheres grow from none to some three thousand over
// a hundred steps, mostly while the list is kept, past the wall stage's room (at first 1,024
// facets, then twice what a stage-by-stage step found). A graph step that
// overruns it aborts after the pair stage and finishes stage by stage with more room: the same
// bits, and at least one such step (else this test would not test it).
TEST(GpuGraphStep, OverrunWallRoomFinishesStageByStage) {
  SKIP_WITHOUT_GPU();
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << R"(time: {step: 1.0e-5, end: 1.0e-2}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  cube: {shape: "cube:0.008", material: glass}
walls:
  - drum: {center: [0, 0, 0], axis: [0, 1, 0], radius: 0.04, length: 0.1, segments: 2000,
           material: glass}
particles:
  - explicit:
)";
  // Two rows of cubes, each cube's bounding sphere (6.9 mm) 0.6 mm above the bottom, falling at
  // 2 m/s: they reach it after some 30 steps and land after some 175.
  for (const double x : {-0.0045, 0.0045}) {
    const double bottom = -std::sqrt(0.04 * 0.04 - x * x);
    for (int k = 0; k < 10; ++k) {
      yaml << "      - {template: cube, position: [" << x << ", " << -0.045 + 0.01 * k << ", "
           << bottom + 0.0075 << "], velocity: [0, 0, -2]}\n";
    }
  }
  yaml << "effects:\n  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n"
          "  rotation: true\n";
  const Scene scene = parse_scene(yaml.str(), "row.yaml", ".");
  const Comparison c = compare(scene, 400);
  EXPECT_EQ(c.differing, 0);
  if (max_steps() <= 0) {
    EXPECT_GT(c.graphs.aborted, 0);
    EXPECT_GT(c.contact_steps, 0);
  }
}

// A feed into a box inside a domain box: the removal's buffers (flag_outside) are grown before a
// capture, never in it, at the first capture and after each feed has added particles (until
// this test, every scene with a domain box ran stage by stage: its first capture allocated and
// failed). One ball, then one more every 100 steps of 5 us for 10 ms: the feed's steps and the
// list's rebuilds run stage by stage, the steps between them (more than half of 2,000) as graphs.
TEST(GpuGraphStep, FedSceneInADomainGivesTheSameBits) {
  SKIP_WITHOUT_GPU();
  const std::string yaml =
      std::string("time: {step: 5.0e-6, end: 0.02}\n") +
      "materials:\n  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, "
      "friction: 0.4, restitution: 0.5}\n" +
      testing::kBallFeedScene + "domain: {min: [-0.03, -0.03, -0.01], max: [0.03, 0.03, 0.05]}\n";
  const Comparison c = compare(parse_scene(yaml, "fed.yaml", "."), 2000);
  EXPECT_EQ(c.differing, 0);
  EXPECT_GT(c.graphs.steps, c.steps / 2);
}

// Particles leave the domain box under graph steps: group B of tests/support/domain_scenes.hpp's
// pour (8 dodecahedra thrown down beside the box) falls out of it between 10 and 18 ms and is
// removed after the graph step that flagged it, as stage by stage: the same bits at every step,
// graph steps taken, and 20 ms on the same 24 particles left (DomainGpu.RemovalMatchesTheHost:
// the rain is gone by 18 ms; at 15 ms four of it were still falling).
TEST(GpuGraphStep, RemovalFromADomainGivesTheSameBits) {
  SKIP_WITHOUT_GPU();
  const Scene scene = parse_scene(testing::pour_scene(true, true, false), "pour.yaml", ".");
  const long long steps = static_cast<long long>(std::ceil(0.02 / scene.time_step));
  const Comparison c = compare(scene, steps);
  EXPECT_EQ(c.differing, 0);
  EXPECT_GT(c.graphs.steps, 0);
  if (max_steps() <= 0) EXPECT_EQ(c.final_count, 24);
}

// A box shaken up and down (`motion: oscillation`) under graph steps: the wall's velocity changes
// every step, and a graph launch copies it up from the pinned copy the host refreshed (as the
// placements), so each graph step reads its own time's velocity: the same bits as stage by
// stage, most steps graphs. Two cubes ("cube:0.01": circumscribed diameter 10 mm, so a side of
// 5.77 mm, the centre 2.887 mm above a face) start 13 µm above the floor, land on it at step 782
// (1.56 ms) and ride it (0.08 mm at 50 Hz: 0.8 g at most, so they hop a little): on the host,
// the same scene's wall force is non-zero at 3,225 of the 5,000 steps, hence more than 1,000.
// (Placed at 5.01 mm, as first written, they fell 2.1 mm and met nothing in 10 ms.)
TEST(GpuGraphStep, ShakenBoxGivesTheSameBits) {
  SKIP_WITHOUT_GPU();
  const Scene scene = parse_scene(R"(time: {step: 2.0e-6, end: 1.0e-2}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  cube: {shape: "cube:0.01", material: glass}
particles:
  - explicit:
      - {template: cube, position: [-0.006, 0.001, 0.0029],
         orientation: {axis: [0, 0, 1], degrees: 20}}
      - {template: cube, position: [0.007, -0.002, 0.0029]}
walls:
  - box:
      min: [-0.015, -0.015, 0]
      max: [0.015, 0.015, 0.03]
      open_top: true
      material: glass
      motion:
        oscillation: {direction: [0, 0, 1], amplitude: 0.00008, frequency: 50, start: 0.001}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
)",
                                  "shaken.yaml", ".");
  const Comparison c = compare(scene, 5000);
  EXPECT_EQ(c.differing, 0);
  EXPECT_GT(c.graphs.steps, c.steps / 2);
  if (max_steps() <= 0) EXPECT_GT(c.contact_steps, 1000);
}

}  // namespace
}  // namespace talus
