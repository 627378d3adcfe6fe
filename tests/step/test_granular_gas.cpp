// Closed systems on the host step: a gas of 27 cubes in a closed box. With restitution 1 and no
// friction nothing dissipates, so the energy balance (energy.hpp) must stay constant but for the
// integrator's error, which for velocity Verlet shrinks as dt^2. With restitution below 1 and
// friction the balance counts what damping, friction and the ended contacts' springs took, and
// must close alike. Both with the particles' rotation: the default law's torque is the exact
// gradient of U(V) (the overlap's surface moment) and its rocking spring's energy is counted
// (force_law.hpp's patch_couple).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "solver/step/host/host_step.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

constexpr double kBox = 0.05;  // m, the closed box's side, centred on the origin

// Friction mu and restitution eps of the one material; friction is on where mu > 0.
struct Material {
  double friction = 0, restitution = 1;
};

std::string head(double dt, double end, bool rotation, Material m) {
  std::ostringstream s;
  s << "time: {step: " << dt << ", end: " << end << "}\n"
    << "materials:\n"
    << "  stone: {density: 1200, youngs_modulus: 5.0e6, poisson_ratio: 0.3, friction: "
    << m.friction << ",\n"
    << "          restitution: " << m.restitution << "}\n"
    << "templates:\n"
    << "  grain: {shape: \"cube:0.01\", material: stone}\n"
    << "effects: {contact: volume, rotation: " << (rotation ? "true" : "false")
    << ", friction: " << (m.friction > 0 ? "true" : "false") << "}\n"
    << "walls:\n"
    << "  - box: {min: [" << -kBox / 2 << ", " << -kBox / 2 << ", " << -kBox / 2 << "], max: ["
    << kBox / 2 << ", " << kBox / 2 << ", " << kBox / 2 << "], material: stone}\n"
    << "particles:\n"
    << "  - explicit:\n";
  return s.str();
}

std::string particle(const double x[3], const double v[3], const double w[3], double turn) {
  std::ostringstream s;
  s.precision(17);
  s << "      - {template: grain, position: [" << x[0] << ", " << x[1] << ", " << x[2]
    << "], velocity: [" << v[0] << ", " << v[1] << ", " << v[2] << "], angular_velocity: [" << w[0]
    << ", " << w[1] << ", " << w[2] << "], orientation: {axis: [0.3, -0.5, 1], degrees: " << turn
    << "}}\n";
  return s.str();
}

// 27 cubes on a 3 x 3 x 3 lattice filling the box, speeds up to 0.5 m/s and spins up to 50 rad/s
// in random directions (seeded), turned by random angles.
std::string gas(double dt, double end, bool rotation, Material m = {}) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::string text = head(dt, end, rotation, m);
  const double spacing = kBox / 3;
  for (int i = 0; i < 27; ++i) {
    const double x[3] = {-kBox / 2 + spacing * (i % 3 + 0.5),
                         -kBox / 2 + spacing * (i / 3 % 3 + 0.5),
                         -kBox / 2 + spacing * (i / 9 + 0.5)};
    const double v[3] = {0.5 * unit(random), 0.5 * unit(random), 0.5 * unit(random)};
    const double w[3] = {50 * unit(random), 50 * unit(random), 50 * unit(random)};
    text += particle(x, v, w, 180 * (1 + unit(random)));
  }
  return text;
}

// The largest |balance - balance at start| over the run's steps, relative to the start's energy
// (the energy put in: the gas is closed).
double balance_error(const std::string& yaml) {
  const Scene scene = talus_test::scene_from(yaml);
  HostStep<double> step(scene);
  const double start = step.energy().balance();
  double worst = 0;
  const long long steps = std::llround(scene.end_time / scene.time_step);
  for (long long k = 0; k < steps; ++k) {
    step.step();
    worst = std::max(worst, std::abs(step.energy().balance() - start));
  }
  return worst / start;
}

// The errors at dt and dt / 2 shrink as dt^2 (see below).
void expect_dt_squared(double coarse, double fine) {
  EXPECT_GT(coarse / fine, 3.0) << coarse << " then " << fine;
  EXPECT_LT(coarse / fine, 6.0) << coarse << " then " << fine;
}

// Velocity Verlet's energy error of a smooth force field is O(dt^2): halving dt divides it by 4.
// Contacts make the field only piecewise smooth (a contact starts between two steps), which adds
// O(dt^3) per event: a ratio between 3 and 6 says dt^2 (a first-order error gives 2, a
// non-conservative force ~1: with the force at the overlap's centroid alone and rotation the gas
// gained 14 % at either step, docs/contact.md). The bound on the size: at 1e-5 s the error
// measured 1.5e-5 without rotation and 6.7e-6 with it; 1e-4 leaves room while a work from
// nothing of a percent fails it.
void expect_elastic_gas_conserves(bool rotation) {
  const double coarse = balance_error(gas(1e-5, 0.1, rotation));
  const double fine = balance_error(gas(5e-6, 0.1, rotation));
  EXPECT_LT(coarse, 1e-4);
  expect_dt_squared(coarse, fine);
}

TEST(GranularGas, ElasticGasWithoutRotationConservesEnergyToDtSquared) {
  expect_elastic_gas_conserves(false);
}

TEST(GranularGas, ElasticGasWithRotationConservesEnergyToDtSquared) {
  expect_elastic_gas_conserves(true);
}

// With eps = 0.5, mu = 0.4 and rotation, 81 % of the energy is dissipated in 0.1 s, by damping,
// friction, the patch's dashpots and the springs of the contacts that end (energy.hpp). The
// balance closes but for the integrator's error, O(dt^2) as above (a ratio between 3 and 6 on
// halving), within 1e-6 of the energy put in at dt = 1.25e-6 s (measured 4.8e-7, and 1.9e-6 at
// 2.5e-6 s; 3.4e-5 at 1e-5 s over 0.2 s). Before the ended contacts' springs were counted the
// balance missed 4 % of the dissipation (without rotation); with the springs' change taken as a
// rate (half a step late) the error within a contact was O(dt).
TEST(GranularGas, FrictionalGasBalanceClosesToDtSquared) {
  const Material m{0.4, 0.5};
  const double coarse = balance_error(gas(2.5e-6, 0.1, true, m));
  const double fine = balance_error(gas(1.25e-6, 0.1, true, m));
  EXPECT_LT(fine, 1e-6);
  expect_dt_squared(coarse, fine);
}

}  // namespace
}  // namespace talus
