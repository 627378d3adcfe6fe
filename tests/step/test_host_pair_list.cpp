// The host step's pair list (solver/step/host/contact_stage.hpp): a Verlet list with the CUDA
// step's rule (bounding spheres within r_a + r_b + skin, kept until some particle has moved 0.45
// skin since the build, rebuilt when the particles change). Kept across steps, it is built far
// fewer times than the scene steps, within the bounds its rule sets, and the run is the same to
// the bit as one with the list rebuilt every step (skin 0): settling, fed and removing scenes. A
// run with `reorder` (renumbered at each build) resumed from a checkpoint between two builds
// builds, renumbers and ends as the uninterrupted run does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/run/any_step.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/step/step_test_util.hpp"
#include "tests/support/domain_scenes.hpp"
#include "tests/support/feed_scenes.hpp"

namespace talus {
namespace {

using talus::testing::pour_scene;
using talus_test::scene_from;
using talus_test::StepTempDir;

// The first particle whose position or velocity differs in any bit between the two steps
// (same particle order), or -1.
int first_difference(const HostStep<double>& a, const HostStep<double>& b) {
  if (a.particle_count() != b.particle_count()) return 0;
  const ParticleView<double>& p = a.particles();
  const ParticleView<double>& q = b.particles();
  for (int i = 0; i < a.particle_count(); ++i) {
    const Vec3d xa = p.position.get(i), xb = q.position.get(i);
    const Vec3d va = p.velocity.get(i), vb = q.velocity.get(i);
    if (p.global_id[i] != q.global_id[i] || std::memcmp(&xa, &xb, sizeof xa) != 0 ||
        std::memcmp(&va, &vb, sizeof va) != 0)
      return i;
  }
  return -1;
}

struct ListRun {
  long long steps = 0;
  long long builds = 0;
  long long contacts = 0;         // touching pairs summed over the steps
  long long skin_only_steps = 0;  // steps where the list held pairs a list without skin lacks
  double largest_step_move = 0;   // m: the most any particle moved in one step
  double largest_total_move = 0;  // m: the farthest any particle got from its start
};

// `scene` stepped `steps` times with its skin beside the same scene with skin 0 (the list rebuilt
// at every evaluation: the host's broad phase before the list), both on `threads` threads; every
// step's positions and velocities compared to the bit, and the final states (every array, the
// history stores).
ListRun run_beside_skin_zero(Scene scene, long long steps, int threads) {
  Scene no_skin = scene;
  no_skin.skin = 0.0;
  HostStep<double> kept(scene, threads), rebuilt(no_skin, threads);
  ListRun r;
  std::vector<Vec3d> start, before;
  for (const TrajectoryRow& row : kept.trajectory_rows()) start.push_back(row.position);
  for (long long k = 0; k < steps; ++k) {
    before.clear();
    for (const TrajectoryRow& row : kept.trajectory_rows()) before.push_back(row.position);
    kept.step();
    rebuilt.step();
    const int at = first_difference(kept, rebuilt);
    if (at >= 0) {
      ADD_FAILURE() << "step " << k + 1 << ": particle " << at << " differs";
      return r;
    }
    EXPECT_EQ(kept.pair_contact_count(), rebuilt.pair_contact_count());
    r.contacts += static_cast<long long>(kept.pair_contact_count());
    if (kept.candidate_pair_count() > rebuilt.candidate_pair_count()) ++r.skin_only_steps;
    // The rows are in global-id order; a particle set that changed is not measured (feeds).
    const std::vector<TrajectoryRow> rows = kept.trajectory_rows();
    if (rows.size() == before.size() && rows.size() == start.size()) {
      for (std::size_t i = 0; i < rows.size(); ++i) {
        r.largest_step_move = std::max(r.largest_step_move, norm(rows[i].position - before[i]));
        r.largest_total_move = std::max(r.largest_total_move, norm(rows[i].position - start[i]));
      }
    }
  }
  // Skin 0: a build at every evaluation, the first (F_0) and one per step.
  EXPECT_EQ(rebuilt.pair_list_builds(), steps + 1);
  talus_test::expect_same_state(kept.export_state(), rebuilt.export_state());
  r.steps = steps;
  r.builds = kept.pair_list_builds();
  return r;
}

// 24 dodecahedra of 10 mm poured into an open box (tests/support/domain_scenes.hpp) with a skin of
// 1 mm (the default, a tenth of the bounding diameter, given exactly): they fall up to 3 cm, land
// and settle on each other, 0.3 s in 7,124 steps of the advisor's time step.
TEST(HostPairList, SettlingSceneBuildsItsListFarLessOftenThanItStepsWithTheSameBits) {
  Scene scene = scene_from(pour_scene(false, false, false, 0.3));
  const double skin = 0.001;
  scene.skin = skin;
  const long long steps = std::llround(scene.end_time / scene.time_step);
  const ListRun r = run_beside_skin_zero(scene, steps, 2);
  ASSERT_EQ(r.steps, steps);
  // The comparison saw contacts (a bed of two dozen polyhedra touches at a few tens of pairs;
  // measured: 14.7 a step on average, the fall included) and a list holding pairs beyond the
  // bounding spheres, which the evaluation must leave out, at most steps.
  EXPECT_GT(r.contacts, 5 * steps);
  EXPECT_GT(r.skin_only_steps, steps / 2);
  // The rule's bounds, from the motion measured (the particles do not change, so only motion
  // rebuilds). After the first build (at t = 0), each build needs some particle to have moved
  // more than 0.45 skin since the last one, at most largest_step_move a step: at most
  // steps * largest_step_move / (0.45 skin) builds. And the list is tested at every step, so a
  // particle moves at most 0.45 skin + largest_step_move from one build's reference to the next's
  // and at most 0.45 skin after the last: the one that got farthest needs at least
  // (largest_total_move - 0.45 skin) / (0.45 skin + largest_step_move) builds after the first.
  const double per_list = 0.45 * skin;
  EXPECT_LE(r.builds - 1, static_cast<double>(steps) * r.largest_step_move / per_list);
  EXPECT_GE(r.builds - 1, (r.largest_total_move - per_list) / (per_list + r.largest_step_move));
  EXPECT_GE(r.builds, 3);  // the bed moved by several skins: the list expired and was rebuilt
  // Far fewer than the steps (measured: 111 builds).
  EXPECT_LT(r.builds * 20, steps) << r.builds << " builds";

  // The runner's view of the step (AnyStep) counts the same builds.
  std::unique_ptr<AnyStep> any = make_host_step(scene, 1);
  for (long long k = 0; k < steps; ++k) any->step();
  EXPECT_EQ(any->pair_list_builds(), r.builds);
}

// A feed (balls inserted one by one, tests/step/test_restart.cpp's feeding scene, shorter): each
// insertion rebuilds the list, whose new particles have no candidates yet.
TEST(HostPairList, FedSceneKeepsTheSameBitsAsRebuildingEveryStep) {
  const Scene scene = scene_from(talus::testing::thrown_feed_scene("0.02"));
  const long long steps = std::llround(scene.end_time / scene.time_step);
  const ListRun r = run_beside_skin_zero(scene, steps, 1);
  EXPECT_GT(r.contacts, 0);
  // 20 insertions, each a build at the next evaluation, and builds for the motion besides; far
  // fewer than the 4000 steps.
  EXPECT_GE(r.builds, 20);
  EXPECT_LT(r.builds * 10, steps) << r.builds << " builds";
}

// The domain box removes the 8 dodecahedra thrown down beside the box (ids 0-7) between 9 and
// 18 ms, which moves the others to lower indices; the list is rebuilt over them. The pour beside
// lands and settles in the 0.1 s.
TEST(HostPairList, RemovalKeepsTheSameBitsAsRebuildingEveryStep) {
  const Scene scene = scene_from(pour_scene(true, true, false, 0.1));
  const long long steps = std::llround(scene.end_time / scene.time_step);
  const ListRun r = run_beside_skin_zero(scene, steps, 2);
  EXPECT_GT(r.contacts, steps);
  // The thrown dodecahedra (2 m/s and faster, 0.1 mm a step) expire the list every few steps
  // until they leave, about 400 steps; the pour little after it lands. Measured: 140 builds.
  EXPECT_LT(r.builds * 10, steps) << r.builds << " builds";
}

// A run with `reorder` renumbers the particles at each build of the list, so when it builds
// matters to the bits. A checkpoint written between two builds carries the list's reference (the
// positions at the last build); the resumed step builds the uninterrupted run's list from it,
// and so builds and renumbers at the same steps, with the same candidates, and ends the same.
TEST(HostPairList, RunResumedBetweenTwoBuildsBuildsAndRenumbersAsTheUninterruptedOne) {
  StepTempDir dir;
  const Scene scene = scene_from(pour_scene(false, false, true, 0.04));
  const long long steps = std::llround(scene.end_time / scene.time_step);
  HostStep<double> whole(scene, 1);
  std::vector<long long> builds{0};  // after each step (0: before the first)
  std::vector<std::size_t> candidates{0};
  for (long long k = 0; k < steps; ++k) {
    whole.step();
    builds.push_back(whole.pair_list_builds());
    candidates.push_back(whole.candidate_pair_count());
  }
  // The checkpoint after step `cut`: the first from a third of the run on where neither step
  // `cut` nor step `cut` + 1 built the list.
  long long cut = steps / 3;
  while (cut + 1 < steps && !(builds[cut] == builds[cut - 1] && builds[cut + 1] == builds[cut]))
    ++cut;
  ASSERT_LT(cut + 1, steps);
  ASSERT_GE(builds[steps] - builds[cut], 2) << "the list should be built again after the cut";

  HostStep<double> first(scene, 2);
  for (long long k = 0; k < cut; ++k) first.step();
  const StepState<double> state = first.export_state();
  ASSERT_EQ(state.list_reference.size(), 3u * static_cast<std::size_t>(state.count));
  EXPECT_FALSE(state.list_stale);
  Checkpoint written;
  put_step_state(written, state);
  const std::string path = dir.path() + "/state.bin";
  write_checkpoint(path, written);
  HostStep<double> second(scene, 2);
  second.import_state(get_step_state<double>(read_checkpoint(path)));
  EXPECT_EQ(second.pair_list_builds(), 0);
  for (long long k = cut; k < steps; ++k) {
    second.step();
    // One build more than the uninterrupted run's since the cut: the list made again from the
    // reference at the first evaluation; then the same builds at the same steps, the same list.
    ASSERT_EQ(second.pair_list_builds(), 1 + builds[k + 1] - builds[cut]) << "step " << k + 1;
    ASSERT_EQ(second.candidate_pair_count(), candidates[k + 1]) << "step " << k + 1;
  }
  const StepState<double> a = whole.export_state(), b = second.export_state();
  // The renumbering ran: the particles are no longer in the order of their ids.
  EXPECT_FALSE(std::is_sorted(a.global_ids.begin(), a.global_ids.end()));
  EXPECT_GT(a.pair_keys.size(), 0u);
  talus_test::expect_same_state(a, b);
  EXPECT_EQ(a.list_reference, b.list_reference);
}

}  // namespace
}  // namespace talus
