// Body forces of the reference solver, added to a body's world-frame accumulators at its current
// state.
#pragma once

#include "reference/dynamics/rigid_body.hpp"

namespace talus::reference {

// F += m g (g in m/s^2, world frame).
void add_gravity(RigidBody& body, const Eigen::Vector3d& gravity);

// Quadratic air drag F += -alpha v |v| (BLAZE-DEM §5.1), alpha in kg/m.
void add_quadratic_drag(RigidBody& body, double alpha);

}  // namespace talus::reference
