// The damping ratio beta(eps) of the volume model's calibrated normal damping (force_law.hpp):
// the beta for which the normalised impact q'' = -max(0, q^(1/3) + beta q'), q(0) = 0,
// q'(0) = 1, rebounds with speed eps. Host only, computed once per material pair.
#pragma once

namespace talus {

// The rebound speed of that problem for a given beta. The constant is defined by its numerical
// solution: classical RK4 with step 2e-4 from q = 0, q' = 1, stopped at the first step where the
// overlap shrinks (q' < 0) and either q <= 0 or the force has vanished (the contact cannot pull,
// so the bodies then separate at constant speed); the reference solver defines it the same way,
// and both solvers must use the same number to agree to 1e-8.
double normalised_impact_restitution(double beta);

// beta(eps) by bisection to 1e-10 relative (eps = 1: beta = 0). Throws std::invalid_argument
// unless eps is in (0, 1].
double calibrated_damping_ratio_for(double restitution);

}  // namespace talus
