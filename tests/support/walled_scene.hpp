// A scene of particles resting on moving walls, for the tests of the wall stage's facet grid:
// a drum (axis +y, centred off the origin at (0.1, 0, 0), 3000 rpm about its axis, so that its
// rotation also translates it: p - R p), a plate translating upward at 0.5 m/s, and a hopper
// whose closed outlet opens at 5e-4 s; particles touching each (tests/step/test_wall_grid_step.cpp
// runs the host step with and without the grid, tests/gpu/test_step_gpu.cpp the GPU against the
// host). 200 steps of 1e-5 s.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "solver/scene/scene_loader.hpp"

namespace talus_test {

using talus::Vec3d;

constexpr double kDrumRadius = 0.04, kDrumLength = 0.03;
// The drum's centre, off the origin: its rotation then has a translation part (p - R p), which
// the grid's inverse transform must undo too.
inline const Vec3d kDrumCentre(0.1, 0, 0);
constexpr double kOmega = 3000 * 2 * M_PI / 60;  // the drum's 3000 rpm, rad/s

// Where the particles start: each touching a wall of the scene, from a point
// on the wall (`anchor`) and the direction into it. On the drum's side and caps (two near the
// fan centres), turning with the drum (which keeps those on the side pressed to it), on the
// plate, on the hopper's plate and cone (held by gravity); anchors at least 9 mm apart.
struct Layout {
  std::vector<Vec3d> anchor, into, velocity;
};

inline Layout walled_layout(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  Layout l;
  const auto add = [&](const Vec3d& anchor, const Vec3d& into, const Vec3d& velocity) {
    for (const Vec3d& q : l.anchor)
      if (talus::norm(anchor - q) < 0.009) return;
    l.anchor.push_back(anchor);
    l.into.push_back(into);
    l.velocity.push_back(velocity);
  };
  for (int k = 0; k < 60 && l.anchor.size() < 12; ++k) {  // the drum's side
    const double angle = 2 * M_PI * unit(rng), y = (kDrumLength / 2 - 0.005) * (2 * unit(rng) - 1);
    const Vec3d out(std::cos(angle), 0, std::sin(angle));
    const Vec3d spin = talus::cross(Vec3d(0, kOmega, 0), out);
    add(kDrumCentre + out * kDrumRadius + Vec3d(0, y, 0), out, spin * (kDrumRadius - 0.004));
  }
  for (int k = 0; k < 60 && l.anchor.size() < 18; ++k) {  // the caps
    const double angle = 2 * M_PI * unit(rng), rho = k < 2 ? 0.001 : 0.025 * unit(rng);
    const Vec3d into(0, k % 2 ? 1 : -1, 0);
    const Vec3d out(std::cos(angle), 0, std::sin(angle));
    add(kDrumCentre + into * (kDrumLength / 2) + out * rho, into,
        into * 0.05 + talus::cross(Vec3d(0, kOmega, 0), out) * rho);
  }
  const Vec3d down(0, 0, -1);
  for (const double x : {0.24, 0.25, 0.26}) add(Vec3d(x, 0.004 * unit(rng), 0), down, down * 0.05);
  for (const double x : {-0.005, 0.005}) add(Vec3d(0.35 + x, 0, 0), down, down * 0.05);
  for (const double angle : {0.5, 2.5, 4.5}) {
    // The cone rises 0.03 m while its radius grows from 0.012 to 0.03 m: at 15 mm up, 21 mm.
    const Vec3d out(std::cos(angle), std::sin(angle), 0);
    const Vec3d into = (out * 0.03 + Vec3d(0, 0, -0.018)) * (1 / std::hypot(0.03, 0.018));
    add(Vec3d(0.35, 0, 0.015) + out * 0.021, into, into * 0.05);
  }
  return l;
}

// The scene with the layout's particles (templates in turn, random orientations), each
// moved so that it reaches `depth` past its anchor along `into`: its extent along `into` is the
// largest of its vertices' (a polyhedron) or its radius (a sphere).
inline talus::Scene walled_scene(const std::string& precision, const std::string& contact,
                                 const std::vector<std::string>& templates, int segments = 150) {
  const Layout l = walled_layout(17);
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(0, 1);
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "time: {step: 1.0e-5, end: 2.0e-3}\nprecision: " << precision << R"(
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}
templates:
  cube: {shape: "cube:0.008", material: glass}
  ico: {shape: "icosahedron:0.009", material: glass}
)" << (contact == "volume" ? "" : "  ball: {sphere: 0.004, material: glass}\n")
       << R"(walls:
  - drum: {center: [0.1, 0, 0], axis: [0, 1, 0], radius: 0.04, length: 0.03, segments: )"
       << segments << R"(, material: glass,
           motion: {rotation: {axis: [0, 1, 0], point: [0.1, 0, 0], rpm: 3000}}}
  - plane: {point: [0.25, 0, 0], normal: [0, 0, 1], size: 0.04, material: glass,
            motion: {translation: {velocity: [0, 0, 0.5]}}}
  - hopper: {base: [0.35, 0, 0], axis: [0, 0, 1], bottom_radius: 0.012, top_radius: 0.03,
             height: 0.03, outlet: closed, outlet_opens_at: 5.0e-4, segments: 60,
             material: glass}
particles:
  - explicit:
)";
  for (std::size_t k = 0; k < l.anchor.size(); ++k) {
    const Vec3d& p = l.anchor[k];
    const Vec3d& v = l.velocity[k];
    yaml << "      - {template: " << templates[k % templates.size()] << ", position: [" << p.x
         << ", " << p.y << ", " << p.z << "], velocity: [" << v.x << ", " << v.y << ", " << v.z
         << "], orientation: {axis: [" << unit(rng) - 0.5 << ", 1, " << unit(rng) - 0.5
         << "], degrees: " << 180 * unit(rng) << "}, angular_velocity: [" << 20 * unit(rng)
         << ", 0, " << 20 * unit(rng) << "]}\n";
  }
  yaml << "effects:\n  gravity: [0, 0, -9.81]\n  contact: " << contact
       << "\n  friction: true\n  rotation: true\n";
  talus::Scene scene = talus::parse_scene(yaml.str(), "walled.yaml", ".");
  // About the depth at rest: the weight or the centripetal force over the normal stiffness
  // (deeper, the linear model's soft spring throws the spheres off the walls at once).
  const double depth = contact == "volume" ? 5e-5 : 2e-6;
  for (std::size_t k = 0; k < scene.particles.size(); ++k) {
    talus::ParticleState& p = scene.particles[k];
    const talus::ParticleTemplate& t = scene.templates.at(p.template_index);
    double extent = t.sphere_radius;
    if (t.kind == talus::ParticleShapeKind::polyhedron) {
      extent = 0;
      for (const Vec3d& v : t.shape.vertices) {
        extent =
            std::max(extent, talus::dot(talus::rotate(p.orientation.normalized(), v), l.into[k]));
      }
    }
    p.position = l.anchor[k] - l.into[k] * (extent - depth);
  }
  return scene;
}

}  // namespace talus_test
