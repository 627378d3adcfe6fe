// BLAZE-DEM §5.2 (Figs. 14-15): a lattice of 8-face polyhedra (octahedra) falls into a
// container under gravity, once with talus's default volume law and once with BLAZE-DEM's linear
// law; the kinetic energy must die away (Fig. 15), the volume law's energy balance must hold
// (nothing gains energy it was not given; the linear law's is reported), and the final packing
// fraction is reported. README.md here says what is run and why.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "solver/io/checkpoint.hpp"
#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

constexpr double kSize = 0.01;      // m, the octahedra's circumscribed diameter
constexpr double kSpacing = 0.015;  // m between lattice points (BLAZE-DEM: 128 across 2 m)
constexpr double kLift = 0.01;      // m from the floor to the lattice's lowest layer (the paper's)
// s: a linear-law contact (K_N = 1e4 N/m, 0.42 g) lasts 32 steps, and the volume law's step is
// 0.4 of its critical one (the advisor's 4.8e-5 s at E = 5 MPa)
constexpr double kStep = 2e-5;
constexpr int kSamples = 100;  // energy samples over the run
// Steps between the run's resume points (below): at 1e6 particles about 100 s of an H200's time
// once the bed forms, the saving a second or two.
constexpr long long kResumeEvery = 5000;
constexpr long long kProgressEvery = 1000;  // steps between progress lines on stderr (full only)

struct Grid {
  int nx, ny, nz;
  double duration;  // s: the paper shows 1 s; each bed is at rest well before its end
};

// The two laws: BLAZE-DEM's linear spring-dashpot (K_N, eta, gamma), the paper's, and the
// default volume law, each with its grid for the small (CI) and the full version. Full: the
// paper's 128 x 128 x 64 for 1 s (its Fig. 14's instant) under the linear law; the volume law on
// the same footprint eight layers deep, since its million-particle pour costs over 20 ms a step
// on an H200 once the bed forms (README.md): both at a million would take longer than a
// session's lease of the GPU machine.
struct Law {
  const char* name;
  const char* yaml;  // effects.contact
  Grid small, full;
};
const Law kLaws[] = {
    {"linear",
     "{model: linear, stiffness: 1.0e4, damping: 0.5, tangential_damping: 0.5}",
     {3, 3, 12, 0.5},
     {128, 128, 64, 1.0}},
    {"volume", "volume", {3, 3, 12, 0.5}, {128, 128, 8, 0.6}},
};

std::string scene_text(const Grid& g, const char* law) {
  // The lattice puts n points where n spacings fit (min + spacing (i + 1/2)): its box is a
  // quarter spacing longer than n spacings on each axis, the container half a spacing.
  const double bottom = kLift + kSize / 2 - kSpacing / 2;  // the lowest layer's vertex at kLift
  const auto region = [](int n) { return (n + 0.25) * kSpacing; };
  const double wx = (g.nx + 0.5) * kSpacing, wy = (g.ny + 0.5) * kSpacing;
  const double top = bottom + region(g.nz);
  return fmt::format(
      "# BLAZE-DEM section 5.2: {} x {} x {} octahedra of {} mm falling from rest into a\n"
      "# container. Written by validation/gravity_packing/check.cpp\n"
      "# (talus validate).\n"
      "time: {{step: {}, end: {}}}\n"
      "seed: 52\n\n"
      "materials:\n"
      "  glass: {{density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.25, friction: 0.4,\n"
      "          restitution: 0.5}}\n\n"
      "templates:\n"
      "  octahedron: {{shape: \"octahedron:{}\", material: glass}}\n\n"
      "particles:\n"
      "  - lattice:\n"
      "      template: octahedron\n"
      "      region: {{box: {{min: [0, 0, {}], max: [{}, {}, {}]}}}}\n"
      "      spacing: {}\n"
      "      random_orientation: true\n"
      "      seed: 7\n\n"
      "walls:\n"
      "  - box: {{name: container, min: [0, 0, 0], max: [{}, {}, {}], open_top: true,\n"
      "           material: glass}}\n\n"
      "effects:\n"
      "  gravity: [0, 0, -9.81]\n"
      "  contact: {}\n"
      "  friction: true\n"
      "  rotation: true\n\n"
      "outputs:\n"
      "  probes: {{every: {}, file: probes.csv, quantities: [kinetic_energy, energy]}}\n",
      g.nx, g.ny, g.nz, kSize * 1e3, kStep, g.duration, kSize, bottom, region(g.nx), region(g.ny),
      top, kSpacing, wx, wy, top + kSpacing, law, std::llround(g.duration / kStep / kSamples));
}

void pour(const CaseContext& context, CaseResult& result, const Grid& grid, const char* name,
          const char* law) {
  const ExpectedQuantity& rest_q = context.expected.quantity("kinetic_fraction_end");
  const ExpectedQuantity& gain_q = context.expected.quantity("energy_gain");
  const ExpectedQuantity& fraction_q = context.expected.quantity("packing_fraction");
  const ExpectedQuantity& ke_q = context.expected.quantity("kinetic_energy");
  const std::string path =
      joined_path(context.output_directory, fmt::format("scene_{}.yaml", name));
  write_file_atomically(path, scene_text(grid, law));
  const Scene scene = load_case_scene(path, result);
  std::unique_ptr<AnyStep> step = context.make_step(scene);
  const std::size_t n = step->particles();
  const long long steps = std::llround(grid.duration / kStep);
  const long long every = steps / kSamples;
  const EnergyTerms initial = step->energy();
  // What the run has found so far, and the kinetic energy at each sample (time, J).
  struct Progress {
    long long step = 0;   // the last step done
    double peak = 0;      // the largest kinetic energy, J
    double gain = 0;      // the largest rise of the balance, J
    double balance0 = 0;  // the balance at the start, J
    double gravity0 = 0;  // the gravitational energy at the start, J
  } state{0, 0, 0, initial.balance(), initial.gravitational};
  std::vector<double> samples;
  // The run resumes from `<law>.resume` when an earlier run of the same scene into the same
  // output directory was cut off (a GPU machine's calls are limited to minutes; the full pour
  // takes longer), and keeps one every kResumeEvery steps; the case removes them once it is done.
  const std::string resume = joined_path(context.output_directory, fmt::format("{}.resume", name));
  const std::string scene_file = read_input_file(path);
  if (std::filesystem::exists(resume)) {
    const Checkpoint saved = read_checkpoint(resume);
    if (saved.text("validation_scene") == scene_file) {
      step->restore_state(saved);
      state = saved.get_value<Progress>("validation_state");
      samples = saved.get<double>("validation_samples");
      result.notes.push_back(
          fmt::format("{} law: resumed at step {} from {}", name, state.step, resume));
    }
  }
  const auto save = [&] {
    Checkpoint c;
    step->save_state(c);
    c.put_text("validation_scene", scene_file);
    c.put_value("validation_state", state);
    c.put("validation_samples", samples);
    write_checkpoint(resume, c);
  };
  using Clock = std::chrono::steady_clock;
  const Clock::time_point started = Clock::now();
  const long long first = state.step;
  for (long long s = state.step + 1; s <= steps; ++s) {
    step->step();
    state.step = s;
    if (s % every == 0) {
      const EnergyTerms e = step->energy();
      state.peak = std::max(state.peak, e.kinetic());
      state.gain = std::max(state.gain, e.balance() - state.balance0);
      samples.push_back(double(s) * kStep);
      samples.push_back(e.kinetic());
    }
    if (s % kResumeEvery == 0 || s == steps) save();
    // A line now and then, so that whoever waits on the full run sees it move and what a step
    // costs (the stages' device seconds so far, stage_timer.cuh).
    if (context.full && !context.quiet && s % kProgressEvery == 0) {
      const double wall = std::chrono::duration<double>(Clock::now() - started).count();
      std::string stages;
      const StageSeconds& t = step->stage_seconds();
      for (int k = 0; k < kStageCount; ++k)
        stages += fmt::format(" {} {:.3g}", to_string(static_cast<Stage>(k)), t[k]);
      std::fprintf(stderr,
                   "talus validate: gravity_packing %s: step %lld of %lld, %.1f s, %.2f ms a "
                   "step; kinetic energy %.4g J; %zu pair and %zu wall contacts; stages (s):%s\n",
                   name, s, steps, wall, 1e3 * wall / double(s - first), step->kinetic_energy(),
                   step->pair_contacts(), step->wall_contacts(), stages.c_str());
    }
  }
  const double peak = state.peak, gain = state.gain;
  for (std::size_t k = 0; k + 1 < samples.size(); k += 2)
    add_check(result, ke_q, samples[k], samples[k + 1], 0, name, true);
  const double kinetic = samples.empty() ? 0.0 : samples.back();
  const EnergyTerms end = step->energy();
  const double released = state.gravity0 - end.gravitational;
  if (!(released > 0)) throw std::runtime_error("the particles did not fall");
  add_check(result, rest_q, grid.duration, kinetic / peak, 0, name);
  // The linear law's point force is not the gradient of its energy (README.md here): reported.
  add_check(result, gain_q, grid.duration, gain / released, 0, name, std::string(name) == "linear");
  // The packing: the particles' volume over the container's floor times the bed's height, taken
  // as twice the mean height of the centres (a flat bed's centres average half its height).
  double mean_z = 0;
  for (const TrajectoryRow& r : step->rows()) mean_z += r.position.z;
  mean_z /= double(n);
  const ParticleTemplate& t = scene.templates.at(0);
  const double area = (grid.nx + 0.5) * kSpacing * (grid.ny + 0.5) * kSpacing;
  const double fraction = double(n) * t.volume / (area * 2 * mean_z);
  add_check(result, fraction_q, 2 * mean_z, fraction, 0, name, true);
  add_check(result, context.expected.quantity("particles"), grid.duration, double(n), 0, name,
            true);
  const double wall = std::chrono::duration<double>(Clock::now() - started).count();
  result.notes.push_back(fmt::format(
      "{} law: {} octahedra ({} x {} x {}), dt {} s, {} steps on the {} backend; energy "
      "released {:.4g} J, kinetic energy at most {:.4g} J and {:.3g} J at {} s; dissipated "
      "{:.4g} J; the balance (held + dissipated) rose by {:.3g} J at most; the centres' mean "
      "height {:.4g} m, packing fraction {:.3f}; {:.1f} s of wall time for its {} steps{}",
      name, n, grid.nx, grid.ny, grid.nz, kStep, steps, context.backend, released, peak, kinetic,
      grid.duration, end.ledger.dissipated, gain, mean_z, fraction, wall, steps - first,
      first > 0 ? " after the resume" : ""));
}

void run_case(const CaseContext& context, CaseResult& result) {
  // Small (CI): 108 particles, a bed about 4 layers deep; full: kLaws.
  for (const Law& law : kLaws)
    pour(context, result, context.full ? law.full : law.small, law.name, law.yaml);
  for (const Law& law : kLaws)  // done: a later run starts afresh
    std::remove(joined_path(context.output_directory, fmt::format("{}.resume", law.name)).c_str());
}

}  // namespace

extern const ValidationCase kGravityPacking{
    "gravity_packing",
    "Gravity packing of octahedra (BLAZE-DEM section 5.2, Figs. 14-15)",
    {"kinetic_energy", "kinetic_fraction_end", "energy_gain", "packing_fraction", "particles"},
    run_case};

}  // namespace talus::validation
