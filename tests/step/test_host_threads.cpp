// The host step on several threads (core/host_parallel.hpp) gives the bits of one thread: a bed of
// 1331 overlapping dodecahedra in a box, moving and spinning, stepped on 1, 2 and 3 threads; and
// the per-particle accumulation adds the contacts exactly as the serial loop over the contacts
// (add_pair_force, then add_wall_force) did. Every comparison is exact (EXPECT_EQ on the
// doubles): any change in the order of a floating-point sum changes the last bits of some force
// in a bed with ~3 contacts per particle, and so the trajectories.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <random>
#include <string>
#include <vector>

#include "solver/step/host/contact_stage.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/step/host/wall_stage.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

// side^3 dodecahedra of 10 mm on a lattice of 8.2 mm (each overlaps its neighbours: about 3 pair
// contacts per particle) in a box whose walls cut the outer layer, with random orientations,
// velocities (|v_k| <= 0.05 m/s) and angular velocities (|w_k| <= 20 rad/s), so that friction,
// rotation and the wall contacts all act from the first step. 1331 particles: more than
// kParallelMinIndices, so the per-particle loops run on several threads too.
Scene bed(const std::string& effects, Precision precision, int side = 11) {
  const double spacing = 0.0082, extent = spacing * side;
  const std::string lo = std::to_string(-0.0005), hi = std::to_string(extent + 0.0005);
  Scene scene = talus_test::scene_from(R"(time: {step: 1.0e-6, end: 1.0}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  grain: {shape: "dodecahedron:0.01", material: glass}
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0]}
walls:
  - box: {min: [)" + lo + ", " + lo + ", " +
                                       lo + "], max: [" + hi + ", " + hi + ", " + hi +
                                       "], material: glass}\neffects:\n" + effects);
  scene.precision = precision;
  const ParticleState model = scene.particles.front();
  scene.particles.clear();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int i = 0; i < side * side * side; ++i) {
    ParticleState p = model;
    p.position = Vec3d(spacing * (0.5 + i % side), spacing * (0.5 + (i / side) % side),
                       spacing * (0.5 + i / (side * side)));
    const double w = unit(rng), x = unit(rng), y = unit(rng), z = unit(rng);
    const double norm = std::sqrt(w * w + x * x + y * y + z * z);
    p.orientation = Quatd(w / norm, x / norm, y / norm, z / norm);
    p.velocity = Vec3d(unit(rng), unit(rng), unit(rng)) * 0.05;
    p.angular_velocity = Vec3d(unit(rng), unit(rng), unit(rng)) * 20.0;
    scene.particles.push_back(p);
  }
  return scene;
}

const char* const kVolume =
    "  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n  rotation: true\n";
const char* const kLinearWithDrag =
    "  gravity: [0, 0, -9.81]\n  contact: {model: linear, stiffness: 1.0e4, damping: 0.5, "
    "tangential_damping: 1.0}\n  friction: true\n  rotation: true\n  drag: {alpha: 1.0e-4}\n";

// Everything a step leaves behind, in a fixed order, with a name per value for the messages.
struct Snapshot {
  std::vector<double> values;
  std::vector<std::string> names;
  std::size_t pair_contacts = 0, wall_contacts = 0;
};

template <class Real>
void add_field(Snapshot& s, const char* name, const Soa3<Real>& f, int count) {
  for (int i = 0; i < count; ++i) {
    const Real v[3] = {f.x[i], f.y[i], f.z[i]};
    for (int k = 0; k < 3; ++k) {
      s.values.push_back(double(v[k]));
      s.names.push_back(std::string(name) + "[" + std::to_string(i) + "]." + "xyz"[k]);
    }
  }
}

template <class Real>
Snapshot run(const Scene& scene, int threads, int steps) {
  HostStep<Real> step(scene, threads);
  EXPECT_EQ(step.threads(), threads);
  for (int n = 0; n < steps; ++n) step.step();
  Snapshot s;
  const ParticleView<Real>& p = step.particles();
  add_field(s, "position", p.position, p.count);
  add_field(s, "velocity", p.velocity, p.count);
  add_field(s, "angular_velocity", p.angular_velocity, p.count);
  add_field(s, "force", p.force, p.count);
  add_field(s, "torque", p.torque, p.count);
  const Soa3<Real> orientation_xyz{p.orientation.x, p.orientation.y, p.orientation.z};
  add_field(s, "orientation", orientation_xyz, p.count);
  for (int i = 0; i < p.count; ++i) {
    s.values.push_back(double(p.orientation.w[i]));
    s.names.push_back("orientation[" + std::to_string(i) + "].w");
  }
  for (std::size_t w = 0; w < scene.walls.size(); ++w) {
    const Vec3d f = step.wall_force(static_cast<int>(w)), t = step.wall_torque(static_cast<int>(w));
    for (const double v : {f.x, f.y, f.z, t.x, t.y, t.z}) {
      s.values.push_back(v);
      s.names.push_back("wall " + std::to_string(w) + " force/torque");
    }
  }
  s.pair_contacts = step.pair_contact_count();
  s.wall_contacts = step.wall_contact_count();
  return s;
}

// Exact equality, reported at the first difference (one line rather than thousands).
void expect_identical(const Snapshot& serial, const Snapshot& parallel, int threads) {
  EXPECT_EQ(serial.pair_contacts, parallel.pair_contacts) << threads << " threads";
  EXPECT_EQ(serial.wall_contacts, parallel.wall_contacts) << threads << " threads";
  ASSERT_EQ(serial.values.size(), parallel.values.size());
  for (std::size_t k = 0; k < serial.values.size(); ++k) {
    if (!(serial.values[k] == parallel.values[k])) {
      EXPECT_EQ(serial.values[k], parallel.values[k])
          << serial.names[k] << " differs on " << threads << " threads: " << std::setprecision(17)
          << serial.values[k] << " vs " << parallel.values[k];
      return;
    }
  }
}

template <class Real>
void check_thread_counts(const Scene& scene, int steps) {
#ifndef _OPENMP
  GTEST_SKIP() << "built without OpenMP: the host step has one thread";
#endif
  const Snapshot serial = run<Real>(scene, 1, steps);
  // The bed must exercise every stage: pair contacts (about 3 per particle), wall contacts, and
  // motion (the positions moved, so a stage that did nothing would not pass unseen).
  EXPECT_GT(serial.pair_contacts, 3000u);
  EXPECT_GT(serial.wall_contacts, 100u);
  for (const int threads : {2, 3})
    expect_identical(serial, run<Real>(scene, threads, steps), threads);
}

TEST(HostThreads, VolumeModelStepsAreBitIdenticalOnOneTwoAndThreeThreads) {
  check_thread_counts<double>(bed(kVolume, Precision::float64), 20);
}

TEST(HostThreads, LinearModelWithDragStepsAreBitIdenticalOnOneTwoAndThreeThreads) {
  check_thread_counts<double>(bed(kLinearWithDrag, Precision::float64), 20);
}

TEST(HostThreads, FloatStepsAreBitIdenticalOnOneTwoAndThreeThreads) {
  check_thread_counts<float>(bed(kVolume, Precision::float32), 20);
}

// The per-particle accumulation of the stages against the serial loop it replaced: add_pair_force
// over the contacts in pair order, then add_wall_force over the wall contacts in order, onto the
// same starting forces. The contacts come from a bed stepped a few times (springs loaded).
TEST(HostThreads, PerParticleAccumulationAddsAsTheSerialLoopOverContacts) {
  const Scene scene = bed(kVolume, Precision::float64);
  HostStep<double> step(scene, 1);
  for (int n = 0; n < 5; ++n) step.step();
  const int threads = 2;
  PairContactStage<double> contacts(scene, step.bodies(), threads);
  WallContactStage<double> walls(scene, step.bodies(), threads);
  const ParticleView<double>& state = step.particles();
  contacts.find_candidates(state);
  contacts.compute(state, 1.0e-6);
  walls.place(step.time());
  walls.compute(state, contacts.tables(), 1.0e-6);
  ASSERT_GT(contacts.contact_count(), 3000u);
  ASSERT_GT(walls.contact_count(), 100u);

  // Two copies of the force and torque arrays, starting from the step's (gravity and contacts:
  // not zero, so the first addition rounds too).
  const int n = state.count;
  std::vector<std::vector<double>> arrays(12);
  const double* start[6] = {state.force.x,  state.force.y,  state.force.z,
                            state.torque.x, state.torque.y, state.torque.z};
  for (int a = 0; a < 12; ++a) arrays[a].assign(start[a % 6], start[a % 6] + n);
  ParticleView<double> gathered = state, serial = state;
  gathered.force = Soa3<double>{arrays[0].data(), arrays[1].data(), arrays[2].data()};
  gathered.torque = Soa3<double>{arrays[3].data(), arrays[4].data(), arrays[5].data()};
  serial.force = Soa3<double>{arrays[6].data(), arrays[7].data(), arrays[8].data()};
  serial.torque = Soa3<double>{arrays[9].data(), arrays[10].data(), arrays[11].data()};

  contacts.accumulate(gathered);
  walls.accumulate(gathered);
  for (const PairContactRecord<double>& c : contacts.contacts()) add_pair_force(serial, c);
  for (const WallContactRecord<double>& c : walls.contacts()) add_wall_force(serial, c);

  for (int a = 0; a < 6; ++a) {
    for (int i = 0; i < n; ++i) {
      if (!(arrays[a][i] == arrays[a + 6][i])) {
        EXPECT_EQ(arrays[a][i], arrays[a + 6][i])
            << "array " << a << ", particle " << i << ": " << std::setprecision(17) << arrays[a][i]
            << " vs " << arrays[a + 6][i];
        return;
      }
    }
    // The contacts changed the forces (the comparison is not of two untouched copies).
    EXPECT_NE(arrays[a], std::vector<double>(start[a], start[a] + n)) << "array " << a;
  }
}

}  // namespace
}  // namespace talus
