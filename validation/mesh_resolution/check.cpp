// Method paper §3.2 (Table 2, Fig. 12): a 25 mm cube slides across plane walls meshed at six
// resolutions lambda = L_c / L_m (Eq. 29); its contact force against kappa = dx / L_c (Eq. 30)
// must not depend on the mesh. README.md here says what is run and why.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "solver/geometry/wall_clip.hpp"
#include "solver/io/output_files.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/shape/mesh_io.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

constexpr double kSide = 0.025;      // L_c, m (Table 2)
constexpr double kDepth = 0.5e-3;    // m: how far the cube's lower face sits below the wall's plane
constexpr double kSpeed = 0.5;       // m/s of the walls under the cube (the paper gives none)
constexpr double kGap = 1e-3;        // m between the cube and the wall's leading edge at the start
constexpr double kSpacing = 0.1;     // m between the lanes (cube and wall) along y
constexpr double kWall = 2 * kSide;  // each wall is 2 L_c long in x: in, across, out
// and a little wider than the cube in y: a planar patch (walls/planar_patch.hpp) holds no disc
// as large as the cube's section circle (radius 18 mm), so the facets are clipped and summed
// with their area weights everywhere, the algorithm the paper's test is about.
constexpr double kWidth = kSide + 2e-3;
constexpr double kReference = 16;  // the finest mesh, against which the others are checked

std::vector<double> resolutions() {
  return {0.5, 1, 2, 4, 8, kReference};
}

// A plane wall [0, kWall] x [0, kWidth] at z = 0 in cells of about L_m = kSide / lambda on a
// side (lambda = L_c / L_m, Eq. 29), each two triangles wound counter-clockwise seen from +z.
std::string wall_obj(double lambda) {
  const int nx = static_cast<int>(std::lround(kWall * lambda / kSide));
  const int ny = std::max(1, static_cast<int>(std::lround(kWidth * lambda / kSide)));
  const double hx = kWall / nx, hy = kWidth / ny;
  std::string text = fmt::format("# plane wall, lambda = {}: {} x {} cells of {} x {} m\n", lambda,
                                 nx, ny, hx, hy);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) text += fmt::format("v {} {} 0\n", i * hx, j * hy);
  }
  const auto at = [nx](int i, int j) { return j * (nx + 1) + i + 1; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      text += fmt::format("f {} {} {}\n", at(i, j), at(i + 1, j), at(i + 1, j + 1));
      text += fmt::format("f {} {} {}\n", at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return text;
}

std::string scene_text(const Quatd& q, double dt, double end) {
  std::string text = fmt::format(
      "# Method paper section 3.2 (Table 2): a 25 mm cube on plane walls meshed at lambda =\n"
      "# L_c / L_m of 0.5 to 16, one lane each along y. Each wall slides under its cube at {} m/s\n"
      "# in -x; the cube's lower face sits {} mm below the wall's plane. Written by\n"
      "# validation/mesh_resolution/check.cpp (talus validate), with the walls' OBJ files.\n"
      "time: {{step: {}, end: {}}}\n\n"
      "materials:\n"
      "  # Table 2's material; the cube's density is 1e9 times Table 2's so that it stays where\n"
      "  # it is put, as the paper moves it: the elastic force does not depend on the mass.\n"
      "  resin: {{density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.8,\n"
      "          restitution: 0.1}}\n"
      "  held: {{density: 1.5e12, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.8,\n"
      "         restitution: 0.1}}\n\n"
      "templates:\n"
      "  cube: {{shape: \"cuboid:{},{},{}\", material: held}}\n\n"
      "particles:\n"
      "  - explicit:\n",
      kSpeed, kDepth * 1e3, dt, end, kSide, kSide, kSide);
  const std::vector<double> lambdas = resolutions();
  for (std::size_t k = 0; k < lambdas.size(); ++k) {
    text += fmt::format(
        "      - {{template: cube, position: [{}, {}, {}], orientation: [{}, {}, {}, {}]}}"
        "  # lambda {}\n",
        -kSide / 2 - kGap, kSpacing * double(k) + kWidth / 2, kSide / 2 - kDepth, q.w, q.x, q.y,
        q.z, lambdas[k]);
  }
  text += "\nwalls:\n";
  for (std::size_t k = 0; k < lambdas.size(); ++k) {
    text += fmt::format(
        "  - mesh: {{name: lambda_{}, file: wall_{}.obj, translation: [0, {}, 0], material: "
        "resin,\n"
        "          motion: {{translation: {{velocity: [{}, 0, 0]}}}}}}\n",
        k, k, kSpacing * double(k), -kSpeed);
  }
  text +=
      "\neffects:\n"
      "  contact: volume\n"
      "  friction: true\n"
      "  rotation: true\n";
  return text;
}

// Without the area weighting (§2.4), each facet that the cube's section touches would give the
// whole section's force (weight 1 instead of its share of the section): the force the same
// contact would give so, over the one with the weights, is (touched facets) / (sum of weights),
// the volume law's facet force being linear in its weight and every facet of a plane wall cutting
// the same section. Clipped here with the production code (wall_clip.hpp) on the cube's pose and
// the wall as it stands; 1 where the cube touches no facet.
double unweighted_over_weighted(const ConvexView<double>& cube, const TrajectoryRow& row,
                                const TriangleMesh& wall) {
  const Posed pose{row.position, row.orientation};
  int touched = 0;
  double weights = 0;
  for (const auto& t : wall.triangles) {
    const WallContact<double> wc = clip_against_triangle_sized(
        cube, pose, wall.vertices[t[0]], wall.vertices[t[1]], wall.vertices[t[2]]);
    if (wc.overlap_area > 0 && wc.section_area > 0 && wc.volume_below > 0) {
      ++touched;
      weights += wc.overlap_area / wc.section_area;
    }
  }
  return weights > 0 ? touched / weights : 1.0;
}

void run_case(const CaseContext& context, CaseResult& result) {
  const ExpectedQuantity& normal_q = context.expected.quantity("normal_force");
  const ExpectedQuantity& tangential_q = context.expected.quantity("tangential_force");
  const ExpectedQuantity& unweighted_q = context.expected.quantity("normal_force_unweighted");
  const std::vector<double> lambdas = resolutions();
  for (std::size_t k = 0; k < lambdas.size(); ++k) {
    write_file_atomically(joined_path(context.output_directory, fmt::format("wall_{}.obj", k)),
                          wall_obj(lambdas[k]));
  }
  const double dt = 1e-5;  // s (Table 2)
  // The force is sampled every this many steps: every 0.2 mm (small) or 0.1 mm (full) of travel.
  const int kSampleSteps = context.full ? 20 : 40;
  // Until the cube has left the wall: kappa from -gap / L_c to 3 and a little more.
  const long long steps =
      std::llround((kGap + 3.1 * kSide) / kSpeed / dt / kSampleSteps) * kSampleSteps;
  const ShapeTemplate cube = make_shape(fmt::format("cuboid:{},{},{}", kSide, kSide, kSide));
  const std::string path = joined_path(context.output_directory, "scene.yaml");
  write_file_atomically(path, scene_text(cube.body_to_input, dt, double(steps) * dt));
  const Scene scene = load_case_scene(path, result);
  std::unique_ptr<AnyStep> step = context.make_step(scene);
  const ShapeArrays<double> cube_arrays(cube);
  const std::vector<WallMesh> meshes = make_wall_meshes(scene);

  // force[k][s]: wall k's force on its cube at sample s (the wall gets the opposite);
  // unweighted[k][s]: its normal force without the area weights.
  const std::size_t n = lambdas.size();
  std::vector<std::vector<Vec3d>> force(n);
  std::vector<std::vector<double>> unweighted(n);
  std::vector<double> kappa;
  double drift = 0;  // the cubes' largest displacement, m
  const std::vector<TrajectoryRow> start = step->rows();
  for (long long s = 1; s <= steps; ++s) {
    step->step();
    if (s % kSampleSteps != 0) continue;
    kappa.push_back((kSpeed * double(s) * dt - kGap) / kSide);
    const std::vector<TrajectoryRow> rows = step->rows();
    const std::vector<TriangleMesh> walls = walls_at(scene, meshes, step->time());
    for (std::size_t k = 0; k < n; ++k) {
      force[k].push_back(-1.0 * step->wall_force(int(k)));
      const TrajectoryRow& row = rows.at(k);  // one cube per lane, in lane order
      unweighted[k].push_back(force[k].back().z *
                              unweighted_over_weighted(cube_arrays.view(), row, walls.at(k)));
    }
  }
  for (const TrajectoryRow& r : step->rows())
    drift = std::max(drift, norm(r.position - start.at(std::size_t(r.id)).position));
  // The force scale: the reference's normal force where the cube is wholly on its wall.
  const std::size_t ref = n - 1;
  double scale = 0;
  for (std::size_t s = 0; s < kappa.size(); ++s) scale = std::max(scale, force[ref][s].z);
  if (!(scale > 0)) throw std::runtime_error("the reference cube felt no force from its wall");
  double worst = 0, worst_kappa = 0, worst_lambda = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::string variant = fmt::format("lambda {}", lambdas[k]);
    for (std::size_t s = 0; s < kappa.size(); ++s) {
      // A copy: the checks added next may move the vector that add_check returned a reference into.
      const Check c = add_check(result, normal_q, kappa[s], force[k][s].z / scale,
                                force[ref][s].z / scale, variant, k == ref);
      add_check(result, tangential_q, kappa[s], force[k][s].x / scale, force[ref][s].x / scale,
                variant, true);
      add_check(result, unweighted_q, kappa[s], unweighted[k][s] / scale, force[ref][s].z / scale,
                variant, true);
      if (c.verdict != Verdict::reported && std::abs(c.measured - c.expected) > worst)
        worst = std::abs(c.measured - c.expected), worst_kappa = kappa[s],
        worst_lambda = lambdas[k];
    }
  }
  result.notes.push_back(fmt::format(
      "{} lanes (lambda {}), dt {} s, {} steps on the {} backend, the force sampled every {} "
      "steps; force scale (the reference's largest normal force) {:.4g} N; the cubes moved "
      "{:.2g} m at most",
      n, fmt::join(lambdas, ", "), dt, steps, context.backend, kSampleSteps, scale, drift));
  result.notes.push_back(fmt::format(
      "largest normal-force difference from lambda {} where checked: {:.3g} of the force scale "
      "(lambda {} at kappa {:.2f})",
      kReference, worst, worst_lambda, worst_kappa));
  std::string off;
  for (std::size_t k = 0; k < n; ++k) {
    double most = 0;
    for (std::size_t s = 0; s < kappa.size(); ++s)
      if (kappa[s] >= 1.02 && kappa[s] <= 1.98) most = std::max(most, unweighted[k][s] / scale);
    off += fmt::format("{}lambda {}: {:.3g}", k ? ", " : "", lambdas[k], most);
  }
  result.notes.push_back(
      "without the area weights (each touched facet giving the whole section's force), the "
      "largest normal force over the force scale where the cube is wholly on the wall: " +
      off);
}

}  // namespace

extern const ValidationCase kMeshResolution{
    "mesh_resolution",
    "Wall mesh resolution (method paper section 3.2, Table 2, Fig. 12)",
    {"normal_force", "tangential_force", "normal_force_unweighted"},
    run_case};

}  // namespace talus::validation
