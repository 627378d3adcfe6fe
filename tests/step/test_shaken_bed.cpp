// An oscillating wall (WallMotion::Kind::oscillation) gives energy and only that: nine balls
// resting on the floor of a box that is shaken up and down (amplitude 0.5 mm, 40 Hz: a peak
// acceleration A (2 pi f)^2 = 3.2 g, so the balls leave the floor at every cycle), four cycles,
// then left to come to rest. The energy balance (EnergyTerms::balance: what the particles hold,
// plus what was dissipated, less the walls' work) stays constant but for the integrator's error;
// the bed flies while shaken and rests on the floor's rest position after.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "solver/step/host/host_step.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

constexpr double kRadius = 0.005, kAmplitude = 0.0005, kFrequency = 40;

std::string shaken_box(double dt) {
  std::string text = "time: {step: " + std::to_string(dt) + R"(, end: 0.35}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  ball: {sphere: 0.005, material: glass}
walls:
  - box:
      min: [-0.02, -0.02, 0]
      max: [0.02, 0.02, 0.06]
      open_top: true
      material: glass
      motion:
        oscillation: {direction: [0, 0, 1], amplitude: 0.0005, frequency: 40, start: 0.02,
                      cycles: 4}
effects:
  gravity: [0, 0, -9.81]
  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 1.0}
  friction: true
  rotation: true
particles:
  - explicit:
)";
  // A 3 x 3 layer 1 mm apart, 0.1 mm above the floor: they land within the first 20 ms.
  for (int i = 0; i < 9; ++i) {
    text += "      - {template: ball, position: [" + std::to_string(-0.011 + 0.011 * (i % 3)) +
            ", " + std::to_string(-0.011 + 0.011 * (i / 3)) + ", 0.0051]}\n";
  }
  return text;
}

struct ShakenRun {
  double balance_error = 0;  // the largest |balance - its start|
  double wall_work = 0;      // J, the walls' work at the end
  double highest = 0;        // m, the highest ball centre while shaken
  double final_kinetic = 0;  // J
  double final_highest = 0;  // m, the highest ball centre at the end
};

ShakenRun shake(double dt) {
  const Scene scene = talus_test::scene_from(shaken_box(dt));
  HostStep<double> step(scene);
  const double start = step.energy().balance();
  ShakenRun run;
  const long long steps = std::llround(scene.end_time / scene.time_step);
  for (long long k = 1; k <= steps; ++k) {
    step.step();
    run.balance_error = std::max(run.balance_error, std::abs(step.energy().balance() - start));
    if (step.time() > 0.02 && step.time() < 0.12) {
      for (const TrajectoryRow& r : step.trajectory_rows())
        run.highest = std::max(run.highest, r.position.z);
    }
  }
  run.wall_work = step.energy().ledger.wall_work;
  run.final_kinetic = step.kinetic_energy();
  for (const TrajectoryRow& r : step.trajectory_rows())
    run.final_highest = std::max(run.final_highest, r.position.z);
  return run;
}

TEST(ShakenBed, AnOscillatingFloorGivesEnergyThatTheBalanceCounts) {
  const ShakenRun coarse = shake(2e-5), fine = shake(1e-5);
  std::printf(
      "wall work %.3g J; balance error %.3g then %.3g J; highest %.4g m; at the end "
      "%.3g J, highest %.5g m\n",
      fine.wall_work, coarse.balance_error, fine.balance_error, fine.highest, fine.final_kinetic,
      fine.final_highest);
  // The floor worked on the balls: a tenth of a millijoule or more (nine balls of 1.3 g thrown at
  // up to A 2 pi f = 0.13 m/s each cycle, four cycles: measured 3.4e-4 J).
  EXPECT_GT(fine.wall_work, 1e-4);
  // They flew: their centres rose above the floor's top (2 A) plus their radius (measured 10.4
  // mm against 6 mm).
  EXPECT_GT(fine.highest, kRadius + 2 * kAmplitude);
  // The balance's error, O(dt^2) (velocity Verlet, the walls' work by the trapezoid rule at the
  // force evaluations): halving dt divides it by about 4 (between 2.5 and 6: contacts that start
  // between two steps add O(dt^3) each; measured 4.1), and it is below 1e-3 of the work at
  // 1e-5 s (measured 1.8e-4). A work counted with the wall's velocity of another time, or not at
  // all, is off by a good part of the whole work.
  EXPECT_LT(fine.balance_error, 1e-3 * fine.wall_work);
  EXPECT_GT(coarse.balance_error / fine.balance_error, 2.5)
      << coarse.balance_error << " then " << fine.balance_error;
  EXPECT_LT(coarse.balance_error / fine.balance_error, 6.0)
      << coarse.balance_error << " then " << fine.balance_error;
  // 0.23 s after the last cycle the bed rests on the floor's rest position: no ball's centre
  // above its radius (its overlap, weight over stiffness, 1.3 um, puts it below; 0.1 mm would be
  // a ball on another or a floor left raised), the kinetic energy below 1e-12 J (a ball at
  // 0.04 mm/s; measured 1e-21 J).
  EXPECT_LT(fine.final_highest, kRadius + 1e-4);
  EXPECT_LT(fine.final_kinetic, 1e-12);
}

}  // namespace
}  // namespace talus
