#include "reference/dynamics/effects.hpp"

namespace talus::reference {

void add_gravity(RigidBody& body, const Eigen::Vector3d& gravity) {
  body.force += body.mass * gravity;
}

void add_quadratic_drag(RigidBody& body, double alpha) {
  body.force -= alpha * body.velocity.norm() * body.velocity;
}

}  // namespace talus::reference
