// Walls of the reference solver (paper §2.4): triangle meshes given in world coordinates at t = 0
// and a rigid motion. A wall is infinitely large in mass and rigid: it is never moved by the
// contacts, only by its prescribed motion.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace talus::reference {

struct RefWallMotion {
  enum class Kind { kNone, kRotation, kTranslation, kOscillation };
  Kind kind = Kind::kNone;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();     // rotation: unit axis through `point`
  Eigen::Vector3d point = Eigen::Vector3d::Zero();     // rotation axis point; torque reference
  double angular_speed = 0;                            // rad/s, right-handed about `axis`
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // translation, m/s
  // Oscillation: the shift along the unit `axis` is s(t) = amplitude (1 - cos w (t - start)),
  // w = 2 pi frequency, while 0 < t - start < cycles / frequency (cycles 0: without end), else 0.
  double amplitude = 0, frequency = 0, start = 0;
  int cycles = 0;

  // Where the material point at x0 (t = 0) is at time t, and the velocity of the wall's material
  // point that is at x at time t.
  Eigen::Vector3d position(const Eigen::Vector3d& x0, double t) const;
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& x, double t) const;
  // The wall's angular velocity, rad/s: angular_speed times the unit axis for a rotation, else 0.
  Eigen::Vector3d angular_velocity() const;
};

// One triangle (a, b, c): particles live on the side (b - a) x (c - a) points to.
using RefTriangle = std::array<Eigen::Vector3d, 3>;

struct RefWall {
  std::string name;
  std::vector<RefTriangle> triangles;  // world coordinates at t = 0
  RefWallMotion motion;
  int material = -1;  // index into the world's materials
};

}  // namespace talus::reference
