#include "reference/contact/force_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
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

double volume_law_reference_area(double radius_a, double radius_b) {
  const double r = std::min(radius_a, radius_b);
  return M_PI * r * r;
}

double volume_law_pressure(double modulus, double reference_area, double volume) {
  if (!(volume > 0)) return 0;
  return modulus * std::min(volume / reference_area, std::cbrt(volume));
}

double volume_law_pressure_slope(double modulus, double reference_area, double volume) {
  if (!(volume > 0)) return modulus / reference_area;
  // V / A_ref <= V^(1/3) exactly when V <= V_s = A_ref^(3/2).
  return volume / reference_area <= std::cbrt(volume)
             ? modulus / reference_area
             : modulus / (3 * std::cbrt(volume) * std::cbrt(volume));
}

double volume_law_energy(double modulus, double reference_area, double volume) {
  if (!(volume > 0)) return 0;
  if (volume / reference_area <= std::cbrt(volume)) {
    return modulus * volume * volume / (2 * reference_area);
  }
  // 3/4 K V^(4/3) shifted down by its excess at V_s, 3/4 K A_ref^2 - K A_ref^2 / 2.
  return 0.75 * modulus * volume * std::cbrt(volume) -
         0.25 * modulus * reference_area * reference_area;
}

double paper_law_energy(double modulus, double volume) {
  return volume > 0 ? 0.75 * modulus * volume * std::cbrt(volume) : 0.0;
}

VolumeElastic volume_elastic(VolumeLaw law, const VolumeModuli& moduli, double volume,
                             double area) {
  VolumeElastic out;
  if (!(volume > 0) || !(area > 0)) return out;
  const double k = moduli.normal;
  if (law == VolumeLaw::kPaper) {
    out.stiffness = k * area;                       // Eq. 13
    out.force = out.stiffness * std::cbrt(volume);  // Eq. 12
    out.energy = paper_law_energy(k, volume);
  } else {
    const double a_ref = moduli.reference_area;
    out.force = volume_law_pressure(k, a_ref, volume) * area;
    out.stiffness = volume_law_pressure_slope(k, a_ref, volume) * area * area;
    out.energy = volume_law_energy(k, a_ref, volume);
  }
  return out;
}

double tangential_spring_energy(const Eigen::Vector3d& elastic_force, double tangential_stiffness) {
  return tangential_stiffness > 0 ? elastic_force.squaredNorm() / (2 * tangential_stiffness) : 0.0;
}

double clamped_volume_oscillator_restitution(double beta) {
  // q'' = -max(0, q^(1/3) + beta q') by RK4 from q = 0, q' = 1, until the force vanishes while
  // the overlap shrinks (the bodies then fly apart at constant speed) or q returns to 0. Near
  // that end the force tends to 0 continuously, so stopping at the first step past it costs
  // O(h * force) in the speed, far below the tolerance.
  const auto accel = [beta](double q, double v) {
    return -std::max(0.0, std::cbrt(std::max(q, 0.0)) + beta * v);
  };
  const double h = 2e-4;
  double q = 0, v = 1;
  for (long k = 0; k < 100000000; ++k) {
    const double k1v = accel(q, v), k1q = v;
    const double k2v = accel(q + 0.5 * h * k1q, v + 0.5 * h * k1v), k2q = v + 0.5 * h * k1v;
    const double k3v = accel(q + 0.5 * h * k2q, v + 0.5 * h * k2v), k3q = v + 0.5 * h * k2v;
    const double k4v = accel(q + h * k3q, v + h * k3v), k4q = v + h * k3v;
    q += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (v < 0 && (q <= 0 || accel(q, v) == 0)) return -v;
  }
  throw std::runtime_error("reference contact: the calibration oscillator did not end");
}

double calibrated_damping_ratio(double restitution) {
  if (!(restitution > 0 && restitution <= 1)) {
    throw std::invalid_argument("reference contact: restitution must be in (0, 1], got " +
                                std::to_string(restitution));
  }
  if (restitution == 1) return 0;
  static std::mutex mutex;
  static std::map<double, double> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = cache.find(restitution); it != cache.end()) return it->second;
  // The rebound speed falls monotonically from 1 (beta = 0) towards 0 as beta grows.
  double lo = 0, hi = 1;
  while (clamped_volume_oscillator_restitution(hi) > restitution) lo = hi, hi *= 2;
  while (hi - lo > 1e-10 * hi) {
    const double mid = 0.5 * (lo + hi);
    (clamped_volume_oscillator_restitution(mid) > restitution ? lo : hi) = mid;
  }
  return cache[restitution] = 0.5 * (lo + hi);
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
                                  ContactHistory& history) {
  const Eigen::Vector3d& n = contact.normal;
  const double v_n = relative_velocity.dot(n);
  history.approach_speed = std::max(history.approach_speed, std::max(v_n, 0.0));
  double c_n = 0;
  const double m = law.effective_mass;
  if (law.damping == NormalDamping::kPaper) {
    c_n = damping_coefficient(law.restitution, contact.normal_stiffness, m);  // Eq. 15
  } else if (law.restitution < 1 && contact.area > 0) {
    // eta = beta m v0 / dV*, dV* = (m v0^2 / K)^(3/4): beta m^(1/4) K^(3/4) / sqrt(v0).
    const double modulus = contact.normal_stiffness / contact.area;  // K
    // v0 is at least the speed that would have made the current overlap: m v^2 / 2 = U(dV) =
    // 3/4 K dV^(4/3) (the potential of Eqs. 12-13). In a head-on impact that never exceeds the
    // approach speed (damping only removes energy), so impacts keep the calibrated eta; a contact
    // formed at rest or approached very slowly (v0 ~ 0, eta ~ 1/sqrt(v0)) gets the finite eta of
    // its load instead of the step limit below, which makes an explicit step chatter.
    if (contact.elastic > 0) {
      const double cube_root = contact.elastic / contact.normal_stiffness;  // dV^(1/3)
      const double energy = 0.75 * modulus * std::pow(cube_root, 4.0);
      history.approach_speed = std::max(history.approach_speed, std::sqrt(2 * energy / m));
    }
    const double v0 = history.approach_speed;
    const double beta = calibrated_damping_ratio(law.restitution);
    c_n = v0 > 0 ? beta * std::pow(m, 0.25) * std::pow(modulus, 0.75) / std::sqrt(v0) * contact.area
                 : std::numeric_limits<double>::infinity();
  }
  if (law.time_step > 0) c_n = std::min(c_n, m / law.time_step);
  if (!std::isfinite(c_n)) c_n = 0;  // v0 = 0 without a step limit: no approach to damp
  ContactForce out;
  out.normal_force = normal_force(n, contact.elastic, c_n, v_n);
  out.normal_damping = c_n;
  if (!law.with_friction) {
    history.elastic_force.setZero();
    return out;
  }
  // Eq. 18's elastic force, turned onto the current tangent plane with its length kept, then
  // advanced by -k_t v_t dt (see the header).
  Eigen::Vector3d& f_e = history.elastic_force;
  const double length = f_e.norm();
  f_e -= f_e.dot(n) * n;
  const double projected = f_e.norm();
  if (projected > 0) f_e *= length / projected;
  const Eigen::Vector3d v_t = relative_velocity - v_n * n;
  const double k_t = contact.tangential_stiffness;
  // The default law: where k_t fell, the force that keeps the spring's energy (see the header).
  const double k_before = history.spring_stiffness;
  if (law.bounded_spring_energy && k_before > 0 && k_t < k_before) {
    f_e *= std::sqrt(k_t / k_before);
  }
  history.spring_stiffness = k_t;
  f_e -= (k_t * dt) * v_t;
  const double c_t = damping_coefficient(law.restitution, k_t, law.effective_mass);  // Eq. 20
  out.tangential_damping = c_t;
  Eigen::Vector3d f_t = f_e - c_t * v_t;  // Eqs. 17, 20
  const double cap = law.friction * out.normal_force.norm();
  const double f_t_norm = f_t.norm();
  if (f_t_norm > cap) {
    out.sliding = true;
    f_t *= f_t_norm > 0 ? cap / f_t_norm : 0.0;
    f_e = f_t + c_t * v_t;  // the elastic part of the capped force
  }
  out.tangential_force = f_t;
  return out;
}

PatchCouple patch_couple(const ContactForce& force, const Eigen::Vector3d& normal, double area,
                         double normal_stiffness, double friction,
                         const Eigen::Vector3d& relative_angular_velocity, double dt,
                         ContactHistory& history) {
  PatchCouple out;
  if (!(area > 0)) {
    history.rocking_moment.setZero();
    history.rocking_stiffness = 0;
    return out;
  }
  const Eigen::Vector3d& w = relative_angular_velocity;
  const double normal_load = force.normal_force.norm();  // |F_n|, after the no-tension rule
  const double spin = normal.dot(w);                     // w_n
  const Eigen::Vector3d tilt = w - spin * normal;        // w_perp
  // The rocking spring M_e: into the current contact plane with its length kept, its energy kept
  // where k_r = k_n A_n / 12 fell, then advanced by -k_r w_perp dt (see the header).
  Eigen::Vector3d& spring = history.rocking_moment;
  const double kept_length = spring.norm();
  spring -= spring.dot(normal) * normal;
  if (const double in_plane = spring.norm(); in_plane > 0) spring *= kept_length / in_plane;
  const double k_r = normal_stiffness * area / 12;
  const double k_previous = history.rocking_stiffness;
  if (k_previous > 0 && k_r < k_previous) spring *= std::sqrt(k_r / k_previous);
  history.rocking_stiffness = k_r;
  spring -= (k_r * dt) * tilt;
  // With the dashpot c_n I / A_n, I = A_n^2 / 12 (square patch), within the patch's edge; the
  // spring keeps what the capped moment leaves it.
  const double c_r = force.normal_damping * area / 12;
  out.rocking = spring - c_r * tilt;
  const double rocking_limit = normal_load * std::sqrt(area) / 2;
  if (const double size = out.rocking.norm(); size > rocking_limit) {
    out.rocking *= rocking_limit / size;
    spring = out.rocking + c_r * tilt;
  }
  out.spring_energy = k_r > 0 ? spring.squaredNorm() / (2 * k_r) : 0.0;
  // Twisting: -c_t J / A_n w_n, J = A_n^2 / 6, within Coulomb's mu |F_n| at the mean radius
  // (2/3) sqrt(A_n / pi).
  const double twist_limit = friction * normal_load * (2.0 / 3.0) * std::sqrt(area / M_PI);
  const double twist =
      std::clamp(-force.tangential_damping * area / 6 * spin, -twist_limit, twist_limit);
  out.twisting = twist * normal;
  out.dissipation = -out.total().dot(w);
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
