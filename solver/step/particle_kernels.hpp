// The per-particle stages of the step (one thread per particle on the GPU, a loop on the host):
// each loads particle i from the ParticleView, calls the stateless functions of dynamics/ and
// stores the result. Absent arrays are never touched: the plan (step_plan.hpp) runs only the
// stages of the scene's effects, and each stage reads only the arrays they allocate.
#pragma once

#include <cmath>

#include "solver/dynamics/body_forces.hpp"
#include "solver/dynamics/integrator.hpp"
#include "solver/geometry/convex.hpp"
#include "solver/step/particle_state.hpp"

namespace talus {

// What every particle of one template shares (mass properties with its material's density).
template <class Real>
struct BodyProperties {
  bool sphere = false;
  Real mass = 0;               // kg
  Vec3<Real> inertia;          // principal moments I^, kg m^2 (body frame)
  Real bounding_radius = 0;    // m, about the centroid
  Real equivalent_radius = 0;  // R of Eq. 13: the sphere of equal volume, m
  Real sphere_radius = 0;      // spheres, m
  int material = -1;           // index into the scene's materials
  ConvexView<Real> shape;      // polyhedra: the template's arrays
  int faces = 0;               // polyhedra: merged faces (overlap workspace capacity)
};

template <class Real>
TALUS_HD inline Vec3<Real> force_or_zero(const ParticleView<Real>& p, int i) {
  return p.force.present() ? p.force.get(i) : Vec3<Real>();
}

template <class Real>
TALUS_HD inline Vec3<Real> torque_or_zero(const ParticleView<Real>& p, int i) {
  return p.torque.present() ? p.torque.get(i) : Vec3<Real>();
}

// Stage integrate_begin. Returns false when the free rotation did not converge.
template <class Real>
TALUS_HD inline bool integrate_begin(const ParticleView<Real>& p,
                                     const BodyProperties<Real>* bodies, int i, Real dt) {
  const BodyProperties<Real>& body = bodies[p.template_id[i]];
  Vec3<Real> x = p.position.get(i), v = p.velocity.get(i), a0;
  begin_translation(x, v, force_or_zero(p, i), body.mass, dt, a0);
  p.position.set(i, x);
  p.velocity.set(i, v);
  if (p.step_start_acceleration.present()) p.step_start_acceleration.set(i, a0);
  if (!p.angular_velocity.present()) return true;
  Quat<Real> q = p.orientation.get(i);
  Vec3<Real> w = p.angular_velocity.get(i), t0;
  const bool ok = begin_rotation(q, w, torque_or_zero(p, i), body.inertia, dt, t0);
  p.orientation.set(i, q);
  p.angular_velocity.set(i, w);
  if (p.step_start_torque.present()) p.step_start_torque.set(i, t0);
  return ok;
}

// Stage clear_forces.
template <class Real>
TALUS_HD inline void clear_forces(const ParticleView<Real>& p, int i) {
  p.force.set(i, Vec3<Real>());
  if (p.torque.present()) p.torque.set(i, Vec3<Real>());
}

// Stage gravity.
template <class Real>
TALUS_HD inline void add_gravity(const ParticleView<Real>& p, const BodyProperties<Real>* bodies,
                                 int i, const Vec3<Real>& gravity) {
  p.force.set(i, p.force.get(i) + gravity_force(bodies[p.template_id[i]].mass, gravity));
}

// Stage drag, at the predicted velocity.
template <class Real>
TALUS_HD inline void add_drag(const ParticleView<Real>& p, int i, Real alpha) {
  p.force.set(i, p.force.get(i) + quadratic_drag_force(alpha, p.velocity.get(i)));
}

// Stage integrate_end.
template <class Real>
TALUS_HD inline void integrate_end(const ParticleView<Real>& p, const BodyProperties<Real>* bodies,
                                   int i, Real dt) {
  const BodyProperties<Real>& body = bodies[p.template_id[i]];
  if (p.step_start_acceleration.present()) {
    Vec3<Real> v = p.velocity.get(i);
    end_translation(v, p.force.get(i), body.mass, dt, p.step_start_acceleration.get(i));
    p.velocity.set(i, v);
  }
  if (p.torque.present()) {
    Vec3<Real> w = p.angular_velocity.get(i);
    end_rotation(p.orientation.get(i), w, p.torque.get(i), body.inertia, dt,
                 p.step_start_torque.get(i));
    p.angular_velocity.set(i, w);
  }
}

// The kinetic (translational and rotational) and gravitational energy particle i holds, J, in
// double (`gravity` null: none): what a feed brings and a removal takes to the energy ledger.
template <class Real>
TALUS_HD inline double particle_energy(const ParticleView<Real>& p,
                                       const BodyProperties<Real>& body, const Vec3d* gravity,
                                       int i) {
  double energy = 0.5 * double(body.mass) * norm2(Vec3d(p.velocity.get(i)));
  if (p.angular_velocity.present()) {
    const Vec3d w(p.angular_velocity.get(i));  // body frame, with the principal moments
    const Vec3d inertia(body.inertia);
    energy += 0.5 * (inertia.x * w.x * w.x + inertia.y * w.y * w.y + inertia.z * w.z * w.z);
  }
  if (gravity) energy -= double(body.mass) * dot(*gravity, Vec3d(p.position.get(i)));
  return energy;
}

// The highest point of particle i along the unit vector `up`, m, in double: its bounding
// sphere's top for a sphere, its highest vertex for a polyhedron (the bed_height probe's term;
// the host loop and the CUDA kernel both call this).
template <class Real>
TALUS_HD inline double particle_top(const ParticleView<Real>& p, const BodyProperties<Real>& body,
                                    int i, const Vec3d& up) {
  const Vec3d x(p.position.get(i));
  if (body.sphere) return dot(up, x) + double(body.sphere_radius);
  const Quatd q(p.orientation.get(i));
  double top = -HUGE_VAL;
  for (int v = 0; v < body.shape.n_vertices; ++v) {
    const double h = dot(up, x + rotate(q, Vec3d(body.shape.vertices[v])));
    top = h > top ? h : top;
  }
  return top;
}

}  // namespace talus
