// Helpers of the reference-world tests: materials, walls and one-particle or two-particle worlds.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "reference/world/world.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus::reference::testing {

inline RefMaterial material(double youngs_modulus, double restitution, double friction = 0,
                            double density = 2500, double poisson_ratio = 0.3) {
  RefMaterial m;
  m.name = "m";
  m.density = density;
  m.youngs_modulus = youngs_modulus;
  m.poisson_ratio = poisson_ratio;
  m.friction = friction;
  m.restitution = restitution;
  return m;
}

// A square of side `size` centred at `centre` in the plane normal to `normal`, as two triangles
// whose normals point along `normal`; `u` fixes the in-plane orientation of the square's sides.
inline RefWall square_wall(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal,
                           double size, int material,
                           const Eigen::Vector3d& u_hint = Eigen::Vector3d::UnitX()) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d u = (u_hint - u_hint.dot(n) * n).normalized();
  const Eigen::Vector3d v = n.cross(u);
  const double h = 0.5 * size;
  const Eigen::Vector3d p00 = centre - h * u - h * v, p10 = centre + h * u - h * v;
  const Eigen::Vector3d p11 = centre + h * u + h * v, p01 = centre - h * u + h * v;
  RefWall w;
  w.name = "square";
  w.material = material;
  w.triangles = {{p00, p10, p11}, {p00, p11, p01}};  // (b - a) x (c - a) along u x v = n
  return w;
}

inline RefBodySpec polyhedron(int shape, int material, long long id, const Eigen::Vector3d& x,
                              const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity(),
                              const Eigen::Vector3d& v = Eigen::Vector3d::Zero()) {
  RefBodySpec b;
  b.kind = ParticleShapeKind::polyhedron;
  b.shape = shape;
  b.material = material;
  b.id = id;
  b.position = x;
  b.orientation = q;
  b.velocity = v;
  return b;
}

// The rotation that takes the body-frame direction `body_dir` to the world direction `world_dir`.
inline Eigen::Quaterniond turning(const Eigen::Vector3d& body_dir,
                                  const Eigen::Vector3d& world_dir) {
  return Eigen::Quaterniond::FromTwoVectors(body_dir, world_dir);
}

}  // namespace talus::reference::testing
