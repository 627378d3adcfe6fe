#include "reference/world/wall.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <utility>

namespace talus::reference {

namespace {

// The oscillation's shift along the axis and its rate at time t (both 0 outside its cycles).
std::pair<double, double> oscillation(const RefWallMotion& m, double t) {
  const double tau = t - m.start;
  const bool running = tau > 0 && (m.cycles == 0 || m.frequency * tau < m.cycles);
  if (!running) return {0.0, 0.0};
  const double w = 2 * M_PI * m.frequency;
  return {m.amplitude - m.amplitude * std::cos(w * tau), m.amplitude * w * std::sin(w * tau)};
}

}  // namespace

Eigen::Vector3d RefWallMotion::position(const Eigen::Vector3d& x0, double t) const {
  switch (kind) {
    case Kind::kRotation:
      return point + Eigen::AngleAxisd(angular_speed * t, axis.normalized()) * (x0 - point);
    case Kind::kTranslation:
      return x0 + t * velocity;
    case Kind::kOscillation:
      return x0 + oscillation(*this, t).first * axis.normalized();
    case Kind::kNone:
      break;
  }
  return x0;
}

Eigen::Vector3d RefWallMotion::velocity_at(const Eigen::Vector3d& x, double t) const {
  switch (kind) {
    case Kind::kRotation:
      return angular_speed * axis.normalized().cross(x - point);
    case Kind::kTranslation:
      return velocity;
    case Kind::kOscillation:
      return oscillation(*this, t).second * axis.normalized();
    case Kind::kNone:
      break;
  }
  return Eigen::Vector3d::Zero();
}

Eigen::Vector3d RefWallMotion::angular_velocity() const {
  return kind == Kind::kRotation ? Eigen::Vector3d(angular_speed * axis.normalized())
                                 : Eigen::Vector3d::Zero();
}

}  // namespace talus::reference
