// The energy balance of a run (the `energy` probe and the run's watchdog): the state's kinetic,
// gravitational and elastic energies, and the running totals of what left or entered through the
// contacts: dissipated by damping and friction, given by moving walls, brought in by feeds.
// Host code; both steps fill it (the CUDA step from device reductions).
#pragma once

#include <cmath>

namespace talus {

// Running totals over the steps, in double. The rates are the contacts' at the last force
// evaluation; each step adds the trapezoid of the rates at its two ends, the rule that matches
// velocity Verlet's average of the step-start and step-end forces.
struct EnergyLedger {
  double dissipated = 0;        // J
  double wall_work = 0;         // J, by moving walls on the particles
  double fed = 0;               // J, kinetic + gravitational energy of inserted particles
  double dissipation_rate = 0;  // W, at the last evaluation
  double wall_power = 0;        // W, at the last evaluation

  // The rates at the force evaluation before the first step (nothing accumulated yet).
  void start(double dissipation_now, double wall_power_now) {
    dissipation_rate = dissipation_now;
    wall_power = wall_power_now;
  }
  // One step of dt ending at an evaluation with these rates.
  void advance(double dt, double dissipation_now, double wall_power_now) {
    dissipated += 0.5 * dt * (dissipation_rate + dissipation_now);
    wall_work += 0.5 * dt * (wall_power + wall_power_now);
    start(dissipation_now, wall_power_now);
  }
};

struct EnergyTerms {
  double kinetic_translational = 0;  // J
  double kinetic_rotational = 0;     // J
  double gravitational = 0;          // J, -sum m g . x (zero at the origin)
  double elastic_normal = 0;         // J, the contacts' normal potentials U
  double elastic_tangential = 0;     // J, the tangential springs' |F_t^e|^2 / (2 k_t)
  EnergyLedger ledger;

  double kinetic() const { return kinetic_translational + kinetic_rotational; }
  // What the particles hold now.
  double mechanical() const {
    return kinetic() + gravitational + elastic_normal + elastic_tangential;
  }
  // Held + dissipated - given: constant in an exact run (its change is the balance error).
  double balance() const {
    return mechanical() + ledger.dissipated - ledger.wall_work - ledger.fed;
  }
  bool finite() const { return std::isfinite(balance()) && std::isfinite(ledger.wall_work); }
};

}  // namespace talus
