// Method paper §3.1 (Table 1, Fig. 10): a cylinder strikes a plane wall with a rim corner first,
// frictionless and without gravity; its angular velocity and normal velocity after the impact
// against Eqs. 27-28 over the impact angle theta. README.md here says what is run and why.
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "solver/io/output_files.hpp"
#include "solver/shape/mesh_io.hpp"
#include "validation/framework/validation.hpp"

namespace talus::validation {
namespace {

constexpr char kShape[] = "cylinder:0.008,0.0053";  // D = 8 mm, L = 5.3 mm: 42 vertices, 80 faces
constexpr double kDensity = 1245;                   // kg/m^3 (Table 1)
constexpr double kRestitution = 0.85;               // (Table 1)
constexpr double kSpeed =
    1.0;                       // m/s towards the wall; Table 1 gives none, Eqs. 27-28 scale with it
constexpr double kGap = 1e-7;  // m between the corner and the wall at the start
constexpr double kSpacing = 0.02;  // m between the cylinders along y (8 mm wide, moving in x-z)
constexpr double kPi = 3.14159265358979323846;
// Steps after the velocity last changed before an impact counts as over: a contact's force is
// never exactly zero for three steps in a row while the overlap lasts.
constexpr int kQuietSteps = 3;
constexpr long long kMaxSteps = 100000;  // 0.01 s at 1e-7 s: an impact lasts well under 1 ms

std::vector<double> sweep(bool full) {
  std::vector<double> thetas;
  const double step = full ? 1 : 5;  // degrees: Fig. 10's 5, or 1 for the full version
  for (double t = 5; t <= 85 + 1e-9; t += step) thetas.push_back(t);
  return thetas;
}

Quatd about(const Vec3d& axis, double radians) {
  const double s = std::sin(radians / 2);
  return {std::cos(radians / 2), axis.x * s, axis.y * s, axis.z * s};
}

// Numbers in the scene text are fmt's shortest that read back to the same double.

// Each cylinder's pose: the body frame has the axis along z (the largest principal moment); a
// rim corner C of the -z face is turned to +x about z, then the body is tilted by theta about y,
// which brings C lowest, at r (cos(alpha + theta), 0, -sin(alpha + theta)) from the centre (the
// paper's Fig. 9 with tan alpha = (L/2) / (D/2)).
struct Placed {
  double theta_deg;
  Quatd orientation;
  Vec3d position;
  Vec3d corner;  // C, the lowest vertex, from the centre (world frame)
};

std::vector<Placed> place(const ShapeTemplate& shape, const std::vector<double>& thetas) {
  int corner = -1;
  for (int i = 0; i < static_cast<int>(shape.vertices.size()); ++i) {
    const Vec3d& p = shape.vertices[i];
    if (p.z < 0 && (corner < 0 || norm(p) > norm(shape.vertices[corner]) + 1e-12)) corner = i;
  }
  const Vec3d c = shape.vertices[corner];
  const Quatd to_x = about({0, 0, 1}, -std::atan2(c.y, c.x));
  std::vector<Placed> placed;
  for (std::size_t k = 0; k < thetas.size(); ++k) {
    const Quatd q = about({0, 1, 0}, thetas[k] * kPi / 180) * to_x;
    Vec3d lowest;
    for (const Vec3d& v : shape.vertices) {
      const Vec3d r = rotate(q, v);
      if (r.z < lowest.z) lowest = r;
    }
    placed.push_back({thetas[k], q, {0, kSpacing * double(k), -lowest.z + kGap}, lowest});
  }
  return placed;
}

std::string scene_text(const std::vector<Placed>& placed, double dt, bool full) {
  std::string text = fmt::format(
      "# Method paper section 3.1 (Table 1): {} cylinders, each striking the plane with a rim\n"
      "# corner first at its own angle theta ({} to {} degrees by {}), frictionless, no "
      "gravity.\n"
      "# Written by validation/cylinder_wall_impact/check.cpp (talus validate); the committed\n"
      "# scene.yaml is the small version, and the validation test checks that they agree.\n"
      "time: {{step: {}, end: {}}}\n\n"
      "materials:\n"
      "  resin: {{density: {}, youngs_modulus: 1.15e9, poisson_ratio: 0.35, friction: 0.0,\n"
      "          restitution: {}}}\n\n"
      "templates:\n"
      "  cylinder: {{shape: \"{}\", material: resin}}\n\n"
      "particles:\n"
      "  - explicit:\n",
      placed.size(), placed.front().theta_deg, placed.back().theta_deg, full ? 1 : 5, dt,
      dt * double(kMaxSteps), kDensity, kRestitution, kShape);
  for (const Placed& p : placed) {
    text += fmt::format(
        "      - {{template: cylinder, position: [{}, {}, {}],  # theta {} degrees\n"
        "         orientation: [{}, {}, {}, {}], velocity: [0, 0, {}]}}\n",
        p.position.x, p.position.y, p.position.z, p.theta_deg, p.orientation.w, p.orientation.x,
        p.orientation.y, p.orientation.z, -kSpeed);
  }
  const double span = kSpacing * double(placed.size() - 1);
  text += fmt::format(
      "\nwalls:\n"
      "  - plane: {{point: [0, {}, 0], normal: [0, 0, 1], size: {}, material: resin}}\n\n"
      "effects:\n"
      "  contact: volume_paper\n"
      "  friction: false\n"
      "  rotation: true\n",
      span / 2, span + 0.1);
  return text;
}

struct Impact {
  int state = 0;  // 0 before, 1 in contact, 2 over
  long long steps = 0;
  int quiet = 0;
  double last_vz = 0;
  Vec3d velocity, angular_velocity;  // after the impact, world frame
};

void run_case(const CaseContext& context, CaseResult& result) {
  const ExpectedQuantity& omega_q = context.expected.quantity("omega_plus");
  const ExpectedQuantity& vz_q = context.expected.quantity("v_z_plus");
  const ShapeTemplate shape = make_shape(kShape);
  const std::vector<Placed> placed = place(shape, sweep(context.full));
  // Table 1 has 5e-7 s; the advisor bounds this law's step by its cylinder-cylinder contacts at
  // 1.2e-7 s (docs/contact.md), so 1e-7 s: finer, never coarser than the paper's.
  const double dt = 1e-7;
  const std::string path = joined_path(context.output_directory, "scene.yaml");
  write_file_atomically(path, scene_text(placed, dt, context.full));
  const Scene scene = load_case_scene(path, result);
  std::unique_ptr<AnyStep> step = context.make_step(scene);

  const std::size_t n = placed.size();
  std::vector<Impact> impacts(n);
  for (Impact& i : impacts) i.last_vz = -kSpeed;
  long long steps = 0;
  std::size_t over = 0;
  while (over < n && steps < kMaxSteps) {
    step->step();
    ++steps;
    for (const TrajectoryRow& row : step->rows()) {
      Impact& i = impacts.at(static_cast<std::size_t>(row.id));
      const bool changed = row.velocity.z != i.last_vz;
      i.last_vz = row.velocity.z;
      if (i.state == 0 && changed) i.state = 1;
      if (i.state != 1) continue;
      ++i.steps;
      i.quiet = changed ? 0 : i.quiet + 1;
      if (i.quiet >= kQuietSteps) {
        i.state = 2;
        i.steps -= kQuietSteps;
        i.velocity = row.velocity;
        i.angular_velocity = row.angular_velocity;
        ++over;
      }
    }
  }
  const double mass = kDensity * shape.volume;
  long long fewest = kMaxSteps, most = 0;
  double off_plane = 0;  // the largest |omega_x|, |omega_z| after an impact, rad/s
  for (std::size_t k = 0; k < n; ++k) {
    const Impact& i = impacts[k];
    if (i.state != 2) {
      throw std::runtime_error(
          fmt::format("the cylinder at theta {} degrees was still in contact after {} steps",
                      placed[k].theta_deg, steps));
    }
    // Eqs. 27-28 from the start pose: the corner's lever arm r cos(alpha + theta) is its x
    // offset from the centre, I_yy the moment about the world y axis (a transverse principal
    // axis: the tilt is about y).
    const double arm = placed[k].corner.x;
    const Mat3<double> rot = rotation_matrix(placed[k].orientation);
    double i_yy = 0;
    const double moments[3] = {shape.principal_moments.x, shape.principal_moments.y,
                               shape.principal_moments.z};
    for (int a = 0; a < 3; ++a) i_yy += kDensity * moments[a] * rot.m[1][a] * rot.m[1][a];
    const double omega = mass * kSpeed * (1 + kRestitution) * arm / (i_yy + mass * arm * arm);
    const double v_z = omega * arm - kRestitution * kSpeed;  // Eq. 28
    // The paper's frame has z into the wall: V_z^- = +V, and omega_y^+ > 0 for a corner on +x.
    add_check(result, omega_q, placed[k].theta_deg, -i.angular_velocity.y, omega);
    add_check(result, vz_q, placed[k].theta_deg, -i.velocity.z, v_z);
    fewest = std::min(fewest, i.steps);
    most = std::max(most, i.steps);
    off_plane =
        std::max({off_plane, std::abs(i.angular_velocity.x), std::abs(i.angular_velocity.z)});
  }
  result.notes.push_back(fmt::format(
      "{} cylinders (theta {} to {} degrees), dt {} s, {} steps on the {} backend; each impact "
      "lasted {} to {} steps; m = {:.4g} kg, I_yy = {:.4g} kg m^2 (Table 1: 2.047e-9)",
      n, placed.front().theta_deg, placed.back().theta_deg, dt, steps, context.backend, fewest,
      most, mass, kDensity * shape.principal_moments.x));
  result.notes.push_back(fmt::format(
      "out of the impact plane after the impacts: |omega_x|, |omega_z| at most {:.2g} rad/s",
      off_plane));
}

}  // namespace

extern const ValidationCase kCylinderWallImpact{
    "cylinder_wall_impact",
    "Cylinder-wall impact (method paper section 3.1, Table 1, Fig. 10)",
    {"omega_plus", "v_z_plus"},
    run_case};

}  // namespace talus::validation
