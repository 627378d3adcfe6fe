// The particles as the step holds them: a structure of arrays (docs/design.md, "The step";
// BLAZE-DEM §2.1 measured AoS 3x slower), one array per component, with global ids that key the
// pair histories and survive reordering. ParticleView is the POD view of raw pointers that the
// per-particle and per-pair functions take (host memory here, device memory in the CUDA
// backend); an array the scene's effects do not need is absent (null) and never allocated.
#pragma once

#include <string>

#include "solver/core/quat.hpp"

namespace talus {

// Three (or four) component arrays of one vector field.
template <class Real>
struct Soa3 {
  Real* x = nullptr;
  Real* y = nullptr;
  Real* z = nullptr;
  TALUS_HD bool present() const { return x != nullptr; }
  TALUS_HD Vec3<Real> get(int i) const { return {x[i], y[i], z[i]}; }
  TALUS_HD void set(int i, const Vec3<Real>& v) const {
    x[i] = v.x;
    y[i] = v.y;
    z[i] = v.z;
  }
};

template <class Real>
struct Soa4 {
  Real* w = nullptr;
  Real* x = nullptr;
  Real* y = nullptr;
  Real* z = nullptr;
  TALUS_HD bool present() const { return w != nullptr; }
  TALUS_HD Quat<Real> get(int i) const { return {w[i], x[i], y[i], z[i]}; }
  TALUS_HD void set(int i, const Quat<Real>& q) const {
    w[i] = q.w;
    x[i] = q.x;
    y[i] = q.y;
    z[i] = q.z;
  }
};

template <class Real>
struct ParticleView {
  int count = 0;
  // Always present.
  Soa3<Real> position;     // centroid, m (world)
  Soa3<Real> velocity;     // m/s (world)
  Soa4<Real> orientation;  // unit quaternion, body -> world
  int* template_id = nullptr;
  int* material_id = nullptr;
  long long* global_id = nullptr;
  // With any force (gravity, drag, contacts): the accumulated force, N, and the acceleration
  // that started the step (dynamics/integrator.hpp).
  Soa3<Real> force;
  Soa3<Real> step_start_acceleration;
  // With rotation: the angular velocity in the BODY frame (Euler's equations, Eq. 26), rad/s.
  Soa3<Real> angular_velocity;
  // With rotation and contacts: the torque about the centroid (world), N m, and T_k.
  Soa3<Real> torque;
  Soa3<Real> step_start_torque;
  // With contacts: the bounding radius about the centroid, m (the broad phase's input).
  Real* bounding_radius = nullptr;
};

// A ParticleView over named arrays: `array(name)` gives the array's pointer, null for one the
// plan does not need.
template <class Real, class Array>
inline ParticleView<Real> view_over(Array&& array) {
  const auto soa3 = [&](const std::string& name) {
    Soa3<Real> s;
    s.x = array(name + ".x"), s.y = array(name + ".y"), s.z = array(name + ".z");
    return s;
  };
  ParticleView<Real> v;
  v.position = soa3("position");
  v.velocity = soa3("velocity");
  v.orientation.w = array("orientation.w");
  v.orientation.x = array("orientation.x");
  v.orientation.y = array("orientation.y");
  v.orientation.z = array("orientation.z");
  v.force = soa3("force");
  v.step_start_acceleration = soa3("step_start_acceleration");
  v.angular_velocity = soa3("angular_velocity");
  v.torque = soa3("torque");
  v.step_start_torque = soa3("step_start_torque");
  v.bounding_radius = array("bounding_radius");
  return v;
}

}  // namespace talus
