// Where a moving wall is at time t, and how fast a point attached to it moves.
//
// A wall's mesh is given at t = 0 (wall_meshes.hpp); its motion (WallMotion) is rigid:
// rotation by angle angular_speed() * t about `axis` through `point` (right-handed),
// translation by velocity * t, or an oscillation: translation by direction * d(t)
// (WallMotion::oscillation_displacement). So a point x0 of the wall at t = 0 is at
// transform(t).apply(x0).
#pragma once

#include "solver/scene/scene.hpp"

namespace talus {

// world = rotation (x) + translation.
struct RigidTransform {
  Quatd rotation;  // identity by default
  Vec3d translation;
  Vec3d apply(const Vec3d& x) const { return rotate(rotation, x) + translation; }
};

// The placement of the wall at time t (s) relative to t = 0. Rotation: R(axis, w t) and
// translation point - R point, so that the axis stays put. Translation: identity rotation and
// velocity * t. No motion: the identity.
RigidTransform wall_transform(const WallMotion& motion, double time);

// The velocity (m/s) of the point of the wall that is at world position `x` at time t:
// w axis x (x - point) for a rotation (a constant angular velocity, so it does not depend on t
// beyond where x is), the constant velocity for a translation, direction * d'(t) for an
// oscillation, zero without motion.
Vec3d wall_point_velocity(const WallMotion& motion, double time, const Vec3d& x);

// The wall's angular velocity vector, rad/s (zero unless it rotates).
Vec3d wall_angular_velocity(const WallMotion& motion);

// A mesh moved by a transform (each vertex; the triangles unchanged, so the winding and hence
// the side the normals face are kept).
TriangleMesh transformed(const TriangleMesh& mesh, const RigidTransform& transform);

}  // namespace talus
