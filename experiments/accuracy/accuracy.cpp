// The accuracy-against-time study: README.md here says what each scene measures, against what,
// and why the settings are the ones below.
#include "experiments/accuracy/accuracy.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "solver/contact/time_step_advisor.hpp"
#include "solver/io/output_files.hpp"
#include "solver/scene/scene_loader.hpp"
#include "validation/rotating_drum/drum_analysis.hpp"

namespace talus::accuracy {
namespace {

constexpr double kPi = 3.14159265358979323846;

enum class Law { volume, volume_paper, linear };

// Where one run stands on every knob. The defaults are each scene's usual settings; a knob's
// settings change one field.
struct Setting {
  Law law = Law::volume;
  int sides = 20;       // impact: the cylinder's prism sides; 0: a sphere of the same volume
  int segments = 128;   // drum: the drum wall's polygon sides
  bool single = false;  // float instead of double
  int divisor = 1;      // dt = the advised step (0.2 dt_crit) / divisor
  double skin = 1;      // times the default skin (a tenth of the largest bounding diameter)
  int seed = 0;         // added to the scene's seeds (the noise runs)
  std::string key() const {
    return fmt::format("{}|{}|{}|{}|{}|{}|{}", int(law), sides, segments, single, divisor, skin,
                       seed);
  }
};

const char* law_name(Law law) {
  return law == Law::volume ? "volume" : law == Law::volume_paper ? "volume_paper" : "linear";
}

// One knob's settings on one scene: the label, the ordering value and the setting.
struct KnobSetting {
  std::string label;
  double value;
  Setting setting;
};

// ---- The scenes ------------------------------------------------------------------------------

// The §3.1 impact (validation/cylinder_wall_impact): resin cylinders D = 8 mm, L = 5.3 mm striking
// a plane corner first at 1 m/s, frictionless, without gravity.
constexpr double kImpactD = 0.008, kImpactL = 0.0053, kImpactDensity = 1245;
constexpr double kImpactE = 1.15e9, kImpactRestitution = 0.85, kImpactSpeed = 1.0;
// The packing (the built-in scene, §3.3): 30 mm dodecahedra poured into a 10 cm tube.
constexpr double kPackSize = 0.03;
// The drum (§3.4's, at validation/rotating_drum's small size): 10 mm dodecahedra, 45 rpm.
constexpr double kDrumSize = 0.01, kDrumThickness = 0.011, kDrumRpm = 45, kDrumSpacing = 0.0105;
constexpr double kDrumRadius = 0.075;
constexpr int kDrumLattice = 9;     // 81 particles
constexpr int kDrumCells = 10;      // velocity grid across the diameter
constexpr int kDrumMinSamples = 5;  // a cell counts when both fields have this many samples

// The linear law (BLAZE-DEM Eqs. 2-3) has no material of its own: K_N = E D (the stiffness of a
// contact of the particle's size under the material's modulus) and eta from the restitution for
// a contact of two of the particles (effective mass m/2), or of one with a wall (m), as a user
// would set them: zeta = -ln e / sqrt(pi^2 + ln^2 e), eta = 2 zeta sqrt(m_eff K_N).
void set_linear(Scene& scene, double youngs, double size, double restitution, bool wall) {
  const ParticleTemplate& t = scene.templates.at(0);
  const double mass = scene.materials.at(t.material).density * t.volume;
  const double k = youngs * size;
  const double l = std::log(restitution);
  const double zeta = -l / std::sqrt(kPi * kPi + l * l);
  const double eta = 2 * zeta * std::sqrt((wall ? mass : mass / 2) * k);
  scene.effects.contact = ContactModel::linear;
  scene.effects.linear = {k, eta, eta};
}

std::string contact_text(Law law) {
  // The linear law's numbers are set by set_linear once the template's mass is known.
  return law == Law::linear ? "{model: linear, stiffness: 1, damping: 1, tangential_damping: 1}"
                            : law_name(law);
}

struct ImpactPose {
  double theta_deg;
  Quatd orientation;
  Vec3d position;
  double arm = 0;         // the corner's x offset from the centre (Eqs. 27-28)
  double i_yy = 0;        // the template's moment about world y, kg m^2
  double smooth_arm = 0;  // the same for the smooth cylinder
};

Quatd about(const Vec3d& axis, double radians) {
  const double s = std::sin(radians / 2);
  return {std::cos(radians / 2), axis.x * s, axis.y * s, axis.z * s};
}

std::vector<double> impact_angles(bool quick) {
  std::vector<double> thetas;
  for (double t = 10; t <= 60 + 1e-9; t += quick ? 25 : 5) thetas.push_back(t);
  return thetas;
}

// Eq. 27: the angular velocity after a frictionless corner impact of a body of mass m and
// moment I about the impact plane's normal axis, lever arm `arm`, at speed V, restitution e.
double omega_plus(double mass, double inertia, double arm) {
  return mass * kImpactSpeed * (1 + kImpactRestitution) * arm / (inertia + mass * arm * arm);
}

std::string impact_text(const Setting& s, bool quick) {
  const std::vector<double> thetas = impact_angles(quick);
  std::string shape;
  if (s.sides > 0) {
    shape = fmt::format("shape: \"cylinder:{},{},{}\"", kImpactD, kImpactL, s.sides);
  } else {
    const double volume = kPi * kImpactD * kImpactD / 4 * kImpactL;
    shape = fmt::format("sphere: {}", std::cbrt(3 * volume / (4 * kPi)));
  }
  const double span = 0.02 * double(thetas.size() - 1);
  std::string bodies;  // placed here 1 cm up; run_impact poses them
  for (std::size_t k = 0; k < thetas.size(); ++k)
    bodies +=
        fmt::format("      - {{template: body, position: [0, {}, 0.01], velocity: [0, 0, {}]}}\n",
                    0.02 * double(k), -kImpactSpeed);
  return fmt::format(
      "# The accuracy study's impact (method paper section 3.1): written by\n"
      "# experiments/accuracy/accuracy.cpp; the poses are set after loading.\n"
      "time: {{step: auto, end: 0.001}}\n"
      "precision: {}\n"
      "skin: {}\n"
      "materials:\n"
      "  resin: {{density: {}, youngs_modulus: {}, poisson_ratio: 0.35, friction: 0.0,\n"
      "          restitution: {}}}\n"
      "templates:\n"
      "  body: {{{}, material: resin}}\n"
      "particles:\n"
      "  - explicit:\n{}"
      "walls:\n"
      "  - plane: {{point: [0, {}, 0], normal: [0, 0, 1], size: {}, material: resin}}\n"
      "effects:\n"
      "  contact: {}\n"
      "  friction: false\n"
      "  rotation: true\n",
      s.single ? "float" : "double", s.skin * 0.1 * std::hypot(kImpactD, kImpactL), kImpactDensity,
      kImpactE, kImpactRestitution, shape, bodies, span / 2, span + 0.1, contact_text(s.law));
}

std::string packing_text(const Setting& s, bool quick) {
  // Quick: 16 particles poured from up to 0.2 m, settled by 0.4 s; else the built-in scene's 63
  // from up to 0.6 m for 0.7 s.
  const int count = quick ? 16 : 63;
  const double height = quick ? 0.2 : 0.6;
  return fmt::format(
      "# The accuracy study's packing (the built-in scene, method paper section 3.3): written by\n"
      "# experiments/accuracy/accuracy.cpp.\n"
      "time: {{step: auto, end: {}}}\n"
      "seed: {}\n"
      "precision: {}\n"
      "skin: {}\n"
      "materials:\n"
      "  resin: {{density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.8,\n"
      "          restitution: 0.1}}\n"
      "templates:\n"
      "  dodecahedron: {{shape: dodecahedron:{}, material: resin}}\n"
      "particles:\n"
      "  - random:\n"
      "      template: dodecahedron\n"
      "      region: {{cylinder: {{base: [0, 0, 0], axis: [0, 0, 1], radius: 0.05, height: {}}}}}\n"
      "      count: {}\n"
      "walls:\n"
      "  - cylinder: {{name: tube, base: [0, 0, 0], axis: [0, 0, 1], radius: 0.05, height: {},\n"
      "               bottom_cap: true, segments: 64, material: resin}}\n"
      "effects:\n"
      "  gravity: [0, 0, -9.81]\n"
      "  contact: {}\n"
      "  friction: true\n"
      "  rotation: true\n",
      quick ? 0.4 : 0.7, 33 + s.seed, s.single ? "float" : "double", s.skin * 0.1 * kPackSize,
      kPackSize, height, count, height + 0.1, contact_text(s.law));
}

struct DrumTimes {
  double spin_up, record, sampling;
};
DrumTimes drum_times(bool quick) {
  return quick ? DrumTimes{0.2, 0.1, 2.5e-3} : DrumTimes{0.5, 0.5, 2.5e-3};
}

std::string drum_text(const Setting& s, bool quick) {
  const DrumTimes t = drum_times(quick);
  const double half = 0.5 * kDrumLattice * kDrumSpacing + 0.25 * kDrumSpacing;
  return fmt::format(
      "# The accuracy study's drum (method paper section 3.4 at validation/rotating_drum's small\n"
      "# size): written by experiments/accuracy/accuracy.cpp.\n"
      "time: {{step: auto, end: {}}}\n"
      "seed: {}\n"
      "precision: {}\n"
      "skin: {}\n"
      "materials:\n"
      "  resin: {{density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.7,\n"
      "          restitution: 0.1}}\n"
      "templates:\n"
      "  dodecahedron: {{shape: \"dodecahedron:{}\", material: resin}}\n"
      "particles:\n"
      "  - lattice:\n"
      "      template: dodecahedron\n"
      "      region: {{box: {{min: [{}, {}, {}], max: [{}, {}, {}]}}}}\n"
      "      spacing: [{}, {}, {}]\n"
      "      random_orientation: true\n"
      "      seed: {}\n"
      "walls:\n"
      "  - drum: {{name: drum, center: [0, 0, 0], axis: [0, 1, 0], radius: {}, length: {},\n"
      "            segments: {}, material: resin,\n"
      "            motion: {{rotation: {{axis: [0, 1, 0], point: [0, 0, 0], rpm: {}}}}}}}\n"
      "effects:\n"
      "  gravity: [0, 0, -9.81]\n"
      "  contact: {}\n"
      "  friction: true\n"
      "  rotation: true\n",
      t.spin_up + t.record, 34 + s.seed, s.single ? "float" : "double", s.skin * 0.1 * kDrumSize,
      kDrumSize, -half, -kDrumThickness / 2, -half, half, kDrumThickness / 2, half, kDrumSpacing,
      kDrumThickness, kDrumSpacing, 7 + s.seed, kDrumRadius, kDrumThickness, s.segments, kDrumRpm,
      contact_text(s.law));
}

// ---- Runs ------------------------------------------------------------------------------------

// What one run measured: the wall time of its steps alone (not the scene's setup) and what the
// scene's error is computed from.
struct Measured {
  double wall_seconds = 0, simulated_seconds = 0;
  long long steps = 0;
  std::size_t particles = 0;
  std::vector<double> omega;                          // impact: omega+ per angle, rad/s
  std::vector<double> omega_reference, omega_smooth;  // Eqs. 27-28: this template's, smooth's
  double bed_height = 0;                              // packing, m
  std::shared_ptr<validation::VelocityField> field;   // drum
  double dt = 0;
  bool skipped = false;  // more than kMaxSteps: not run, its error and time NaN
};

// The most steps one run of the study may take: 3e6 steps are about 15 minutes of the drum on
// the GPU, more than the whole study is meant to cost.
constexpr double kMaxSteps = 3e6;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The scene of `name` at `setting`, loaded from the text written into `directory`, with its time
// step the advisor's for this law and these particles, divided by the setting's divisor.
Scene build_scene(const std::string& name, const Setting& s, bool quick,
                  const std::string& directory, const std::string& file) {
  const std::string text = name == "impact"    ? impact_text(s, quick)
                           : name == "packing" ? packing_text(s, quick)
                                               : drum_text(s, quick);
  const std::string path = joined_path(directory, file);
  write_file_atomically(path, text);
  Scene scene = load_scene(path);
  if (s.law == Law::linear) {
    if (name == "impact")
      set_linear(scene, kImpactE, kImpactD, kImpactRestitution, true);
    else
      set_linear(scene, 1.0e6, name == "packing" ? kPackSize : kDrumSize, 0.1, false);
  }
  const TimeStepAdvice advice = advise_time_step(scene);
  scene.time_step = advice.recommended_step / s.divisor;
  return scene;
}

Measured run_impact(const Scene& scene_in, bool quick, const StudyOptions& options) {
  Scene scene = scene_in;
  const std::vector<double> thetas = impact_angles(quick);
  const ParticleTemplate& t = scene.templates.at(0);
  const double density = scene.materials.at(t.material).density;
  const double mass = density * t.volume;
  // The smooth cylinder of the same D and L: mass, transverse moment, the rim corner's radius
  // and angle below the mid-plane (Fig. 9: tan alpha = (L/2) / (D/2)).
  const double smooth_mass = density * kPi * kImpactD * kImpactD / 4 * kImpactL;
  const double smooth_i = smooth_mass * (3 * kImpactD * kImpactD / 4 + kImpactL * kImpactL) / 12;
  const double corner_r = std::hypot(kImpactD / 2, kImpactL / 2);
  const double alpha = std::atan2(kImpactL / 2, kImpactD / 2);

  Measured m;
  if (scene.particles.size() != thetas.size())
    throw std::runtime_error(fmt::format("the impact scene placed {} bodies, expected {}",
                                         scene.particles.size(), thetas.size()));
  for (std::size_t k = 0; k < thetas.size(); ++k) {
    const double theta = thetas[k] * kPi / 180;
    ParticleState& p = scene.particles[k];
    double lowest = 0, arm = 0, i_yy = 0;
    if (t.kind == ParticleShapeKind::polyhedron) {
      // As validation/cylinder_wall_impact: the -z face's outermost corner turned to +x, then the
      // body tilted by theta about y, bringing that corner lowest.
      const ShapeTemplate& shape = t.shape;
      int corner = -1;
      for (int i = 0; i < static_cast<int>(shape.vertices.size()); ++i) {
        const Vec3d& v = shape.vertices[i];
        if (v.z < 0 && (corner < 0 || norm(v) > norm(shape.vertices[corner]) + 1e-12)) corner = i;
      }
      const Vec3d c = shape.vertices[corner];
      p.orientation = about({0, 1, 0}, theta) * about({0, 0, 1}, -std::atan2(c.y, c.x));
      Vec3d low;
      for (const Vec3d& v : shape.vertices) {
        const Vec3d r = rotate(p.orientation, v);
        if (r.z < low.z) low = r;
      }
      lowest = low.z;
      arm = low.x;
      const Mat3<double> rot = rotation_matrix(p.orientation);
      const double moments[3] = {shape.principal_moments.x, shape.principal_moments.y,
                                 shape.principal_moments.z};
      for (int a = 0; a < 3; ++a) i_yy += density * moments[a] * rot.m[1][a] * rot.m[1][a];
    } else {
      p.orientation = {1, 0, 0, 0};
      lowest = -t.sphere_radius;
    }
    p.position = {0, 0.02 * double(k), -lowest + 1e-7};
    p.velocity = {0, 0, -kImpactSpeed};
    p.angular_velocity = {};
    m.omega_reference.push_back(t.kind == ParticleShapeKind::polyhedron
                                    ? omega_plus(mass, i_yy, arm)
                                    : 0.0);  // a sphere's centre is over its contact point
    m.omega_smooth.push_back(omega_plus(smooth_mass, smooth_i, corner_r * std::cos(alpha + theta)));
  }
  std::unique_ptr<AnyStep> step = options.make_step(scene);
  m.particles = step->particles();
  m.dt = scene.time_step;
  // Each body's velocity, sampled every kEvery steps (rows() copies from the device): an impact
  // is over when the velocity has changed and then stays the same over a whole interval (no
  // gravity, no other body: only the wall changes it, and a contact's force is never zero for
  // that long while it lasts). An impact lasts hundreds of steps at the advised step.
  constexpr int kEvery = 16;
  const long long max_steps = std::llround(scene.end_time / scene.time_step);  // 20x an impact
  std::vector<int> state(thetas.size(), 0);
  std::vector<Vec3d> last(thetas.size(), Vec3d{0, 0, -kImpactSpeed});
  m.omega.assign(thetas.size(), 0);
  std::size_t over = 0;
  const Clock::time_point start = Clock::now();
  while (over < thetas.size() && m.steps < max_steps) {
    for (int i = 0; i < kEvery; ++i) step->step();
    m.steps += kEvery;
    for (const TrajectoryRow& row : step->rows()) {
      const std::size_t k = static_cast<std::size_t>(row.id);
      const bool changed = !(row.velocity.x == last[k].x && row.velocity.y == last[k].y &&
                             row.velocity.z == last[k].z);
      last[k] = row.velocity;
      if (state[k] == 0 && changed) state[k] = 1;
      if (state[k] == 1 && !changed) {
        state[k] = 2;
        m.omega[k] = -row.angular_velocity.y;  // the paper's frame has z into the wall
        ++over;
      }
    }
  }
  m.wall_seconds = seconds_since(start);
  if (over < thetas.size())
    throw std::runtime_error(
        fmt::format("the impact: {} of {} bodies still in contact after {} steps",
                    thetas.size() - over, thetas.size(), m.steps));
  m.simulated_seconds = double(m.steps) * scene.time_step;
  return m;
}

Measured run_packing(const Scene& scene, const StudyOptions& options) {
  Measured m;
  std::unique_ptr<AnyStep> step = options.make_step(scene);
  m.particles = step->particles();
  m.dt = scene.time_step;
  m.steps = std::llround(scene.end_time / scene.time_step);
  const Clock::time_point start = Clock::now();
  for (long long k = 0; k < m.steps; ++k) step->step();
  m.wall_seconds = seconds_since(start);
  m.simulated_seconds = double(m.steps) * scene.time_step;
  m.bed_height = step->bed_height(*scene.effects.gravity);
  return m;
}

Measured run_drum(const Scene& scene, bool quick, const StudyOptions& options) {
  const DrumTimes t = drum_times(quick);
  Measured m;
  std::unique_ptr<AnyStep> step = options.make_step(scene);
  m.particles = step->particles();
  m.dt = scene.time_step;
  m.field = std::make_shared<validation::VelocityField>(kDrumCells, 2 * kDrumRadius / kDrumCells);
  const long long first = std::llround(t.spin_up / scene.time_step);
  const long long every = std::max(1LL, std::llround(t.sampling / scene.time_step));
  const long long frames = std::llround(t.record / t.sampling);
  const Clock::time_point start = Clock::now();
  for (long long k = 0; k < first; ++k) step->step();
  m.steps = first;
  for (long long f = 0; f < frames; ++f) {
    for (long long k = 0; k < every; ++k) step->step();
    m.steps += every;
    // The camera's plane: a along x, b along z (up); the drum's axis is y.
    for (const TrajectoryRow& row : step->rows())
      m.field->add({row.position.x, row.position.z}, row.velocity.x, row.velocity.z);
  }
  m.wall_seconds = seconds_since(start);
  m.simulated_seconds = double(m.steps) * scene.time_step;
  return m;
}

// ---- The study -------------------------------------------------------------------------------

// Every knob's settings on a scene (empty where the knob does not apply to it), the scene's
// default setting and its reference setting (the finest of every knob).
struct SceneSpec {
  Setting defaults;
  Setting reference;
  std::map<std::string, std::vector<KnobSetting>> knobs;
};

SceneSpec scene_spec(const std::string& scene, bool quick) {
  SceneSpec spec;
  // The impact runs the paper's own law (Table 1); the others talus's default.
  spec.defaults.law = scene == "impact" ? Law::volume_paper : Law::volume;
  const int finest_divisor = quick ? 2 : scene == "drum" ? 4 : 8;
  spec.reference = spec.defaults;
  spec.reference.divisor = finest_divisor;
  if (scene == "drum") spec.reference.segments = quick ? 128 : 512;
  const auto with = [&](auto change) {
    Setting s = spec.defaults;
    change(s);
    return s;
  };
  auto& knobs = spec.knobs;
  for (Law law : {Law::linear, Law::volume_paper, Law::volume})
    if (!quick || law == spec.defaults.law || law == Law::linear)
      knobs["contact_law"].push_back(
          {law_name(law), double(int(law)), with([&](Setting& s) { s.law = law; })});
  if (scene == "impact") {
    const std::vector<int> sides =
        quick ? std::vector<int>{8, 20} : std::vector<int>{8, 12, 20, 40, 80};
    // Spheres meet walls under the linear law only (the volume laws have no sphere-wall overlap).
    knobs["shape_resolution"].push_back({"sphere (linear law)", 0, with([](Setting& s) {
                                           s.sides = 0;
                                           s.law = Law::linear;
                                         })});
    for (int n : sides)
      knobs["shape_resolution"].push_back(
          {fmt::format("prism {}", n), double(n), with([&](Setting& s) { s.sides = n; })});
  }
  if (scene == "drum") {
    // lambda = the particle's size over a facet's length (method paper Eq. 29).
    const std::vector<int> segments =
        quick ? std::vector<int>{32, 128} : std::vector<int>{16, 32, 64, 128, 256, 512};
    for (int n : segments) {
      const double lambda = kDrumSize / (2 * kPi * kDrumRadius / n);
      knobs["wall_mesh"].push_back({fmt::format("lambda {:.2g}", lambda), lambda,
                                    with([&](Setting& s) { s.segments = n; })});
    }
  }
  knobs["precision"] = {{"double", 64, with([](Setting&) {})},
                        {"float", 32, with([](Setting& s) { s.single = true; })}};
  for (int d = 1; d <= finest_divisor; d *= 2)
    knobs["time_step"].push_back({d == 1 ? std::string("dt") : fmt::format("dt/{}", d), 1.0 / d,
                                  with([&](Setting& s) { s.divisor = d; })});
  for (double f : quick ? std::vector<double>{0, 1} : std::vector<double>{0, 0.5, 1, 2})
    knobs["skin"].push_back(
        {fmt::format("skin {:g}", f), f, with([&](Setting& s) { s.skin = f; })});
  return spec;
}

std::string metric_of(const std::string& scene, const std::string& knob) {
  if (scene == "impact")
    return knob == "shape_resolution"
               ? "rms relative error of omega+ over theta 10-60 deg, against the smooth cylinder"
               : "rms relative error of omega+ over theta 10-60 deg";
  if (scene == "packing") return "relative difference of the bed height";
  return "1 - R^2 of the velocity field";
}

std::string reference_of(const std::string& scene, const std::string& knob,
                         const Setting& reference) {
  if (scene == "impact")
    return knob == "shape_resolution" ? "Eqs. 27-28, smooth cylinder" : "Eqs. 27-28";
  std::string text =
      fmt::format("finest setting ({}, dt/{}", law_name(reference.law), reference.divisor);
  if (scene == "drum") text += fmt::format(", {} segments", reference.segments);
  return text + ", double)";
}

double impact_error(const Measured& m, bool smooth) {
  const std::vector<double>& ref = smooth ? m.omega_smooth : m.omega_reference;
  double sum = 0;
  for (std::size_t k = 0; k < m.omega.size(); ++k) {
    const double e = (m.omega[k] - ref[k]) / ref[k];
    sum += e * e;
  }
  return std::sqrt(sum / double(m.omega.size()));
}

// The scene's error of `m` against the reference run `ref` (packing, drum).
double scene_error(const std::string& scene, const Measured& m, const Measured& ref) {
  if (scene == "packing") return std::abs(m.bed_height - ref.bed_height) / ref.bed_height;
  int used = 0;
  const double r2 = validation::field_r_squared(*m.field, *ref.field, kDrumMinSamples, &used);
  return std::isfinite(r2) ? std::max(0.0, 1 - r2) : std::nan("");
}

std::string csv_number(double x) {
  if (std::isnan(x)) return "nan";
  return fmt::format("{:.10g}", x);
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void check_names(const std::vector<std::string>& given, const std::vector<std::string>& known,
                 const char* what) {
  for (const std::string& name : given) {
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      throw std::invalid_argument(
          fmt::format("unknown {} '{}'; expected one of {}", what, name, list));
    }
  }
}

}  // namespace

const std::vector<std::string>& knob_names() {
  static const std::vector<std::string> names{"contact_law", "shape_resolution", "wall_mesh",
                                              "precision",   "time_step",        "skin"};
  return names;
}

const std::vector<std::string>& scene_names() {
  static const std::vector<std::string> names{"impact", "packing", "drum"};
  return names;
}

std::string study_csv(const StudyResult& result, const StudyOptions& options) {
  std::string text = "# study: talus accuracy against time (experiments/accuracy/README.md)\n";
  text +=
      fmt::format("# machine: {}\n# commit: {}\n# command: {}\n# date: {}\n# backend: {}\n",
                  options.machine, options.commit, options.command, options.date, options.backend);
  text += fmt::format("# size: {}\n", options.quick ? "quick" : "full");
  for (const auto& [scene, noise] : result.noise)
    text += fmt::format("# noise {}: {} (the same error between two seeds of the reference)\n",
                        scene, csv_number(noise));
  for (const std::string& note : result.notes) text += "# " + note + "\n";
  text +=
      "knob,setting,value,scene,metric,reference,error,wall_seconds,simulated_seconds,steps,"
      "particles,precision\n";
  for (const Row& r : result.rows) {
    text += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", r.knob, csv_text(r.setting),
                        csv_number(r.value), r.scene, csv_text(r.metric), csv_text(r.reference),
                        csv_number(r.error), csv_number(r.wall_seconds),
                        csv_number(r.simulated_seconds), r.steps, r.particles, r.precision);
  }
  return text;
}

StudyResult run_study(const StudyOptions& options) {
  check_names(options.scenes, scene_names(), "scene");
  check_names(options.knobs, knob_names(), "knob");
  const auto wanted = [](const std::vector<std::string>& given, const std::string& name) {
    return given.empty() || std::find(given.begin(), given.end(), name) != given.end();
  };
  create_output_directory(options.output_directory, "accuracy output directory");
  StudyResult result;
  result.csv_file = joined_path(options.output_directory, "accuracy.csv");
  const auto save = [&] { write_file_atomically(result.csv_file, study_csv(result, options)); };

  for (const std::string& scene : scene_names()) {
    if (!wanted(options.scenes, scene)) continue;
    const SceneSpec spec = scene_spec(scene, options.quick);
    std::map<std::string, Measured> done;  // by Setting::key: a setting shared by knobs runs once
    int file_number = 0;
    const auto measure = [&](const Setting& s) -> const Measured& {
      auto found = done.find(s.key());
      if (found != done.end()) return found->second;
      const std::string file = fmt::format("{}_{:02d}.yaml", scene, file_number++);
      const Scene built = build_scene(scene, s, options.quick, options.output_directory, file);
      // A law whose advised step makes the run longer than kMaxSteps (the paper's volume law on a
      // bed: its stiffness grows without bound as contacts flatten) is listed, not run.
      const double planned = built.end_time / built.time_step;
      if (planned > kMaxSteps) {
        Measured skipped;
        skipped.skipped = true;
        skipped.wall_seconds = std::nan("");
        skipped.dt = built.time_step;
        skipped.steps = std::llround(planned);
        skipped.particles = built.particles.size();
        skipped.simulated_seconds = built.end_time;
        if (!options.quiet)
          fmt::print(stderr, "talus accuracy: {} {} ({}, dt {:.3g} s): {:.3g} steps, not run\n",
                     scene, file, law_name(s.law), built.time_step, planned);
        return done.emplace(s.key(), std::move(skipped)).first->second;
      }
      Measured m = scene == "impact"    ? run_impact(built, options.quick, options)
                   : scene == "packing" ? run_packing(built, options)
                                        : run_drum(built, options.quick, options);
      if (!options.quiet) {
        fmt::print(stderr,
                   "talus accuracy: {} {} ({}, dt {:.3g} s, {}): {} steps of {} particles in "
                   "{:.3g} s\n",
                   scene, file, law_name(s.law), m.dt, s.single ? "float" : "double", m.steps,
                   m.particles, m.wall_seconds);
      }
      return done.emplace(s.key(), std::move(m)).first->second;
    };
    const bool any_knob = [&] {
      for (const auto& [knob, settings] : spec.knobs)
        if (wanted(options.knobs, knob)) return true;
      return false;
    }();
    if (!any_knob) continue;
    const Measured* reference = nullptr;
    if (scene != "impact") {
      reference = &measure(spec.reference);
      Setting other = spec.reference;
      other.seed = 1;
      result.noise.emplace_back(scene, scene_error(scene, measure(other), *reference));
    } else {
      result.noise.emplace_back(scene, std::nan(""));
    }
    for (const std::string& knob : knob_names()) {
      auto it = spec.knobs.find(knob);
      if (it == spec.knobs.end() || !wanted(options.knobs, knob)) continue;
      for (const KnobSetting& ks : it->second) {
        const Measured& m = measure(ks.setting);
        Row row;
        row.knob = knob;
        row.setting = ks.label;
        row.value = ks.value;
        row.scene = scene;
        row.metric = metric_of(scene, knob);
        row.reference = reference_of(scene, knob, spec.reference);
        if (m.skipped) {
          row.error = std::nan("");  // nothing was measured: no field, no bed, no spin
          row.metric = fmt::format("not run: {} steps of {:.3g} s, over the study's {:g}", m.steps,
                                   m.dt, kMaxSteps);
        } else if (knob == "skin") {
          // The skin changes the work, never the result: against the default skin's run, to the
          // bit where the backend is deterministic.
          const Measured& base = measure(spec.defaults);
          row.reference = "the default skin's run";
          row.metric = "largest relative change of the measured quantity";
          if (scene == "impact") {
            double worst = 0;
            for (std::size_t k = 0; k < m.omega.size(); ++k)
              worst =
                  std::max(worst, std::abs(m.omega[k] - base.omega[k]) / std::abs(base.omega[k]));
            row.error = worst;
          } else {
            row.error = scene_error(scene, m, base);
          }
        } else if (scene == "impact") {
          row.error = impact_error(m, knob == "shape_resolution");
        } else {
          row.error = ks.setting.key() == spec.reference.key() ? std::nan("")
                                                               : scene_error(scene, m, *reference);
        }
        row.wall_seconds = m.wall_seconds;
        row.simulated_seconds = m.simulated_seconds;
        row.steps = m.steps;
        row.particles = m.particles;
        row.precision = ks.setting.single ? "float" : "double";
        result.rows.push_back(row);
        save();
      }
    }
    if (reference) {
      result.notes.push_back(fmt::format(
          "reference {}: {}: {} steps of {} particles, {:.4g} s of wall time for {:.4g} s", scene,
          reference_of(scene, "", spec.reference), reference->steps, reference->particles,
          reference->wall_seconds, reference->simulated_seconds));
    }
    save();
  }
  save();
  return result;
}

}  // namespace talus::accuracy
