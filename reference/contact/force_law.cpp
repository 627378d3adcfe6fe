#include "reference/contact/force_law.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace talus::reference {

double damping_coefficient(double restitution, double stiffness, double mass) {
  if (!(restitution > 0 && restitution <= 1)) {
    throw std::invalid_argument("reference contact: restitution must be in (0, 1], got " +
                                std::to_string(restitution));
  }
  if (!(stiffness >= 0 && mass >= 0)) {
    throw std::invalid_argument("reference contact: damping needs k >= 0 and m >= 0");
  }
  const double log_e = std::log(restitution);
  return -2 * log_e * std::sqrt(stiffness * mass) / std::sqrt(log_e * log_e + M_PI * M_PI);
}

namespace {

// Eq. 16 with Eq. 14, on A, and the no-tension rule: the magnitude along -n is at least 0.
Eigen::Vector3d normal_force(const Eigen::Vector3d& n, double elastic, double damping,
                             double normal_speed) {
  const double push = elastic + damping * normal_speed;
  return push > 0 ? Eigen::Vector3d(-push * n) : Eigen::Vector3d::Zero();
}

}  // namespace

ContactForce volume_contact_force(const NormalContact& contact, const VolumeLawParameters& law,
                                  const Eigen::Vector3d& relative_velocity, double dt,
                                  TangentialHistory& history) {
  const Eigen::Vector3d& n = contact.normal;
  const double v_n = relative_velocity.dot(n);
  // The stiffness in Eq. 15 (DampingStiffness): k_n, or the secant stiffness |F_n^e| / d.
  double scale = 1;
  if (law.damping == DampingStiffness::kLinearised) {
    scale = contact.mean_depth > 0 && contact.normal_stiffness > 0
                ? contact.elastic / (contact.mean_depth * contact.normal_stiffness)
                : 0.0;
  }
  double c_n = damping_coefficient(law.restitution, scale * contact.normal_stiffness,
                                   law.effective_mass);  // Eq. 15
  if (law.time_step > 0) c_n = std::min(c_n, law.effective_mass / law.time_step);
  ContactForce out;
  out.normal_force = normal_force(n, contact.elastic, c_n, v_n);
  if (!law.with_friction) {
    history.spring.setZero();
    return out;
  }
  // Eq. 18's spring, turned onto the current tangent plane with its length kept.
  Eigen::Vector3d& s = history.spring;
  const double length = s.norm();
  s -= s.dot(n) * n;
  const double projected = s.norm();
  if (projected > 0) s *= length / projected;
  const Eigen::Vector3d v_t = relative_velocity - v_n * n;
  s += dt * v_t;
  const double k_t = contact.tangential_stiffness;
  const double c_t =
      damping_coefficient(law.restitution, scale * k_t, law.effective_mass);  // Eq. 20
  Eigen::Vector3d f_t = -k_t * s - c_t * v_t;                                 // Eqs. 17, 18, 20
  const double cap = law.friction * out.normal_force.norm();
  const double f_t_norm = f_t.norm();
  if (f_t_norm > cap) {
    out.sliding = true;
    f_t *= f_t_norm > 0 ? cap / f_t_norm : 0.0;
    // The spring that gives the capped force; with k_t = 0 (no area) nothing can be stored.
    s = k_t > 0 ? Eigen::Vector3d(-(f_t + c_t * v_t) / k_t) : Eigen::Vector3d::Zero();
  }
  out.tangential_force = f_t;
  return out;
}

ContactForce linear_contact_force(const NormalContact& contact, const LinearLawParameters& law,
                                  const Eigen::Vector3d& relative_velocity) {
  const Eigen::Vector3d& n = contact.normal;
  const double v_n = relative_velocity.dot(n);
  ContactForce out;
  out.normal_force = normal_force(n, contact.elastic, law.damping, v_n);  // Eq. 2
  if (!law.with_friction) return out;
  const Eigen::Vector3d v_t = relative_velocity - v_n * n;
  const double speed = v_t.norm();
  if (speed == 0) return out;
  // Eq. 3: mu K_N delta, not mu |F_N|: the cap is the elastic normal force.
  const double magnitude = std::min(law.friction * contact.elastic, law.tangential_damping * speed);
  out.sliding = law.friction * contact.elastic < law.tangential_damping * speed;
  out.tangential_force = -magnitude / speed * v_t;
  return out;
}

}  // namespace talus::reference
