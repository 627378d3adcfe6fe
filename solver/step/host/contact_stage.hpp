// Host driver of the particle-particle contact stages: the pair list (a Verlet list of candidate
// pairs from the broad phase, neighbor/contact_pairs.hpp: bounding spheres within r_a + r_b +
// skin, kept until some particle has moved 0.45 skin since it was built, the CUDA step's rule:
// step/cuda/cuda_pair_list.cuh), per candidate whose bounding spheres meet now the geometry and the
// force law (pair_kernels.hpp, templated on the scene's law: compute picks it once per call from
// contact/contact_laws.hpp) into the pair's own record, compaction of the touching pairs, the
// history store rebuilt from them (sorted global-id keys), and the deterministic accumulation in
// pair order. Host code: std::vector and exceptions allowed here, not in the per-pair functions.
//
// The list's age changes no bit: a pair apart by more than r_a + r_b + skin at the build cannot
// meet before one of its particles has moved 0.45 skin, so the list holds every pair whose
// bounding spheres meet now; compute keeps those that do by the broad phase's own test
// (spheres_overlap without skin) before any geometry, which is the list a broad phase without skin
// would give now, in the same (a, b) order. So are the touching pairs, their forces and sums.
//
// Threads (core/host_parallel.hpp): the pairs run on all of them, each with its own overlap
// workspaces, and the accumulation runs per particle, each particle adding its contacts in pair
// order (as the CUDA step's accumulate_kernel does): the additions of the serial loop over the
// contacts, in the same order per particle, so the forces are the same bits for any thread count.
// The displacement test that expires the list is a yes/no over particles (parallel_first_failure).
// The listing of the candidates that meet, the compaction, the history sort and the lists of each
// particle's contacts stay serial (a few percent of the stage; benchmarks/README.md).
#pragma once

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/contact/contact_laws.hpp"
#include "solver/contact/damping_calibration.hpp"
#include "solver/core/host_parallel.hpp"
#include "solver/domain/domain.hpp"
#include "solver/neighbor/contact_pairs.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/host/sorted_histories.hpp"
#include "solver/step/pair_kernels.hpp"
#include "solver/step/pair_report.hpp"
#include "solver/step/step_plan.hpp"

namespace talus {

template <class Real>
class PairContactStage {
 public:
  // `threads`: how many the host loops use (>= 1; HostStep resolves the default).
  PairContactStage(const Scene& scene, const std::vector<BodyProperties<Real>>& bodies,
                   int threads = 1)
      : scene_(scene),
        bodies_(bodies),
        model_(*scene.effects.contact),
        threads_(threads > 0 ? threads : 1),
        workspaces_(threads_) {
    // The list's skin: the scene's, else a tenth of the largest bounding diameter (as the CUDA
    // step's set_up_pairs, cuda_step.cu).
    double largest_radius = 0;
    for (const BodyProperties<Real>& b : bodies_)
      largest_radius = std::max(largest_radius, double(b.bounding_radius));
    skin_ = Real(scene.skin ? *scene.skin : 0.2 * largest_radius);
    const Effects& fx = scene.effects;
    const int n = static_cast<int>(scene.materials.size());
    for (const Material& m : scene.materials) {
      youngs_.push_back(Real(m.youngs_modulus));
      poisson_.push_back(Real(m.poisson_ratio));
    }
    const bool volume =
        with_contact_law(model_, [](auto law) { return decltype(law)::kVolumeGeometry; });
    const bool calibrated =
        with_contact_law(model_, [](auto law) { return decltype(law)::kCalibratedDamping; });
    bool any_sphere = false, any_polyhedron = false;
    for (const ParticleTemplate& t : scene.templates) {
      (t.kind == ParticleShapeKind::sphere ? any_sphere : any_polyhedron) = true;
    }
    if (volume && any_sphere && any_polyhedron) {
      throw StepNotSupported(
          contact_place(scene) + ": the " + to_string(model_) +
          " model has no sphere-polyhedron overlap; expected contact: {model: linear, ...} for "
          "scenes that mix spheres and polyhedra, got " +
          to_string(model_));
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
        // beta(eps) of the calibrated damping: only the paper's law uses it.
        damping_ratio_.push_back(calibrated ? Real(calibrated_damping_ratio_for(eps)) : Real(0));
      }
    }
    tables_.bodies = bodies_.data();
    tables_.youngs_modulus = youngs_.data();
    tables_.poisson_ratio = poisson_.data();
    tables_.pair_friction = friction_.data();
    tables_.pair_restitution = restitution_.data();
    tables_.pair_damping_ratio = damping_ratio_.data();
    tables_.materials = n;
    tables_.with_friction = fx.friction;
    tables_.time_step = Real(scene.time_step);
    tables_.linear.stiffness = Real(fx.linear.stiffness);
    tables_.linear.damping = Real(fx.linear.damping);
    tables_.linear.tangential_damping = Real(fx.linear.tangential_damping);
  }

  // Whether update_list rebuilds the list at the current positions: the first build, a skin of
  // 0, the particles changed (particles_changed, a restart without a reference), or some particle
  // has moved 0.45 skin from the reference (the positions at the last build; > as the CUDA step
  // compares: half the skin, less 10% for the round-off of the distances the broad phase
  // compared). Measured once per update (a pass over the particles).
  bool list_expired(const ParticleView<Real>& p) {
    if (expired_ < 0) expired_ = measure_expired(p) ? 1 : 0;
    return expired_ == 1;
  }

  // The list for this evaluation: rebuilt at p's positions when expired; after a restart that
  // imported a reference and is not expired, built at the reference positions, which gives the
  // uninterrupted run's list (so that the particles are renumbered, with `reorder`, at the same
  // steps as in that run); else kept.
  // Decomposed (docs/parallel.md): particles from `owned` on are another rank's ghosts, and a pair
  // of two ghosts is left out of the list (its owner computes it); -1: every particle is this
  // rank's.
  void update_list(const ParticleView<Real>& p, const Domain& domain = SingleDomain(),
                   int owned = -1) {
    owned_ = owned;
    const bool rebuild = list_expired(p);
    expired_ = -1;
    if (rebuild) {
      find_candidates(p, domain);
    } else if (!have_list_) {
      const std::size_t n = static_cast<std::size_t>(p.count);
      build(p, reference_.data(), reference_.data() + n, reference_.data() + 2 * n, domain);
    }
  }

  // Builds the list at p's positions now and keeps them as the reference: every pair whose
  // bounding spheres are within the skin (|x_a - x_b| <= r_a + r_b + skin), on a grid anchored
  // at the local domain's reach box when that is bounded.
  void find_candidates(const ParticleView<Real>& p, const Domain& domain = SingleDomain()) {
    build(p, p.position.x, p.position.y, p.position.z, domain);
    const std::size_t n = static_cast<std::size_t>(p.count);
    reference_.resize(3 * n);
    std::copy(p.position.x, p.position.x + n, reference_.begin());
    std::copy(p.position.y, p.position.y + n, reference_.begin() + n);
    std::copy(p.position.z, p.position.z + n, reference_.begin() + 2 * n);
    have_reference_ = true;
    stale_ = false;
  }

  // The particles were appended to, removed or renumbered: the next update rebuilds the list.
  void particles_changed() {
    stale_ = true;
    expired_ = -1;
  }

  // The reference positions (3 per particle, x then y then z; empty without a skin, before the
  // first build, or when the particles changed since: the next update rebuilds then anyway) and
  // whether the particles changed since the last build, as StepState holds the CUDA step's.
  void export_reference(std::vector<Real>& reference, bool& stale) const {
    stale = stale_;
    reference.clear();
    if (skin_ > 0 && have_reference_ && !stale_) reference = reference_;
  }
  // Setting them on a resumed step of `count` particles (before its first update): the list is
  // built again, at the reference positions unless it has expired (update_list). A reference that
  // does not fit (another length, none) makes the next update rebuild at the current positions.
  void import_reference(const std::vector<Real>& reference, bool stale, int count) {
    stale_ = stale;
    expired_ = -1;
    have_list_ = false;
    have_reference_ =
        skin_ > 0 && count > 0 && reference.size() == 3 * static_cast<std::size_t>(count);
    reference_ = have_reference_ ? reference : std::vector<Real>();
  }

  Real skin() const { return skin_; }
  long long list_builds() const { return builds_; }
  std::size_t candidate_count() const { return candidates_.size(); }

  // Narrow phase, overlap and force law per candidate; compaction; the next history store.
  // A degenerate pair throws after the loop, the lowest pair index first, as the serial loop did.
  void compute(const ParticleView<Real>& p, Real spring_dt) {
    with_contact_law(model_, [&](auto law) { compute<decltype(law)>(p, spring_dt); });
  }

  // compute under the law Law (the scene's).
  template <class Law>
  void compute(const ParticleView<Real>& p, Real spring_dt) {
    // The candidates whose bounding spheres meet now, by the broad phase's test without skin
    // (spheres_overlap: the same terms as build_candidate_pairs'), in list order: flagged per
    // candidate (threads), then listed (serial). The rest lie in the skin only.
    NeighborInput<Real> spheres;
    spheres.x = p.position.x, spheres.y = p.position.y, spheres.z = p.position.z;
    spheres.radius = p.bounding_radius;
    spheres.count = p.count;
    const long long listed = static_cast<long long>(candidates_.size());
    meeting_.resize(candidates_.size());
    parallel_for(threads_, listed, [&](long long k) {
      meeting_[k] = spheres_overlap(spheres, candidates_[k].a, candidates_[k].b) ? 1 : 0;
    });
    evaluated_.clear();
    for (long long k = 0; k < listed; ++k)
      if (meeting_[k]) evaluated_.push_back(candidates_[k]);
    const long long count = static_cast<long long>(evaluated_.size());
    records_.resize(evaluated_.size());
    const int old_count = static_cast<int>(keys_.size());
    // Chunks of 64 pairs: a touching pair costs an overlap, a distant one little (dynamic
    // scheduling balances them; each record has its own slot, so the order does not matter).
    parallel_for_dynamic(threads_, count, 64, [&](long long k) {
      int ia, ib;
      order_pair(p, tables_, evaluated_[k].a, evaluated_[k].b, ia, ib);
      const PairGeometryData<Real> g = geometry<Law>(p, ia, ib, workspaces_[host_thread_index()]);
      records_[k] = pair_contact_force<Law>(p, tables_, ia, ib, g, spring_dt, keys_.data(),
                                            histories_.data(), old_count);
    });
    for (const PairContactRecord<Real>& r : records_) {
      if (r.degenerate) {
        throw std::runtime_error(
            degenerate_pair_message(scene_, pose_report(p, r.a), pose_report(p, r.b)));
      }
    }
    contacts_.clear();
    for (const PairContactRecord<Real>& r : records_) {
      if (r.in_contact) contacts_.push_back(r);
    }
    if constexpr (Law::kTangentialHistory) sort_histories_by_key(contacts_, keys_, histories_);
  }

  // Whether some particle of [0, owned) has moved 0.45 skin since the list's build (or the
  // particles changed, or there is no list): the decomposed step's share of the ranks' decision
  // to rebuild, made before the ghosts are brought up to date.
  bool moved_beyond_skin(const ParticleView<Real>& p, int owned) const {
    const std::size_t n = reference_.size() / 3;
    return static_cast<std::size_t>(owned) > n || moved_since_build(p, owned, n);
  }

  // Per-particle sums (deterministic): each particle's contacts listed (serial), then one
  // particle per index (threads) adding them as add_pair_force would, in the order of the
  // partners' global ids, which neither the particles' order in memory nor the ranks they are
  // spread over change (docs/parallel.md).
  void accumulate(const ParticleView<Real>& p) {
    entry_begin_.assign(p.count + 1, 0);
    for (const PairContactRecord<Real>& c : contacts_) {
      ++entry_begin_[c.a + 1];
      ++entry_begin_[c.b + 1];
    }
    for (int i = 0; i < p.count; ++i) entry_begin_[i + 1] += entry_begin_[i];
    entry_fill_.assign(entry_begin_.begin(), entry_begin_.end() - 1);
    entry_contact_.resize(2 * contacts_.size());
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
      entry_contact_[entry_fill_[contacts_[k].a]++] = static_cast<int>(k);
      entry_contact_[entry_fill_[contacts_[k].b]++] = static_cast<int>(k);
    }
    parallel_for(threads_, p.count, [&](long long index) {
      const int i = static_cast<int>(index);
      if (entry_begin_[i] == entry_begin_[i + 1]) return;
      const auto partner = [&](int k) {
        const PairContactRecord<Real>& c = contacts_[k];
        return p.global_id[c.a == i ? c.b : c.a];
      };
      std::sort(entry_contact_.begin() + entry_begin_[i],
                entry_contact_.begin() + entry_begin_[i + 1],
                [&](int k, int l) { return partner(k) < partner(l); });
      // add_pair_force's additions for particle i, in its order: f + F_a or f - F_a, and
      // t + ((x_c - x) x (+-F_a) +- couple).
      Vec3<Real> f = p.force.get(i), t;
      const bool torque = p.torque.present();
      if (torque) t = p.torque.get(i);
      const Vec3<Real> x = p.position.get(i);
      for (int s = entry_begin_[i]; s < entry_begin_[i + 1]; ++s) {
        const PairContactRecord<Real>& c = contacts_[entry_contact_[s]];
        if (c.a == i) {
          f = f + c.force_on_a;
          if (torque) t = t + (cross(c.point - x, c.force_on_a) + c.couple);
        } else {
          f = f - c.force_on_a;
          if (torque) t = t + (cross(c.point - x, -c.force_on_a) - c.couple);
        }
      }
      p.force.set(i, f);
      if (torque) p.torque.set(i, t);
    });
  }

  std::size_t contact_count() const { return contacts_.size(); }
  const PairLawTables<Real>& tables() const { return tables_; }
  const std::vector<PairContactRecord<Real>>& contacts() const { return contacts_; }
  std::size_t history_count() const { return keys_.size(); }
  // The history store (the touching pairs of the last evaluation, sorted by key), and setting it
  // (a restart: the next evaluation looks its histories up in it).
  const std::vector<PairKey>& history_keys() const { return keys_; }
  const std::vector<ContactHistoryData<Real>>& histories() const { return histories_; }
  void set_histories(std::vector<PairKey> keys, std::vector<ContactHistoryData<Real>> histories) {
    keys_ = std::move(keys);
    histories_ = std::move(histories);
  }
  int threads() const { return threads_; }
  std::size_t allocated_bytes() const {
    std::size_t bytes =
        (candidates_.capacity() + evaluated_.capacity()) * sizeof(ContactPair) +
        reference_.capacity() * sizeof(Real) + meeting_.capacity() +
        (records_.capacity() + contacts_.capacity()) * sizeof(PairContactRecord<Real>) +
        keys_.capacity() * sizeof(PairKey) +
        histories_.capacity() * sizeof(ContactHistoryData<Real>) +
        (entry_begin_.capacity() + entry_fill_.capacity() + entry_contact_.capacity()) *
            sizeof(int);
    for (const Workspaces& w : workspaces_) bytes += w.bytes;
    return bytes;
  }

 private:
  // One overlap workspace per capacity, made on first use (a scene of spheres allocates none);
  // one set per thread, each touched only by its thread.
  struct Workspaces {
    std::unique_ptr<OverlapWorkspace<Real, 32>> ws32;
    std::unique_ptr<OverlapWorkspace<Real, 64>> ws64;
    std::unique_ptr<OverlapWorkspace<Real, 128>> ws128;
    std::unique_ptr<OverlapWorkspace<Real, 256>> ws256;
    std::size_t bytes = 0;
  };

  // The pair's geometry under Law: two polyhedra under a law of volume geometry need an overlap
  // workspace (polyhedra_geometry), the rest none.
  template <class Law>
  PairGeometryData<Real> geometry(const ParticleView<Real>& p, int ia, int ib,
                                  Workspaces& ws) const {
    if constexpr (Law::kVolumeGeometry) {
      const BodyProperties<Real>& a = bodies_[p.template_id[ia]];
      const BodyProperties<Real>& b = bodies_[p.template_id[ib]];
      if (!a.sphere && !b.sphere) return polyhedra_geometry(p, ia, ib, a, b, ws);
    }
    return simple_pair_geometry<Law>(p, tables_, ia, ib);
  }

  // Two polyhedra's overlap, in the workspace of their capacity.
  PairGeometryData<Real> polyhedra_geometry(const ParticleView<Real>& p, int ia, int ib,
                                            const BodyProperties<Real>& a,
                                            const BodyProperties<Real>& b, Workspaces& ws) const {
    const Pose<Real> pose_a{p.position.get(ia), p.orientation.get(ia)};
    const Pose<Real> pose_b{p.position.get(ib), p.orientation.get(ib)};
    switch (overlap_capacity_for(a.faces + b.faces)) {
      case 32:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws, ws.ws32));
      case 64:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws, ws.ws64));
      case 128:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws, ws.ws128));
      default:
        return polyhedra_volume_geometry(a.shape, pose_a, b.shape, pose_b, workspace(ws, ws.ws256));
    }
  }

  // The list at the positions x, y, z (p's or the reference), p's bounding radii.
  void build(const ParticleView<Real>& p, const Real* x, const Real* y, const Real* z,
             const Domain& domain) {
    NeighborInput<Real> input;
    const Box reach = domain.reach_box();
    if (reach.bounded()) {
      input.fixed_origin = true;
      input.origin[0] = Real(reach.min.x), input.origin[1] = Real(reach.min.y);
      input.origin[2] = Real(reach.min.z);
    }
    input.x = x;
    input.y = y;
    input.z = z;
    input.radius = p.bounding_radius;
    input.count = p.count;
    input.skin = skin_;
    candidates_ = build_candidate_pairs(input, nullptr, Real(0), threads_);
    if (owned_ >= 0 && owned_ < p.count) {
      const int owned = owned_;
      candidates_.erase(
          std::remove_if(candidates_.begin(), candidates_.end(),
                         [owned](const ContactPair& c) { return c.a >= owned && c.b >= owned; }),
          candidates_.end());
    }
    have_list_ = true;
    ++builds_;
  }

  bool measure_expired(const ParticleView<Real>& p) const {
    const std::size_t n = static_cast<std::size_t>(p.count);
    return reference_.size() != 3 * n || moved_since_build(p, p.count, n);
  }

  // Whether some particle of [0, count) has moved 0.45 skin from the reference positions of a
  // build of n particles (or there is no usable reference): in double, as the CUDA step's
  // max_displacement_kernel.
  bool moved_since_build(const ParticleView<Real>& p, int count, std::size_t n) const {
    if (!(skin_ > 0) || !have_reference_ || stale_) return true;
    const double limit = 0.45 * double(skin_), limit2 = limit * limit;
    const Real *x0 = reference_.data(), *y0 = x0 + n, *z0 = y0 + n;
    const long long moved = parallel_first_failure(threads_, count, [&](long long i) {
      const double dx = double(p.position.x[i]) - double(x0[i]);
      const double dy = double(p.position.y[i]) - double(y0[i]);
      const double dz = double(p.position.z[i]) - double(z0[i]);
      return dx * dx + dy * dy + dz * dz > limit2;
    });
    return moved < count;
  }

  template <class Workspace>
  static Workspace& workspace(Workspaces& set, std::unique_ptr<Workspace>& slot) {
    if (!slot) {
      slot = std::make_unique<Workspace>();
      set.bytes += sizeof(Workspace);
    }
    return *slot;
  }

  const Scene& scene_;
  const std::vector<BodyProperties<Real>>& bodies_;
  ContactModel model_;  // the scene's law, dispatched on once per compute
  int threads_;
  std::vector<Workspaces> workspaces_;  // per thread
  std::vector<Real> youngs_, poisson_, friction_, restitution_, damping_ratio_;
  PairLawTables<Real> tables_;
  // The pair list: candidates_ built at the positions reference_ (x, then y, then z) with the
  // skin, while have_list_ (false after a restart until the next update).
  Real skin_ = 0;
  std::vector<ContactPair> candidates_;
  std::vector<Real> reference_;
  // compute's scratch: whether each candidate's bounding spheres meet, and those that do.
  std::vector<unsigned char> meeting_;
  std::vector<ContactPair> evaluated_;
  bool have_reference_ = false;  // reference_ holds the positions of a build
  bool have_list_ = false;
  bool stale_ = false;  // the particles changed since the last build
  int expired_ = -1;    // list_expired's answer until the next update (-1: not measured)
  int owned_ = -1;      // update_list's: from it on ghosts (-1: none)
  long long builds_ = 0;
  std::vector<PairContactRecord<Real>> records_, contacts_;
  std::vector<PairKey> keys_;  // sorted
  std::vector<ContactHistoryData<Real>> histories_;
  // Particle i's contacts: contacts_[entry_contact_[s]] for s in [entry_begin_[i],
  // entry_begin_[i + 1]), ascending (pair order); entry_fill_ is the scratch of the fill.
  std::vector<int> entry_begin_, entry_fill_, entry_contact_;
};

}  // namespace talus
