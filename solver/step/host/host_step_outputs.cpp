// What a host step reports of its particles (host_step.hpp): the trajectory rows, the kinetic
// and potential energies, the bed height; the same functions compute the CUDA step's from its
// downloaded arrays (cuda_step.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "solver/step/host/contact_stage.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/step/host/wall_stage.hpp"

namespace talus {

template <class Real>
std::vector<TrajectoryRow> particle_rows(const ParticleView<Real>& view) {
  std::vector<TrajectoryRow> rows(view.count);
  for (int i = 0; i < view.count; ++i) {
    TrajectoryRow& row = rows[i];
    row.id = view.global_id[i];
    row.template_index = view.template_id[i];
    row.position = Vec3d(view.position.get(i));
    row.orientation = Quatd(view.orientation.get(i));
    row.velocity = Vec3d(view.velocity.get(i));
    if (view.angular_velocity.present()) {
      row.angular_velocity = rotate(row.orientation, Vec3d(view.angular_velocity.get(i)));
    }
  }
  // In global-id order whatever the particles' order in memory (`reorder`), as the files list them.
  const auto by_id = [](const TrajectoryRow& a, const TrajectoryRow& b) { return a.id < b.id; };
  if (!std::is_sorted(rows.begin(), rows.end(), by_id)) std::sort(rows.begin(), rows.end(), by_id);
  return rows;
}

template <class Real>
double particle_kinetic_energy(const ParticleView<Real>& view,
                               const std::vector<BodyProperties<Real>>& bodies) {
  double energy = 0;
  for (int i = 0; i < view.count; ++i) {
    const BodyProperties<Real>& body = bodies[view.template_id[i]];
    energy += 0.5 * double(body.mass) * norm2(Vec3d(view.velocity.get(i)));
    if (view.angular_velocity.present()) {
      const Vec3d w(view.angular_velocity.get(i));
      const Vec3d inertia(body.inertia);
      energy += 0.5 * (inertia.x * w.x * w.x + inertia.y * w.y * w.y + inertia.z * w.z * w.z);
    }
  }
  return energy;
}

template <class Real>
double particle_energy(const ParticleView<Real>& view,
                       const std::vector<BodyProperties<Real>>& bodies, const Vec3d* gravity,
                       int i) {
  return particle_energy(view, bodies[view.template_id[i]], gravity, i);
}

template <class Real>
void particle_energies(const ParticleView<Real>& view,
                       const std::vector<BodyProperties<Real>>& bodies, const Vec3d* gravity,
                       EnergyTerms& terms) {
  terms.kinetic_translational = terms.kinetic_rotational = terms.gravitational = 0;
  for (int i = 0; i < view.count; ++i) {
    const BodyProperties<Real>& body = bodies[view.template_id[i]];
    terms.kinetic_translational += 0.5 * double(body.mass) * norm2(Vec3d(view.velocity.get(i)));
    if (view.angular_velocity.present()) {
      const Vec3d w(view.angular_velocity.get(i));
      const Vec3d inertia(body.inertia);
      terms.kinetic_rotational +=
          0.5 * (inertia.x * w.x * w.x + inertia.y * w.y * w.y + inertia.z * w.z * w.z);
    }
    if (gravity)
      terms.gravitational -= double(body.mass) * dot(*gravity, Vec3d(view.position.get(i)));
  }
}

template <class Real>
double particle_bed_height(const ParticleView<Real>& view,
                           const std::vector<BodyProperties<Real>>& bodies, const Vec3d& gravity) {
  const double g = norm(gravity);
  if (!(g > 0)) throw std::invalid_argument("bed_height needs a non-zero gravity");
  const Vec3d up = gravity * (-1 / g);
  double highest = 0;
  for (int i = 0; i < view.count; ++i) {
    const double top = particle_top(view, bodies[view.template_id[i]], i, up);
    highest = i == 0 ? top : std::max(highest, top);
  }
  return highest;
}

template <class Real>
std::vector<TrajectoryRow> HostStep<Real>::trajectory_rows() const {
  return particle_rows(owned_view());
}

template <class Real>
double HostStep<Real>::kinetic_energy() const {
  return particle_kinetic_energy(owned_view(), bodies_);
}

template <class Real>
double HostStep<Real>::bed_height(const Vec3d& gravity) const {
  return particle_bed_height(owned_view(), bodies_, gravity);
}

template <class Real>
EnergyTerms HostStep<Real>::energy() const {
  EnergyTerms terms;
  particle_energies(owned_view(), bodies_,
                    scene_.effects.gravity ? &*scene_.effects.gravity : nullptr, terms);
  if (contacts_) {
    for (const PairContactRecord<Real>& c : contacts_->contacts()) {
      if (!attributed(c.a, c.b)) continue;
      terms.elastic_normal += c.normal_energy;
      terms.elastic_tangential += c.tangential_energy;
    }
  }
  if (walls_) {
    for (const WallContactRecord<Real>& c : walls_->contacts()) {
      terms.elastic_normal += c.normal_energy;
      terms.elastic_tangential += c.tangential_energy;
    }
  }
  terms.ledger = ledger_;
  return terms;
}

#define TALUS_INSTANTIATE_OUTPUTS(Real)                                                         \
  template std::vector<TrajectoryRow> particle_rows(const ParticleView<Real>&);                 \
  template double particle_kinetic_energy(const ParticleView<Real>&,                            \
                                          const std::vector<BodyProperties<Real>>&);            \
  template double particle_bed_height(const ParticleView<Real>&,                                \
                                      const std::vector<BodyProperties<Real>>&, const Vec3d&);  \
  template double particle_energy(const ParticleView<Real>&,                                    \
                                  const std::vector<BodyProperties<Real>>&, const Vec3d*, int); \
  template void particle_energies(const ParticleView<Real>&,                                    \
                                  const std::vector<BodyProperties<Real>>&, const Vec3d*,       \
                                  EnergyTerms&);
TALUS_INSTANTIATE_OUTPUTS(double)
TALUS_INSTANTIATE_OUTPUTS(float)
#undef TALUS_INSTANTIATE_OUTPUTS

#define TALUS_INSTANTIATE_MEMBERS(Real)                                        \
  template std::vector<TrajectoryRow> HostStep<Real>::trajectory_rows() const; \
  template double HostStep<Real>::kinetic_energy() const;                      \
  template double HostStep<Real>::bed_height(const Vec3d&) const;              \
  template EnergyTerms HostStep<Real>::energy() const;
TALUS_INSTANTIATE_MEMBERS(double)
TALUS_INSTANTIATE_MEMBERS(float)
#undef TALUS_INSTANTIATE_MEMBERS

}  // namespace talus
