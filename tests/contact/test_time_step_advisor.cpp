// The time-step advisor (solver/contact/time_step_advisor.hpp): its numbers for a cube computed
// here by hand from the formulas, its limit against talus's own integrator, the paper law's
// nanosecond steps, the default law's practical ones, the linear law, and the cases where
// nothing limits the step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "solver/contact/time_step_advisor.hpp"
#include "solver/dynamics/integrator.hpp"
#include "solver/scene/scene_loader.hpp"

namespace talus {
namespace {

// The advisor's numbers are closed formulas of the template's volume, moments and face areas,
// which the template builder computes to a few units of round-off (1e-15 relative): 1e-12
// leaves a thousandfold margin and still catches any wrong factor.
constexpr double kRelTol = 1e-12;

void expect_relative(double actual, double expected, const char* what) {
  EXPECT_NEAR(actual, expected, kRelTol * std::abs(expected)) << what;
}

// A scene of `particles` (YAML list items) of one template `shape` made of `material`, with the
// given effects and, when `floor`, a plane wall.
std::string scene_text(const std::string& shape, const std::string& material,
                       const std::string& particles, const std::string& effects, bool floor) {
  std::string text = "time: {step: 1.0e-5, end: 1}\nmaterials:\n  stuff: {" + material +
                     "}\ntemplates:\n  cube: {shape: " + shape +
                     ", material: stuff}\nparticles:\n  - explicit:\n" + particles;
  if (floor)
    text +=
        "walls:\n  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: stuff}\n";
  return text + "effects:\n" + effects;
}

const std::string kOne = "      - {template: cube, position: [0, 0, 0.01]}\n";
const std::string kTwo = kOne + "      - {template: cube, position: [0, 0, 0.03]}\n";
// The issue's material: E = 5 MPa, density 1200.
const std::string kSoft =
    "density: 1200, youngs_modulus: 5.0e6, poisson_ratio: 0.3, friction: 0.5, restitution: 0.5";
const std::string kVolumeEffects =
    "  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: true\n  rotation: true\n";

Scene parse(const std::string& text) {
  return parse_scene(text, "advisor.yaml", ".");
}

// cube:0.01 is the cube of circumscribed diameter d = 0.01 m, side s = d / sqrt(3) = 5.77 mm.
struct HandCube {
  double d = 0.01, side = d / std::sqrt(3.0), volume = side * side * side;
  double density = 1200, E = 5.0e6, nu = 0.3, eps = 0.5;
  double mass = density * volume;
  double moment = mass * side * side / 6;              // any axis through the centre
  double bounding = d / 2;                             // the corners
  double radius = std::cbrt(3 * volume / (4 * M_PI));  // equal-volume sphere
  double face = side * side;                           // every face
  double zeta_eps() const {                            // Eqs. 15, 20
    const double l = std::log(eps);
    return -l / std::sqrt(l * l + M_PI * M_PI);
  }
};

struct HandKind {
  double k_n, k_t, k, w, omega, zeta, dt;
};

// The default law by hand for two cubes (pair) or a cube at a rigid wall, with rotation:
// K = E/R (+ E/R), A_ref = pi R^2, k_n = K A^2 / A_ref, k_t = G A, G = E/(2(1+nu)R) (+ the same);
// per mode w = sum of 1/m + lever^2/I, the normal lever 0 (a whole face, at its centre), the
// tangential R_b; omega = sqrt(k w), zeta = zeta_eps, dt = 2/omega (sqrt(1 + 4 zeta^2) - 2 zeta);
// the kind's mode is the one with the smaller dt.
HandKind hand_default_law(const HandCube& c, bool pair) {
  const double bodies = pair ? 2 : 1;
  const double K = bodies * c.E / c.radius;
  const double G = bodies * c.E / (2 * (1 + c.nu) * c.radius);
  const double k_n = K * c.face * c.face / (M_PI * c.radius * c.radius);
  const double k_t = G * c.face;
  const auto mode = [&](double k, double lever2) {
    HandKind h;
    h.k_n = k_n;
    h.k_t = k_t;
    h.k = k;
    h.w = bodies * (1 / c.mass + lever2 / c.moment);
    h.omega = std::sqrt(h.k * h.w);
    h.zeta = c.zeta_eps();
    h.dt = 2 / h.omega * (std::sqrt(1 + 4 * h.zeta * h.zeta) - 2 * h.zeta);
    return h;
  };
  const HandKind normal = mode(k_n, 0);
  const HandKind tangential = mode(k_t, c.bounding * c.bounding);
  return tangential.dt < normal.dt ? tangential : normal;
}

void expect_kind(const ContactKindAdvice& kind, const HandKind& h) {
  expect_relative(kind.normal_stiffness, h.k_n, "k_n");
  expect_relative(kind.tangential_stiffness, h.k_t, "k_t");
  expect_relative(kind.stiffness, h.k, "k");
  expect_relative(kind.inverse_mass, h.w, "inverse mass");
  expect_relative(kind.omega, h.omega, "omega");
  expect_relative(kind.damping_ratio, h.zeta, "zeta");
  expect_relative(kind.critical_step, h.dt, "dt_crit");
}

// One cube on a plane wall, default law: the only contact is the wall's (a template meets itself
// only where two of its particles exist), and every number is the hand computation's.
TEST(TimeStepAdvisor, CubeOnPlaneWallMatchesTheHandComputation) {
  const Scene scene = parse(scene_text("cube:0.01", kSoft, kOne, kVolumeEffects, true));
  const TimeStepAdvice advice = advise_time_step(scene);
  const HandCube cube;
  const HandKind hand = hand_default_law(cube, false);
  ASSERT_EQ(advice.kinds.size(), 1u);
  EXPECT_EQ(advice.kinds[0].name, "cube-wall");
  expect_kind(advice.kinds[0], hand);
  // For a cube k_n / k_t = 2 (1 + nu) s^2 / (pi R^2) = 2.15, but the tangential mode has the
  // lever arm R_b (w = 5.5 / m against 1 / m): it limits.
  EXPECT_EQ(advice.kinds[0].stiffness, advice.kinds[0].tangential_stiffness);
  expect_relative(advice.critical_step, hand.dt, "scene dt_crit");
  expect_relative(advice.recommended_step, 0.2 * hand.dt, "auto step");
  EXPECT_EQ(advice.limit, "cube-wall contacts");
  EXPECT_EQ(advice.describe(), "cube-wall contacts, contact: volume");
  // T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu)).
  const double shear = cube.E / (2 * (1 + cube.nu));
  expect_relative(
      advice.rayleigh_time,
      M_PI * cube.radius * std::sqrt(cube.density / shear) / (0.1631 * cube.nu + 0.8766),
      "Rayleigh time");
  // The numbers themselves, printed for the record.
  std::printf(
      "cube on a wall: k_n %.4g N/m, k_t %.4g N/m, omega %.4g rad/s, zeta %.4g, dt_crit "
      "%.4g s\n",
      hand.k_n, hand.k_t, hand.omega, hand.zeta, hand.dt);
}

// Two cubes and the wall: the pair kind appears, with twice K and G and both bodies' inverse
// masses; it is the stiffer contact and limits the scene.
TEST(TimeStepAdvisor, TwoCubesAddThePairContact) {
  const Scene scene = parse(scene_text("cube:0.01", kSoft, kTwo, kVolumeEffects, true));
  const TimeStepAdvice advice = advise_time_step(scene);
  ASSERT_EQ(advice.kinds.size(), 2u);
  EXPECT_EQ(advice.kinds[0].name, "cube-cube");
  EXPECT_EQ(advice.kinds[1].name, "cube-wall");
  const HandCube cube;
  expect_kind(advice.kinds[0], hand_default_law(cube, true));
  expect_kind(advice.kinds[1], hand_default_law(cube, false));
  EXPECT_EQ(advice.limiting_kind, 0);
  EXPECT_EQ(advice.limit, "cube-cube contacts");
  expect_relative(advice.critical_step, hand_default_law(cube, true).dt, "scene dt_crit");
}

// The limit is the one of talus's integrator (begin_translation / end_translation, the force at
// the predicted velocity): a mode of the advisor run at 0.98 dt_crit stays bounded, at 1.02
// dt_crit it grows without bound. Restitutions 1, 0.5 and 0.1 give damping ratios 0 to 1.4.
TEST(TimeStepAdvisor, CriticalStepIsTheIntegratorsStabilityLimit) {
  for (const char* restitution : {"1.0", "0.5", "0.1"}) {
    const std::string material =
        "density: 1200, youngs_modulus: 5.0e6, poisson_ratio: 0.3, friction: 0.5, "
        "restitution: " +
        std::string(restitution);
    const Scene scene = parse(scene_text("cube:0.01", material, kOne, kVolumeEffects, true));
    const ContactKindAdvice& kind = advise_time_step(scene).kinds.at(0);
    // The mode: mass 1/w, spring k, dashpot c = 2 zeta omega / w.
    const double mass = 1 / kind.inverse_mass;
    const double damping = 2 * kind.damping_ratio * kind.omega / kind.inverse_mass;
    auto largest_excursion = [&](double dt) {
      Vec3d x(1e-6, 0, 0), v, start_acceleration;
      Vec3d force = x * -kind.stiffness;  // at rest: no damping force
      double largest = 0;
      for (int step = 0; step < 4000; ++step) {
        begin_translation(x, v, force, mass, dt, start_acceleration);
        force = x * -kind.stiffness - v * damping;  // v: the predicted velocity
        end_translation(v, force, mass, dt, start_acceleration);
        largest = std::max(largest, std::abs(x.x));
      }
      return largest / 1e-6;
    };
    // At 0.98 dt_crit the spectral radius is at most 1: undamped, Verlet's amplitude is at most
    // 1 / sqrt(1 - (omega dt / 2)^2) = 5 times the start, damped less; 10 bounds both. At 1.02 an
    // eigenvalue lies below -1 by a few per cent, and 4000 steps multiply by far more than 1e6.
    EXPECT_LT(largest_excursion(0.98 * kind.critical_step), 10.0) << restitution;
    EXPECT_GT(largest_excursion(1.02 * kind.critical_step), 1e6) << restitution;
  }
}

// The issue's case: the paper's law as printed (volume_paper) for a 5.77 mm cube (E = 5 MPa,
// density 1200) under gravity. At the weight W = m g the face contact's stiffness is
// K^3 A^4 / (3 W^2), about 2e14 N/m at the floor, and the stable step is below 1e-8 s.
TEST(TimeStepAdvisor, PaperLawCubeUnderGravityNeedsNanosecondSteps) {
  const std::string effects =
      "  gravity: [0, 0, -9.81]\n  contact: volume_paper\n  friction: true\n  rotation: true\n";
  const Scene scene = parse(scene_text("cube:0.01", kSoft, kTwo, effects, true));
  const TimeStepAdvice advice = advise_time_step(scene);
  EXPECT_LT(advice.critical_step, 1e-8);
  EXPECT_GT(advice.critical_step, 0.0);
  EXPECT_EQ(advice.model, "volume_paper");
  const HandCube cube;
  ASSERT_EQ(advice.kinds.size(), 2u);
  const ContactKindAdvice& wall = advice.kinds[1];
  const double weight = cube.mass * 9.81, K = cube.E / cube.radius;
  expect_relative(wall.load, weight, "load");
  expect_relative(wall.normal_stiffness, K * K * K * std::pow(cube.face, 4) / (3 * weight * weight),
                  "k_n");
  EXPECT_GT(wall.normal_stiffness, 1e14);  // the docs' "about 2e14 N/m"
  EXPECT_LT(wall.normal_stiffness, 4e14);
  std::printf("paper law, cube under gravity: k_n at the wall %.3g N/m, dt_crit %.3g s (%s)\n",
              wall.normal_stiffness, advice.critical_step, advice.limit.c_str());
}

// Without gravity the paper law is evaluated at the peak force of a face-on impact at the
// largest initial speed: that force F stores the impact's energy, U = 3/4 K A^(4/3) d^(4/3) =
// m_eff v^2 / 2 with d = (F / (K A^(4/3)))^3. Without any speed nothing loads the contacts.
TEST(TimeStepAdvisor, PaperLawWithoutGravityTakesTheImpactOrNothing) {
  const std::string effects = "  contact: volume_paper\n";
  const std::string moving =
      "      - {template: cube, position: [0, 0, 0.01], velocity: [0, 0, -0.5]}\n";
  const TimeStepAdvice impact =
      advise_time_step(parse(scene_text("cube:0.01", kSoft, moving, effects, true)));
  ASSERT_EQ(impact.kinds.size(), 1u);
  const HandCube cube;
  const double K = cube.E / cube.radius, a43 = std::pow(cube.face, 4.0 / 3.0);
  const double d = std::pow(impact.kinds[0].load / (K * a43), 3);
  expect_relative(0.75 * K * a43 * std::pow(d, 4.0 / 3.0), 0.5 * cube.mass * 0.25, "energy");
  EXPECT_TRUE(std::isfinite(impact.critical_step));

  const TimeStepAdvice still =
      advise_time_step(parse(scene_text("cube:0.01", kSoft, kOne, effects, true)));
  EXPECT_TRUE(std::isinf(still.critical_step));
  EXPECT_TRUE(std::isinf(still.recommended_step));
  EXPECT_FALSE(still.limited());
  EXPECT_EQ(still.limit.rfind("no load", 0), 0u) << still.limit;
}

// The default law's steps for 10 mm particles (circumscribed diameter) of E = 5 MPa, density
// 1200, restitution 0.5, with friction and rotation, in pairs and at a wall: above 1e-5 s, so the
// common dt = 1e-5 s is accepted.
TEST(TimeStepAdvisor, DefaultLawAcceptsTenMicrosecondsForTenMillimetreParticles) {
  for (const char* shape : {"tetrahedron:0.01", "cube:0.01", "octahedron:0.01", "dodecahedron:0.01",
                            "icosahedron:0.01"}) {
    const TimeStepAdvice advice =
        advise_time_step(parse(scene_text(shape, kSoft, kTwo, kVolumeEffects, true)));
    EXPECT_GT(advice.critical_step, 1e-5) << shape << ": " << advice.limit;
    std::printf("%s, default law: dt_crit %.3g s (%s), Rayleigh time %.3g s\n", shape,
                advice.critical_step, advice.describe().c_str(), advice.rayleigh_time);
  }
}

// The linear law: k = K_N, no tangential spring, zeta = eta / (2 sqrt(k m_eff)); spheres' normal
// force
// passes through their centres, so rotation adds nothing to their normal mode.
TEST(TimeStepAdvisor, LinearLawOnSpheres) {
  const std::string text = R"(time: {step: 1.0e-5, end: 0.02}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  ball: {sphere: 0.005, material: glass}
particles:
  - explicit:
      - {template: ball, position: [-0.01, 0, 0]}
      - {template: ball, position: [0.01, 0, 0]}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 0.2, tangential_damping: 0.1}
  friction: true
  rotation: true
)";
  const TimeStepAdvice advice = advise_time_step(parse(text));
  ASSERT_EQ(advice.kinds.size(), 1u);
  const ContactKindAdvice& kind = advice.kinds[0];
  const double mass = 2500 * 4.0 / 3.0 * M_PI * std::pow(0.005, 3);
  // zeta = eta / (2 sqrt(k m_eff)), m_eff = m / 2 = 1 / w.
  const double w = 2 / mass, omega = std::sqrt(1.0e4 * w), zeta = 0.2 * w / (2 * omega);
  EXPECT_EQ(kind.normal_stiffness, 1.0e4);
  EXPECT_EQ(kind.tangential_stiffness, 0.0);
  expect_relative(kind.inverse_mass, w, "inverse mass");
  expect_relative(kind.damping_ratio, zeta, "zeta");
  expect_relative(advice.critical_step, 2 / omega * (std::sqrt(1 + 4 * zeta * zeta) - 2 * zeta),
                  "dt_crit");
  EXPECT_EQ(advice.describe(), "ball-ball contacts, contact: linear");
}

// Nothing limits the step without contacts, or with one particle and no walls.
TEST(TimeStepAdvisor, NothingLimitsAStepWithoutContacts) {
  const TimeStepAdvice none = advise_time_step(
      parse(scene_text("cube:0.01", kSoft, kTwo, "  gravity: [0, 0, -9.81]\n", false)));
  EXPECT_TRUE(std::isinf(none.critical_step));
  EXPECT_EQ(none.limit, "no contacts (effects.contact is absent)");
  EXPECT_TRUE(std::isfinite(none.rayleigh_time));  // the particles are still there
  const TimeStepAdvice alone =
      advise_time_step(parse(scene_text("cube:0.01", kSoft, kOne, kVolumeEffects, false)));
  EXPECT_TRUE(std::isinf(alone.critical_step));
  EXPECT_TRUE(alone.kinds.empty());
  EXPECT_EQ(alone.limit, "no contact can occur (one particle and no walls)");
}

// The stable step printed in messages: two digits, never above the value, and what %.1e prints.
TEST(TimeStepAdvisor, RoundDownKeepsTwoDigitsAndStaysBelow) {
  EXPECT_EQ(round_down_two_digits(2.149e-9), 2.1e-9);
  EXPECT_EQ(round_down_two_digits(7.7e-5), 7.7e-5);
  EXPECT_EQ(round_down_two_digits(9.99e-3), 9.9e-3);
  EXPECT_EQ(round_down_two_digits(1.0e-5), 1.0e-5);
  for (const double value : {2.149e-9, 7.7e-5, 1.36e-5, 3.3333e2, 0.1 + 0.2}) {
    const double rounded = round_down_two_digits(value);
    EXPECT_LE(rounded, value);
    EXPECT_GT(rounded, 0.9 * value);  // two digits lose less than 10%
    char text[32];
    std::snprintf(text, sizeof text, "%.1e", rounded);
    EXPECT_EQ(std::stod(text), rounded) << text;
  }
  EXPECT_TRUE(std::isinf(round_down_two_digits(std::numeric_limits<double>::infinity())));
}

}  // namespace
}  // namespace talus
