// The domain box and the renumbering by cell on the host step (host_step.hpp, domain/domain.hpp):
// particles that leave the box are removed with their energy booked (`removed`), the others go on
// exactly as they would without them, a restart continues the smaller state bit for bit, and
// renumbering the particles by cell at every build changes only the last bits: the contact
// histories follow the particles. Scenes in tests/support/domain_scenes.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/step/step_test_util.hpp"
#include "tests/support/domain_scenes.hpp"

namespace talus {
namespace {

using talus::testing::histories_by_key;
using talus::testing::pour_scene;
using talus_test::scene_from;

// Group B's 8 particles fall 25 to 36 mm at 2 m/s and more: all gone by 18 ms; none before 9 ms
// (the nearest starts 25.25 mm above the floor and moves at most 2.1 m/s by then).
constexpr double kFirstRemoval = 0.009, kLastRemoval = 0.018;

TEST(DomainStep, ParticlesLeavingTheBoxAreRemovedWithTheirEnergy) {
  const Scene with = scene_from(pour_scene(true, true, false));
  const Scene without = scene_from(pour_scene(false, false, false));
  HostStep<double> a(with, 1), b(without, 1);
  ASSERT_EQ(a.particle_count(), 32);
  ASSERT_EQ(b.particle_count(), 24);
  a.evaluate_forces();
  b.evaluate_forces();
  const double offset0 = a.energy().balance() - b.energy().balance();
  while (a.time() < kLastRemoval) {
    a.step();
    b.step();
    if (a.time() < kFirstRemoval) {
      ASSERT_EQ(a.particle_count(), 32) << "t = " << a.time();
    }
  }
  EXPECT_EQ(a.particle_count(), 24);
  EXPECT_EQ(a.removed_count(), 8);
  // The rain's ids (0-7, the lattice comes first) are gone; the pour's (8-31) remain.
  const std::vector<TrajectoryRow> rows = a.trajectory_rows();
  ASSERT_EQ(rows.size(), 24u);
  for (std::size_t k = 0; k < rows.size(); ++k)
    EXPECT_EQ(rows[k].id, 8 + static_cast<long long>(k));
  // The pour went on exactly as without the rain: it never came near it, and removal keeps the
  // others' order, so every sum is made in the same order (bit-identical, no tolerance).
  const std::vector<TrajectoryRow> alone = b.trajectory_rows();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(std::memcmp(&rows[k].position, &alone[k].position, sizeof(Vec3d)), 0) << k;
    EXPECT_EQ(std::memcmp(&rows[k].velocity, &alone[k].velocity, sizeof(Vec3d)), 0) << k;
  }
  // The rain's energy left with it: the two runs' balances differ by the rain's mechanical
  // energy at the start and at the end alike. Free fall under constant gravity is integrated
  // exactly by velocity Verlet, so the difference keeps to round-off: 1e-12 of the rain's
  // energy scale (m g h + m v^2 / 2, about 1e-3 J) covers a few hundred rounded additions.
  const double offset = a.energy().balance() - b.energy().balance();
  EXPECT_GT(a.energy().ledger.removed, 0);
  EXPECT_NEAR(offset, offset0, 1e-12 * std::abs(a.energy().ledger.removed) + 1e-15);
}

TEST(DomainStep, RestartAfterRemovalContinuesBitForBit) {
  const Scene scene = scene_from(pour_scene(true, true, false));
  HostStep<double> a(scene, 1);
  while (a.time() < kLastRemoval) a.step();
  ASSERT_EQ(a.particle_count(), 24);
  const StepState<double> saved = a.export_state();
  EXPECT_EQ(saved.next_id, 32);  // ids are never reused
  EXPECT_EQ(saved.removed, 8);
  HostStep<double> b(scene, 1);  // a fresh step of 32 particles takes the state of 24
  b.import_state(saved);
  EXPECT_EQ(b.particle_count(), 24);
  EXPECT_EQ(b.removed_count(), 8);
  for (int k = 0; k < 50; ++k) a.step(), b.step();
  talus_test::expect_same_state(a.export_state(), b.export_state());
}

TEST(DomainStep, RenumberingByCellKeepsTheHistoriesAndThePhysics) {
  // Until the pour has landed and slid for a while (3,600 steps of the advisor's 42 us): about
  // 20 touching pairs with loaded tangential springs, carried through every renumbering.
  const double end = 0.15;
  const Scene plain = scene_from(pour_scene(false, false, false, end));
  const Scene sorted = scene_from(pour_scene(false, false, true, end));
  HostStep<double> a(plain, 1), b(sorted, 1);
  while (a.time() < end - 0.5 * plain.time_step) a.step(), b.step();
  // The renumbering did happen: the particles are no longer in id order in memory.
  const StepState<double> sa = a.export_state(), sb = b.export_state();
  EXPECT_FALSE(std::is_sorted(sb.global_ids.begin(), sb.global_ids.end()));
  // The same contacts with the same springs. A pair's order (which particle is A) and the order
  // of each particle's sums change with the numbering, so the last bits do; over this pour those
  // differences grow to about 2e-13 of the largest spring force (measured), so 1e-10 of it
  // leaves room for other compilers; a lost history would differ by the whole force.
  const auto ha = histories_by_key(sa), hb = histories_by_key(sb);
  ASSERT_GT(ha.size(), 10u);
  ASSERT_EQ(ha.size(), hb.size());
  double largest = 0;
  for (const auto& [key, h] : ha) largest = std::max(largest, norm(h.elastic_force));
  ASSERT_GT(largest, 0);
  for (const auto& [key, h] : ha) {
    ASSERT_TRUE(hb.count(key)) << key.first << "-" << key.second;
    EXPECT_LT(norm(h.elastic_force - hb.at(key).elastic_force), 1e-10 * largest)
        << key.first << "-" << key.second;
  }
  // The same motion: positions within 1e-13 m (measured: 2e-16 m; the particles are 10 mm).
  const std::vector<TrajectoryRow> ra = a.trajectory_rows(), rb = b.trajectory_rows();
  ASSERT_EQ(ra.size(), rb.size());
  for (std::size_t k = 0; k < ra.size(); ++k) {
    EXPECT_EQ(ra[k].id, rb[k].id);
    EXPECT_LT(norm(ra[k].position - rb[k].position), 1e-13) << ra[k].id;
  }
}

TEST(DomainStep, KeepParticlesMovesEveryArrayWithItsParticle) {
  const Scene scene = scene_from(pour_scene(true, false, false));
  HostStep<double> step(scene, 1);
  step.step();
  const StepState<double> before = step.export_state();
  std::vector<int> order;  // every other particle, backwards
  for (int i = step.particle_count() - 1; i >= 0; i -= 2) order.push_back(i);
  step.keep_particles(order);
  const StepState<double> after = step.export_state();
  ASSERT_EQ(after.count, static_cast<int>(order.size()));
  for (std::size_t k = 0; k < order.size(); ++k) {
    EXPECT_EQ(after.global_ids[k], before.global_ids[order[k]]);
    EXPECT_EQ(after.template_ids[k], before.template_ids[order[k]]);
    for (std::size_t a = 0; a < before.arrays.size(); ++a)
      EXPECT_EQ(after.arrays[a].second[k], before.arrays[a].second[order[k]])
          << before.arrays[a].first;
  }
  step.step();  // and the step goes on over the smaller set
  EXPECT_EQ(step.particle_count(), static_cast<int>(order.size()));
}

}  // namespace
}  // namespace talus
