// Host driver of the particle-particle contact stages: candidate pairs from the broad phase
// (neighbor/contact_pairs.hpp: bounding spheres), per pair the geometry and the force law
// (pair_kernels.hpp) into the pair's own record, compaction of the touching pairs, the history
// store rebuilt from them (sorted global-id keys), and the deterministic accumulation in pair
// order. Host code: std::vector and exceptions allowed here, not in the per-pair functions.
#pragma once

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/contact/damping_calibration.hpp"
#include "solver/neighbor/contact_pairs.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/pair_kernels.hpp"
#include "solver/step/sorted_histories.hpp"
#include "solver/step/step_plan.hpp"

namespace talus {

template <class Real>
class PairContactStage {
 public:
  PairContactStage(const Scene& scene, const std::vector<BodyProperties<Real>>& bodies)
      : scene_(scene), bodies_(bodies) {
    const Effects& fx = scene.effects;
    const int n = static_cast<int>(scene.materials.size());
    for (const Material& m : scene.materials) {
      youngs_.push_back(Real(m.youngs_modulus));
      poisson_.push_back(Real(m.poisson_ratio));
    }
    const bool volume = *fx.contact == ContactModel::volume;
    bool any_sphere = false, any_polyhedron = false;
    for (const ParticleTemplate& t : scene.templates) {
      (t.kind == ParticleShapeKind::sphere ? any_sphere : any_polyhedron) = true;
    }
    if (volume && any_sphere && any_polyhedron) {
      throw StepNotSupported(
          scene.file +
          ": effects.contact: the volume model has no sphere-polyhedron overlap; use "
          "contact: linear for scenes that mix spheres and polyhedra");
    }
    for (const BodyProperties<Real>& b : bodies_) {
      for (const BodyProperties<Real>& c : bodies_) {
        if (volume && !b.sphere && !c.sphere && b.faces + c.faces > 256) {
          throw StepNotSupported(scene.file +
                                 ": templates: two templates with more than 256 faces "
                                 "together exceed the overlap workspace");
        }
      }
    }
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        friction_.push_back(Real(scene.pair_friction(a, b)));
        const double eps = scene.pair_restitution(a, b);
        restitution_.push_back(Real(eps));
        damping_ratio_.push_back(volume ? Real(calibrated_damping_ratio_for(eps)) : Real(0));
      }
    }
    tables_.bodies = bodies_.data();
    tables_.youngs_modulus = youngs_.data();
    tables_.poisson_ratio = poisson_.data();
    tables_.pair_friction = friction_.data();
    tables_.pair_restitution = restitution_.data();
    tables_.pair_damping_ratio = damping_ratio_.data();
    tables_.materials = n;
    tables_.volume_model = volume;
    tables_.with_friction = fx.friction;
    tables_.time_step = Real(scene.time_step);
    tables_.linear.stiffness = Real(fx.linear.stiffness);
    tables_.linear.damping = Real(fx.linear.damping);
    tables_.linear.tangential_damping = Real(fx.linear.tangential_damping);
  }

  // Broad phase: every pair whose bounding spheres meet (|x_a - x_b| <= r_a + r_b).
  void find_candidates(const ParticleView<Real>& p) {
    NeighborInput<Real> input;
    input.x = p.position.x;
    input.y = p.position.y;
    input.z = p.position.z;
    input.radius = p.bounding_radius;
    input.count = p.count;
    candidates_ = build_candidate_pairs(input);
  }

  // Narrow phase, overlap and force law per candidate; compaction; the next history store.
  void compute(const ParticleView<Real>& p, Real spring_dt) {
    records_.resize(candidates_.size());
    const int old_count = static_cast<int>(keys_.size());
    for (std::size_t k = 0; k < candidates_.size(); ++k) {
      int ia, ib;
      order_pair(p, tables_, candidates_[k].a, candidates_[k].b, ia, ib);
      const PairGeometryData<Real> g = geometry(p, ia, ib);
      records_[k] = pair_contact_force(p, tables_, ia, ib, g, spring_dt, keys_.data(),
                                       histories_.data(), old_count);
      if (records_[k].degenerate) {
        throw std::runtime_error(
            scene_.file + ": particles " + std::to_string(p.global_id[ia]) + " and " +
            std::to_string(p.global_id[ib]) +
            ": the contact geometry is degenerate (a sphere inside another, or an overlap the "
            "workspace cannot hold)");
      }
    }
    contacts_.clear();
    for (const PairContactRecord<Real>& r : records_) {
      if (r.in_contact) contacts_.push_back(r);
    }
    if (tables_.volume_model) sort_histories_by_key(contacts_, keys_, histories_);
  }

  // Per-particle sums in pair order (deterministic).
  void accumulate(const ParticleView<Real>& p) const {
    for (const PairContactRecord<Real>& c : contacts_) add_pair_force(p, c);
  }

  std::size_t contact_count() const { return contacts_.size(); }
  const PairLawTables<Real>& tables() const { return tables_; }
  const std::vector<PairContactRecord<Real>>& contacts() const { return contacts_; }
  std::size_t history_count() const { return keys_.size(); }
  std::size_t allocated_bytes() const {
    return candidates_.capacity() * sizeof(ContactPair) +
           (records_.capacity() + contacts_.capacity()) * sizeof(PairContactRecord<Real>) +
           keys_.capacity() * sizeof(PairKey) +
           histories_.capacity() * sizeof(ContactHistoryData<Real>) + workspace_bytes_;
  }

 private:
  PairGeometryData<Real> geometry(const ParticleView<Real>& p, int ia, int ib) {
    const BodyProperties<Real>& a = bodies_[p.template_id[ia]];
    const BodyProperties<Real>& b = bodies_[p.template_id[ib]];
    if (!tables_.volume_model || a.sphere || b.sphere) {
      return simple_pair_geometry(p, tables_, ia, ib);
    }
    const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
    const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
    switch (overlap_capacity_for(a.faces + b.faces)) {
      case 32:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws32_));
      case 64:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws64_));
      case 128:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws128_));
      default:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws256_));
    }
  }

  // One workspace per capacity, made on first use (a scene of spheres allocates none).
  template <class Workspace>
  Workspace& workspace(std::unique_ptr<Workspace>& slot) {
    if (!slot) {
      slot = std::make_unique<Workspace>();
      workspace_bytes_ += sizeof(Workspace);
    }
    return *slot;
  }

  const Scene& scene_;
  const std::vector<BodyProperties<Real>>& bodies_;
  std::vector<Real> youngs_, poisson_, friction_, restitution_, damping_ratio_;
  PairLawTables<Real> tables_;
  std::vector<ContactPair> candidates_;
  std::vector<PairContactRecord<Real>> records_, contacts_;
  std::vector<PairKey> keys_;  // sorted
  std::vector<ContactHistoryData<Real>> histories_;
  std::unique_ptr<OverlapWorkspace<Real, 32>> ws32_;
  std::unique_ptr<OverlapWorkspace<Real, 64>> ws64_;
  std::unique_ptr<OverlapWorkspace<Real, 128>> ws128_;
  std::unique_ptr<OverlapWorkspace<Real, 256>> ws256_;
  std::size_t workspace_bytes_ = 0;
};

}  // namespace talus
