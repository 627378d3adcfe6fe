// Method paper §3.3: 63 dodecahedra poured into a 10 cm tube settle into a bed about 16 cm high.
// The built-in scene over several seeds (its random fill's), the bed height of each and their
// mean against the paper's, and how still each bed is at the end. README.md here.
#include <cmath>
#include <cstring>
#include <numeric>

#include <fmt/format.h>

#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"
#include "solver/scene/scene_loader.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

constexpr char kSeedLine[] = "\nseed: 33\n";  // scene.yaml's, replaced per seed
constexpr char kTimeLine[] = "\ntime: {step: 4.0e-5, end: 0.7}\n";  // and its step, per run

// Potential energy of the particles in gravity g, J (m g . x summed; x measured from the origin).
double potential(const Scene& scene, const std::vector<TrajectoryRow>& rows, const Vec3d& g) {
  double u = 0;
  for (const TrajectoryRow& r : rows) {
    const ParticleTemplate& t = scene.templates.at(r.template_index);
    const double mass = scene.materials.at(t.material).density * t.volume;
    u -= mass * dot(g, r.position);
  }
  return u;
}

void pour(const CaseContext& context, CaseResult& result, const std::string& text, double dt,
          const std::string& suffix, const std::vector<int>& seeds) {
  const ExpectedQuantity& height_q = context.expected.quantity("bed_height" + suffix);
  const ExpectedQuantity& mean_q = context.expected.quantity("mean_bed_height" + suffix);
  const ExpectedQuantity& rest_q = context.expected.quantity("kinetic_fraction" + suffix);
  std::vector<double> heights;
  for (int seed : seeds) {
    std::string seeded = text;
    seeded.replace(seeded.find(kSeedLine), std::string(kSeedLine).size(),
                   fmt::format("\nseed: {}\n", seed));
    seeded.replace(seeded.find(kTimeLine), std::string(kTimeLine).size(),
                   fmt::format("\ntime: {{step: {}, end: 0.7}}\n", dt));
    const std::string path =
        joined_path(context.output_directory, fmt::format("scene{}_seed{}.yaml", suffix, seed));
    write_file_atomically(path, seeded);
    const Scene scene = load_case_scene(path, result);
    const Vec3d g = scene.effects.gravity.value();
    std::unique_ptr<AnyStep> step = context.make_step(scene);
    const double u0 = potential(scene, step->rows(), g);
    const long long steps = std::llround(scene.end_time / dt);
    for (long long k = 0; k < steps; ++k) step->step();
    const double height = step->bed_height(g);
    const double released = u0 - potential(scene, step->rows(), g);
    const double kinetic = step->kinetic_energy();
    heights.push_back(height);
    // The bed as a camera beside the tube sees it (the paper's Fig. 13b), one per seed.
    write_particle_picture(
        scene, step->rows(), scene.end_time, "y", 360, 360,
        joined_path(context.output_directory, fmt::format("bed{}_seed{}.png", suffix, seed)));
    add_check(result, height_q, seed, height, 0.16);
    add_check(result, rest_q, seed, kinetic / released, 0);
    result.notes.push_back(fmt::format(
        "seed {}, dt {} s ({} steps on the {} backend): bed {:.1f} cm; kinetic energy {:.2g} J "
        "of the {:.3g} J released",
        seed, dt, steps, context.backend, 100 * height, kinetic, released));
  }
  const double n = double(heights.size());
  const double mean = std::accumulate(heights.begin(), heights.end(), 0.0) / n;
  double spread = 0;
  for (double h : heights) spread += (h - mean) * (h - mean);
  spread = heights.size() > 1 ? std::sqrt(spread / (n - 1)) : 0;
  add_check(result, mean_q, n, mean, 0.16);
  result.notes.push_back(fmt::format(
      "dt {} s: mean bed height over {} seeds {:.2f} cm, standard deviation {:.2f} cm (paper: "
      "about 16 cm)",
      dt, heights.size(), 100 * mean, 100 * spread));
}

void run_case(const CaseContext& context, CaseResult& result) {
  const std::string text = read_input_file(joined_path(context.case_directory, "scene.yaml"));
  if (text.find(kSeedLine) == std::string::npos)
    throw ValidationError(context.case_directory +
                          "/scene.yaml: expected a line 'seed: 33', "
                          "which the checker replaces by each seed");
  if (context.full) {
    pour(context, result, text, 4e-5, "_dt4e-5", {33, 34, 35, 36, 37});
    pour(context, result, text, 1e-5, "_dt1e-5", {33, 34, 35, 36, 37});
  } else {
    pour(context, result, text, 4e-5, "_dt4e-5", {33, 34, 35});
  }
}

}  // namespace

extern const ValidationCase kDodecahedronPacking{
    "dodecahedron_packing",
    "Dodecahedron packing in a tube (method paper section 3.3)",
    {"bed_height_dt4e-5", "mean_bed_height_dt4e-5", "kinetic_fraction_dt4e-5", "bed_height_dt1e-5",
     "mean_bed_height_dt1e-5", "kinetic_fraction_dt1e-5"},
    run_case};

}  // namespace talus::validation
