// Body forces of the production solver, per particle (one thread per particle on the GPU):
// gravity and the quadratic air drag of BLAZE-DEM §5.1. Stateless TALUS_HD functions on values;
// the step (solver/step/) loads a particle's state, calls them and stores the result.
#pragma once

#include "solver/core/vec3.hpp"

namespace talus {

// m g, N.
template <class Real>
TALUS_HD inline Vec3<Real> gravity_force(Real mass, const Vec3<Real>& gravity) {
  return gravity * mass;
}

// Quadratic drag -alpha |v| v, N (BLAZE-DEM §5.1; alpha in kg/m). Evaluated at the velocity the
// integrator predicts for the end of the step (dynamics/integrator.hpp).
template <class Real>
TALUS_HD inline Vec3<Real> quadratic_drag_force(Real alpha, const Vec3<Real>& velocity) {
  return velocity * (-alpha * norm(velocity));
}

}  // namespace talus
