#include "reference/world/wall.hpp"

#include <Eigen/Geometry>

namespace talus::reference {

Eigen::Vector3d RefWallMotion::position(const Eigen::Vector3d& x0, double t) const {
  switch (kind) {
    case Kind::kRotation:
      return point + Eigen::AngleAxisd(angular_speed * t, axis.normalized()) * (x0 - point);
    case Kind::kTranslation:
      return x0 + t * velocity;
    case Kind::kNone:
      break;
  }
  return x0;
}

Eigen::Vector3d RefWallMotion::velocity_at(const Eigen::Vector3d& x) const {
  switch (kind) {
    case Kind::kRotation:
      return angular_speed * axis.normalized().cross(x - point);
    case Kind::kTranslation:
      return velocity;
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
