// The dynamic hard cases (tests/step/test_hard_cases.cpp on the host, tests/gpu on the GPU):
// flat-faced particles set down or dropped on walls and on each other, which the paper's law
// (Eqs. 12-13) cannot bring to rest at any practical step (its stiffness is unbounded face to
// face; docs/contact.md). Each case is a scene and the times to settle and to watch; `rest_of`
// steps any production step (HostStep, CudaStep) through them and measures.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "solver/scene/scene_loader.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus_test {

using namespace talus;

constexpr double kHardGravity = 9.81;

// 10 mm particles (circumscribed), E = 5 MPa, density 1200, nu = 0.3, mu = 0.4, eps = 0.5, with
// friction and rotation, on walls of the same material.
inline std::string hard_scene(double dt, const std::string& templates, const std::string& particles,
                              const std::string& walls) {
  char step[40];
  std::snprintf(step, sizeof step, "%.17g", dt);
  return std::string("time: {step: ") + step +
         ", end: 100}\n"
         "materials:\n"
         "  grain: {density: 1200, youngs_modulus: 5.0e6, poisson_ratio: 0.3, friction: 0.4,\n"
         "          restitution: 0.5}\n"
         "templates:\n" +
         templates + "particles:\n  - explicit:\n" + particles + "walls:\n" + walls +
         "effects:\n"
         "  gravity: [0, 0, -9.81]\n"
         "  contact: volume\n"
         "  friction: true\n"
         "  rotation: true\n";
}

inline std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

inline std::string particle(const std::string& name, double z, const std::string& orientation = "",
                            double x = 0) {
  return "      - {template: " + name + ", position: [" + number(x) + ", 0, " + number(z) + "]" +
         (orientation.empty() ? "" : ", orientation: " + orientation) + "}\n";
}

// A particle of `spec` lying on its largest (or smallest) face, that face's plane `gap` above
// height `base`: the orientation turning the face's outward normal onto -z, and the centre at the
// face's offset above it; then all of it turned by `tilt` about the origin (an incline). The
// template's body frame is its principal axes, which the builder chooses, so the orientation is
// found from the template rather than written by hand.
inline std::string lying(const std::string& name, const std::string& spec, bool largest,
                         double base, double gap, const Quatd& tilt = Quatd()) {
  const ShapeTemplate shape = make_shape(spec);
  const auto area = [&](const Face& f) {  // of the face's polygon, by its fan
    Vec3d sum;
    for (std::size_t k = 1; k + 1 < f.loop.size(); ++k)
      sum += cross(shape.vertices[f.loop[k]] - shape.vertices[f.loop[0]],
                   shape.vertices[f.loop[k + 1]] - shape.vertices[f.loop[0]]);
    return 0.5 * norm(sum);
  };
  const Face* pick = &shape.faces[0];
  for (const Face& f : shape.faces)
    if (largest ? area(f) > area(*pick) + 1e-12 : area(f) < area(*pick) - 1e-12) pick = &f;
  const Vec3d down(0, 0, -1);
  Vec3d axis = cross(pick->normal, down);
  const double angle = std::atan2(norm(axis), dot(pick->normal, down));
  if (norm(axis) < 1e-12) axis = std::abs(pick->normal.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  const Quatd q = (tilt * Quatd::from_axis_angle(axis / norm(axis), angle)).normalized();
  const Vec3d centre = rotate(tilt, Vec3d(0, 0, base + gap + pick->offset));
  return "      - {template: " + name + ", position: [" + number(centre.x) + ", " +
         number(centre.y) + ", " + number(centre.z) + "], orientation: [" + number(q.w) + ", " +
         number(q.x) + ", " + number(q.y) + ", " + number(q.z) + "]}\n";
}

struct HardCase {
  std::string name;
  std::string yaml;              // at dt = 1e-5 s
  double settle = 0, check = 0;  // s: run `settle`, then measure over `check` more
};
// GoogleTest prints a parameter by its name.
inline void PrintTo(const HardCase& c, std::ostream* os) {
  *os << c.name;
}

// The cases. Settling times are what each needs at dt = 1e-5 s with margin. The column's sway (a
// 5.8 cm tower on a 5.8 mm face, about 30 Hz) is damped only by its contacts' rocking dashpots
// (c_n A_n / 12, made for one cube's mass): its kinetic energy falls by about 10 in 2 s and its
// drift stays under 1e-9 m over a second after some 20 s.
inline std::vector<HardCase> hard_cases() {
  const std::string cube = "  cube: {shape: \"cube:0.01\", material: grain}\n";
  const std::string tetra = "  tetra: {shape: \"tetrahedron:0.01\", material: grain}\n";
  const std::string cylinder =
      "  cylinder: {shape: \"cylinder:0.008,0.0053,80\", material: grain}\n";
  const std::string cylinder_spec = "cylinder:0.008,0.0053,80";
  const std::string floor =
      "  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 0.2, material: grain}\n";
  const double edge = 0.01 / std::sqrt(3.0);
  std::vector<HardCase> cases;
  const auto add = [&](const std::string& name, const std::string& templates,
                       const std::string& particles, const std::string& walls, double settle) {
    cases.push_back({name, hard_scene(1e-5, templates, particles, walls), settle, 1.0});
  };
  add("CubeFaceDownOnAPlane", cube, lying("cube", "cube:0.01", true, 0, 1e-4), floor, 1.0);
  add("CubeFaceDownOnACube", cube,
      lying("cube", "cube:0.01", true, 0, 1e-5) + lying("cube", "cube:0.01", true, edge, 1e-4),
      floor, 1.0);
  std::string column;
  for (int k = 0; k < 10; ++k) column += lying("cube", "cube:0.01", true, k * (edge + 1e-4), 1e-4);
  add("ColumnOfTenCubes", cube, column, floor, 25.0);
  add("TetrahedronFaceDown", tetra, lying("tetra", "tetrahedron:0.01", true, 0, 1e-4), floor, 1.0);
  // Vertex-first: a face turned up by a half turn about a horizontal axis slightly off, so that
  // it does not land balanced; dropped from 2 cm, it topples onto a face.
  add("TetrahedronDroppedVertexFirst", tetra,
      particle("tetra", 0.02, "{axis: [1, 0.3, 0.05], degrees: 170}"), floor, 1.0);
  add("CylinderOnItsEndOnAPlane", cylinder, lying("cylinder", cylinder_spec, true, 0, 1e-4), floor,
      1.0);
  add("CylinderOnItsSideOnAPlane", cylinder, lying("cylinder", cylinder_spec, false, 0, 1e-4),
      floor, 1.0);
  add("CylinderOnItsEndOnACylinder", cylinder,
      lying("cylinder", cylinder_spec, true, 0, 1e-5) +
          lying("cylinder", cylinder_spec, true, 0.0053, 1e-4),
      floor, 0.5);
  // 15 degrees, below the friction angle atan(0.4) = 21.8 degrees: friction holds it.
  const Quatd tilt = Quatd::from_axis_angle(Vec3d(0, -1, 0), 15.0 * M_PI / 180);
  const Vec3d normal = rotate(tilt, Vec3d(0, 0, 1));
  add("CubeOnAnInclineBelowTheFrictionAngle", cube, lying("cube", "cube:0.01", true, 0, 1e-5, tilt),
      "  - plane: {point: [0, 0, 0], normal: [" + number(normal.x) + ", 0, " + number(normal.z) +
          "], size: 0.2, material: grain}\n",
      1.0);
  return cases;
}

struct RestMeasure {
  double kinetic_settled = 0;  // J, at the end of the settling time
  double kinetic_end = 0;      // J, after the check time
  double drift = 0;            // m, the largest displacement of a particle over the check
  double floor_force = 0;      // the walls' total force along +z / the total weight
  double lowest = 0;           // m, the lowest particle centre (nothing fell through)
  double weight = 0;           // N, of all the particles
};

// Steps `step` (HostStep or CudaStep of `scene`) for `settle` s, then `check` s more, measuring.
template <class Step>
RestMeasure rest_of(Step& step, const Scene& scene, double settle, double check) {
  const auto run_to = [&](double t) {
    while (step.time() < t - 0.5 * scene.time_step) step.step();
  };
  run_to(settle);
  RestMeasure r;
  r.kinetic_settled = step.kinetic_energy();
  const std::vector<TrajectoryRow> start = step.trajectory_rows();
  run_to(settle + check);
  r.kinetic_end = step.kinetic_energy();
  const std::vector<TrajectoryRow> end = step.trajectory_rows();
  r.lowest = 1e9;
  for (std::size_t i = 0; i < end.size(); ++i) {
    r.drift = std::max(r.drift, norm(end[i].position - start[i].position));
    r.lowest = std::min(r.lowest, end[i].position.z);
    const ParticleTemplate& t = scene.templates[end[i].template_index];
    r.weight += scene.materials[t.material].density * t.volume * kHardGravity;
  }
  for (std::size_t w = 0; w < scene.walls.size(); ++w)
    r.floor_force -= step.wall_force(static_cast<int>(w)).z;  // the force on the wall: down
  r.floor_force /= r.weight;
  return r;
}

}  // namespace talus_test
