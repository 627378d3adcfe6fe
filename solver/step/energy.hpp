// The energy balance of a run (the `energy` probe and the run's watchdog): the state's kinetic,
// gravitational and elastic energies, and the running totals of what left or entered through the
// contacts: dissipated by damping and friction, given by moving walls, brought in by feeds, taken
// out by particles that left the domain box.
// Host code; both steps fill it (the CUDA step from device reductions).
#pragma once

#include <cmath>

namespace talus {

// What the contacts of one force evaluation report to the ledger (sums over the touching ones).
struct ContactRates {
  // W, the power the contacts' non-conservative forces take from the bodies: damping, friction
  // and the springs (force_law.hpp: ContactForceData::dissipation).
  double dissipation = 0;
  double wall_power = 0;  // W, given by moving walls
  double spring = 0;      // J, the tangential and rocking springs' energy after it
};

// Running totals over the steps, in double. The rates are the contacts' at the last force
// evaluation; each step adds the trapezoid of the rates at its two ends, the rule that matches
// velocity Verlet's average of the step-start and step-end forces. What the tangential springs
// took in over the step is not dissipated: their energy's change (a state, not a rate) is taken
// off. A contact that ends takes its spring's energy with it (its history leaves the store,
// tangential_history.hpp, and nothing gives the energy back to the bodies): that fall of the
// springs' total is dissipated, whatever ended the contact (separation, a pair list rebuilt, a
// particle removed).
struct EnergyLedger {
  double dissipated = 0;        // J
  double wall_work = 0;         // J, by moving walls on the particles
  double fed = 0;               // J, kinetic + gravitational energy of inserted particles
  double removed = 0;           // J, kinetic + gravitational energy of removed particles
  double dissipation_rate = 0;  // W, at the last evaluation
  double wall_power = 0;        // W, at the last evaluation
  double spring_energy = 0;     // J, the springs' at the last evaluation

  // The rates at the force evaluation before the first step (nothing accumulated yet).
  void start(const ContactRates& now) {
    dissipation_rate = now.dissipation;
    wall_power = now.wall_power;
    spring_energy = now.spring;
  }
  // One step of dt ending at an evaluation with these rates.
  void advance(double dt, const ContactRates& now) {
    dissipated += 0.5 * dt * (dissipation_rate + now.dissipation) - (now.spring - spring_energy);
    wall_work += 0.5 * dt * (wall_power + now.wall_power);
    start(now);
  }
};

struct EnergyTerms {
  double kinetic_translational = 0;  // J
  double kinetic_rotational = 0;     // J
  double gravitational = 0;          // J, -sum m g . x (zero at the origin)
  double elastic_normal = 0;         // J, the contacts' normal potentials U
  double elastic_tangential = 0;     // J, the tangential (and rocking) springs' energy
  EnergyLedger ledger;

  double kinetic() const { return kinetic_translational + kinetic_rotational; }
  // What the particles hold now.
  double mechanical() const {
    return kinetic() + gravitational + elastic_normal + elastic_tangential;
  }
  // Held + dissipated - given: constant in an exact run (its change is the balance error).
  double balance() const {
    return mechanical() + ledger.dissipated + ledger.removed - ledger.wall_work - ledger.fed;
  }
  bool finite() const { return std::isfinite(balance()) && std::isfinite(ledger.wall_work); }
};

}  // namespace talus
