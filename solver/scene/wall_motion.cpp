#include "solver/scene/wall_motion.hpp"

namespace talus {

RigidTransform wall_transform(const WallMotion& motion, double time) {
  RigidTransform transform;
  if (motion.kind == WallMotion::Kind::rotation) {
    transform.rotation = Quatd::from_axis_angle(motion.axis, motion.angular_speed() * time);
    transform.translation = motion.point - rotate(transform.rotation, motion.point);
  } else if (motion.kind == WallMotion::Kind::translation) {
    transform.translation = motion.velocity * time;
  } else if (motion.kind == WallMotion::Kind::oscillation) {
    transform.translation = motion.direction * motion.oscillation_displacement(time);
  }
  return transform;
}

Vec3d wall_angular_velocity(const WallMotion& motion) {
  return motion.kind == WallMotion::Kind::rotation ? motion.axis * motion.angular_speed() : Vec3d();
}

Vec3d wall_point_velocity(const WallMotion& motion, double time, const Vec3d& x) {
  switch (motion.kind) {
    case WallMotion::Kind::rotation:
      return cross(wall_angular_velocity(motion), x - motion.point);
    case WallMotion::Kind::translation:
      return motion.velocity;
    case WallMotion::Kind::oscillation:
      return motion.direction * motion.oscillation_speed(time);
    case WallMotion::Kind::none:
      break;
  }
  return Vec3d();
}

TriangleMesh transformed(const TriangleMesh& mesh, const RigidTransform& transform) {
  TriangleMesh moved = mesh;
  for (Vec3d& p : moved.vertices) p = transform.apply(p);
  return moved;
}

}  // namespace talus
