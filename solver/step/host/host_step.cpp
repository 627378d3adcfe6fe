#include "solver/step/host/host_step.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "solver/core/host_parallel.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/step/host/contact_stage.hpp"
#include "solver/step/host/wall_stage.hpp"

namespace talus {

namespace {

double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

// Mass properties of a template with its material's density (in double, then rounded once).
template <class Real>
BodyProperties<Real> body_properties(const Scene& scene, const ParticleTemplate& t,
                                     const ShapeArrays<Real>* arrays) {
  const double density = scene.materials.at(t.material).density;
  BodyProperties<Real> body;
  body.material = t.material;
  if (t.kind == ParticleShapeKind::sphere) {
    const double r = t.sphere_radius;
    const double mass = density * 4 * M_PI * r * r * r / 3;
    body.sphere = true;
    body.mass = Real(mass);
    body.inertia =
        Vec3<Real>(Real(0.4 * mass * r * r), Real(0.4 * mass * r * r), Real(0.4 * mass * r * r));
    body.bounding_radius = body.equivalent_radius = body.sphere_radius = Real(r);
  } else {
    const ShapeTemplate& s = t.shape;
    body.mass = Real(density * s.volume);
    body.inertia = Vec3<Real>(s.principal_moments * density);
    body.bounding_radius = arrays->bounding_radius;
    body.equivalent_radius = Real(std::cbrt(3 * s.volume / (4 * M_PI)));
    body.shape = arrays->view();
    body.faces = body.shape.n_faces;
  }
  if (!(body.mass > 0) || !(body.inertia.x > 0 && body.inertia.y > 0 && body.inertia.z > 0)) {
    throw std::runtime_error(t.source.where() + ": template '" + t.name +
                             "' has no positive mass and moments in this precision");
  }
  return body;
}

template BodyProperties<double> body_properties(const Scene&, const ParticleTemplate&,
                                                const ShapeArrays<double>*);
template BodyProperties<float> body_properties(const Scene&, const ParticleTemplate&,
                                               const ShapeArrays<float>*);

template <class Real>
HostStep<Real>::HostStep(const Scene& scene, int threads, WallSearch wall_search)
    : scene_(scene),
      plan_(plan_step(scene)),
      dt_(Real(scene.time_step)),
      threads_(host_thread_count(threads)),
      domain_(make_scene_domain(scene)),
      feeding_(scene) {
  for (const ParticleTemplate& t : scene.templates) {
    shapes_.push_back(t.kind == ParticleShapeKind::polyhedron
                          ? std::make_unique<ShapeArrays<Real>>(t.shape)
                          : nullptr);
    bodies_.push_back(body_properties(scene, t, shapes_.back().get()));
  }
  const std::vector<ParticleState> initial = initial_particles(scene);
  count_ = static_cast<int>(initial.size());
  left_out_ = scene.left_out_particles;
  for (const std::string& name : particle_array_names(plan_.arrays)) allocate(name);
  for (auto* ids : {&template_ids_, &material_ids_}) ids->reserve(std::max(count_, 1));
  global_ids_.reserve(std::max(count_, 1));
  template_ids_.resize(count_);
  material_ids_.resize(count_);
  global_ids_.resize(count_);
  bind_view();
  for (int i = 0; i < count_; ++i) set_particle(i, initial[i]);
  owned_ = count_;
  if (plan_.contacts) {
    contacts_ = std::make_unique<PairContactStage<Real>>(scene, bodies_, threads_);
  }
  if (plan_.walls)
    walls_ = std::make_unique<WallContactStage<Real>>(scene, bodies_, threads_, wall_search);
}

template <class Real>
HostStep<Real>::~HostStep() = default;

template <class Real>
Real* HostStep<Real>::allocate(const std::string& name) {
  std::vector<Real> values;
  values.reserve(std::max(count_, 1));  // never a null pointer: present() tells arrays apart
  values.resize(count_, Real(0));
  storage_.emplace_back(name, std::move(values));
  return storage_.back().second.data();
}

template <class Real>
void HostStep<Real>::bind_view() {
  const auto array = [&](const std::string& name) -> Real* {
    for (auto& entry : storage_)
      if (entry.first == name) return entry.second.data();
    return nullptr;  // an array the plan does not need
  };
  view_ = view_over<Real>(array);
  view_.count = count_;
  view_.template_id = template_ids_.data();
  view_.material_id = material_ids_.data();
  view_.global_id = global_ids_.data();
}

template <class Real>
void HostStep<Real>::grow(int count) {
  const auto resize = [&](auto& values) {
    if (values.capacity() < static_cast<std::size_t>(count))
      values.reserve(std::max<std::size_t>(count, 2 * values.capacity()));
    values.resize(count);
  };
  for (auto& entry : storage_) resize(entry.second);
  resize(template_ids_);
  resize(material_ids_);
  resize(global_ids_);
  count_ = count;
  bind_view();
}

template <class Real>
void HostStep<Real>::set_particle(int i, const ParticleState& p, long long id) {
  const BodyProperties<Real>& body = bodies_.at(p.template_index);
  template_ids_[i] = p.template_index;
  material_ids_[i] = body.material;
  global_ids_[i] = id >= 0 ? id : next_id_++;
  view_.position.set(i, Vec3<Real>(p.position));
  view_.velocity.set(i, Vec3<Real>(p.velocity));
  const Quatd q = p.orientation.normalized();
  view_.orientation.set(i, Quat<Real>(q));
  if (view_.angular_velocity.present()) {
    // The scene gives it in the world frame; Euler's equations want the body frame.
    view_.angular_velocity.set(i, Vec3<Real>(rotate_inverse(q, p.angular_velocity)));
  }
  if (view_.bounding_radius) view_.bounding_radius[i] = body.bounding_radius;
}

template <class Real>
void HostStep<Real>::feed() {
  if (!feeding_.due(time_)) return;
  std::vector<Vec3d> positions;
  std::vector<ParticleState> added;
  std::vector<long long> ids;
  if (comm_) {
    // Every rank runs the feeds on every rank's particles (the same insertions, the same feed
    // states), numbers every insertion some rank owns as one process would, and keeps its own.
    std::vector<int> templates;
    const double start = clock_seconds();
    gather_all(positions, templates);
    exchange_seconds_ += clock_seconds() - start;
    const std::vector<ParticleState> all =
        feeding_.insert_all(time_, std::move(positions), templates);
    for (const ParticleState& p : all) {
      const int owner = domain_->owner(p.position);
      if (owner < 0) continue;
      const long long id = next_id_++;
      if (owner == comm_->rank()) added.push_back(p), ids.push_back(id);
    }
    if (all.empty()) return;
    changed_ = true;
    drop_ghosts();
  } else {
    positions.reserve(count_);
    for (int i = 0; i < count_; ++i) positions.push_back(Vec3d(view_.position.get(i)));
    added = feeding_.insert(time_, std::move(positions), template_ids_, *domain_);
  }
  if (added.empty()) return;
  const int first = count_;
  grow(count_ + static_cast<int>(added.size()));
  owned_ = count_;
  if (contacts_) contacts_->particles_changed();  // the new particles have no candidates yet
  const ParticleView<Real> p = view_;
  for (std::size_t k = 0; k < added.size(); ++k) {
    const int i = first + static_cast<int>(k);
    set_particle(i, added[k], ids.empty() ? -1 : ids[k]);
    ledger_.fed += particle_energy(view_, bodies_,
                                   scene_.effects.gravity ? &*scene_.effects.gravity : nullptr, i);
    // The first half-step uses the stored forces: the new particle's body forces now (it
    // touches nothing: the feed places it clear of particles and walls), as the reference's
    // add_body gives them.
    if (p.force.present()) {
      clear_forces(p, i);
      if (plan_.gravity) add_gravity(p, bodies_.data(), i, Vec3<Real>(*scene_.effects.gravity));
      if (plan_.drag) add_drag(p, i, Real(*scene_.effects.drag_alpha));
    } else if (p.torque.present()) {
      p.torque.set(i, Vec3<Real>());
    }
  }
}

template <class Real>
void HostStep<Real>::keep_particles(const std::vector<int>& order) {
  // Gathered into a scratch vector, then copied back: each array keeps its storage (shrinking
  // never reallocates), so the capacity kept for feeds stays.
  const auto gather = [&](auto& values) {
    std::remove_reference_t<decltype(values)> kept(order.size());
    parallel_for(threads_, static_cast<long long>(order.size()),
                 [&](long long k) { kept[k] = values[order[k]]; });
    values.resize(order.size());
    std::copy(kept.begin(), kept.end(), values.begin());
  };
  for (auto& entry : storage_) gather(entry.second);
  gather(template_ids_);
  gather(material_ids_);
  gather(global_ids_);
  count_ = owned_ = static_cast<int>(order.size());  // decomposed: `order` names its own only
  bind_view();
  if (contacts_) contacts_->particles_changed();  // the list names the old indices
  changed_ = true;
}

template <class Real>
void HostStep<Real>::reorder_by_cell() {
  NeighborInput<Real> in;
  in.x = view_.position.x, in.y = view_.position.y, in.z = view_.position.z;
  in.radius = view_.bounding_radius;
  in.count = count_;
  keep_particles(cell_order(in, threads_));
}

template <class Real>
void HostStep<Real>::remove_outside() {
  const Domain& d = *domain_;
  std::vector<int> kept;
  kept.reserve(count_);
  const Vec3d* gravity = scene_.effects.gravity ? &*scene_.effects.gravity : nullptr;
  for (int i = 0; i < owned_; ++i) {
    const Vec3d x(view_.position.get(i));
    // A non-finite position is no departure: the run's watchdog reports it.
    if (d.owner(x) >= 0 || !is_finite(x.x + x.y + x.z)) {
      kept.push_back(i);
    } else {
      ledger_.removed += particle_energy(view_, bodies_, gravity, i);
    }
  }
  if (static_cast<int>(kept.size()) == owned_) return;
  removed_ += owned_ - static_cast<long long>(kept.size());
  keep_particles(kept);  // the ghosts go too; the next exchange sends them again
}

template <class Real>
std::vector<std::string> HostStep<Real>::allocated_arrays() const {
  std::vector<std::string> names;
  for (const auto& [name, values] : storage_) names.push_back(name);
  names.insert(names.end(), {"template_id", "material_id", "global_id"});
  return names;
}

template <class Real>
std::size_t HostStep<Real>::allocated_bytes() const {
  std::size_t bytes = count_ * (2 * sizeof(int) + sizeof(long long));
  for (const auto& entry : storage_) bytes += entry.second.size() * sizeof(Real);
  if (contacts_) bytes += contacts_->allocated_bytes();
  if (walls_) bytes += walls_->allocated_bytes();
  return bytes;
}

template <class Real>
std::size_t HostStep<Real>::pair_contact_count() const {
  if (!contacts_) return 0;
  if (!comm_) return contacts_->contact_count();
  std::size_t n = 0;
  for (const PairContactRecord<Real>& c : contacts_->contacts()) n += attributed(c.a, c.b) ? 1 : 0;
  return n;
}

template <class Real>
long long HostStep<Real>::pair_list_builds() const {
  return contacts_ ? contacts_->list_builds() : 0;
}

template <class Real>
std::size_t HostStep<Real>::candidate_pair_count() const {
  return contacts_ ? contacts_->candidate_count() : 0;
}

template <class Real>
std::size_t HostStep<Real>::wall_contact_count() const {
  return walls_ ? walls_->contact_count() : 0;
}

template <class Real>
Vec3d HostStep<Real>::wall_force(int w) const {
  return walls_ ? walls_->wall_force(w) : Vec3d();
}

template <class Real>
Vec3d HostStep<Real>::wall_torque(int w) const {
  return walls_ ? walls_->wall_torque(w) : Vec3d();
}

template <class Real>
template <class Body>
void HostStep<Real>::timed(Stage stage, Body&& body) {
  const double start = clock_seconds();
  body();
  stage_seconds_[static_cast<int>(stage)] += clock_seconds() - start;
}

template <class Real>
void HostStep<Real>::run_force_stages(Real spring_dt) {
  ParticleView<Real> p = view_;
  const BodyProperties<Real>* bodies = bodies_.data();
  // The per-particle stages touch particle i only: any split over threads gives the same bits.
  const auto each_particle = [&](auto&& body) {
    parallel_for(threads_, count_, [&](long long i) { body(static_cast<int>(i)); });
  };
  for (const Stage stage : plan_.stages) {
    switch (stage) {
      case Stage::clear_forces:
        timed(stage, [&] { each_particle([&](int i) { clear_forces(p, i); }); });
        break;
      case Stage::gravity:
        timed(stage, [&] {
          const Vec3<Real> g(*scene_.effects.gravity);
          each_particle([&](int i) { add_gravity(p, bodies, i, g); });
        });
        break;
      case Stage::drag:
        timed(stage, [&] {
          const Real alpha = Real(*scene_.effects.drag_alpha);
          each_particle([&](int i) { add_drag(p, i, alpha); });
        });
        break;
      case Stage::candidate_pairs:
        timed(stage, [&] {
          // With `reorder`, the particles are renumbered where the list expires (and only there:
          // a resumed run renumbers at the same steps as the uninterrupted one).
          // Decomposed, the ghosts follow the rank's own particles: none are renumbered.
          if (!comm_ && scene_.reorder.value_or(false) && contacts_->list_expired(p)) {
            reorder_by_cell();
            p = view_;
          }
          contacts_->update_list(p, *domain_, comm_ ? owned_ : -1);
        });
        break;
      case Stage::pair_contacts:
        timed(stage, [&] { contacts_->compute(p, spring_dt); });
        break;
      case Stage::wall_contacts:
        timed(stage, [&] {
          walls_->place(time_);
          walls_->compute(owned_view(), contacts_->tables(), spring_dt);  // a ghost's: its owner's
        });
        break;
      case Stage::accumulate:
        timed(stage, [&] {
          contacts_->accumulate(p);  // pairs first, then walls, each in order
          if (walls_) walls_->accumulate(owned_view());
        });
        break;
      case Stage::integrate_begin:
      case Stage::integrate_end:
        break;
    }
  }
}

template <class Real>
ContactRates HostStep<Real>::contact_rates() const {
  ContactRates r;
  if (contacts_) {
    for (const PairContactRecord<Real>& c : contacts_->contacts()) {
      if (!attributed(c.a, c.b)) continue;
      r.dissipation += c.dissipation;
      r.spring += c.tangential_energy;
    }
  }
  if (walls_) {
    for (const WallContactRecord<Real>& c : walls_->contacts()) {
      r.dissipation += c.dissipation;
      r.wall_power += c.wall_power;
      r.spring += c.tangential_energy;
    }
  }
  return r;
}

template <class Real>
void HostStep<Real>::evaluate_forces() {
  if (comm_) {
    exchange(true);
    std::exception_ptr failure;
    try {
      run_force_stages(Real(0));
    } catch (...) {
      failure = std::current_exception();
    }
    agree_on_failure(*comm_, failure);
  } else {
    run_force_stages(Real(0));
  }
  forces_ready_ = true;
  ledger_.start(contact_rates());
}

template <class Real>
void HostStep<Real>::step() {
  if (!forces_ready_) evaluate_forces();  // F_0, T_0 for the first half-step
  if (walls_) walls_->open_outlets(time_);
  if (!feeding_.empty()) feed();
  const ParticleView<Real> p = view_;
  const BodyProperties<Real>* bodies = bodies_.data();
  // Decomposed, a stage that fails on some rank fails on every rank, with its message
  // (agree_on_failure), before the next exchange; one process throws at once.
  const auto stage = [&](auto&& body) {
    if (!comm_) return body();
    std::exception_ptr failure;
    try {
      body();
    } catch (...) {
      failure = std::current_exception();
    }
    agree_on_failure(*comm_, failure);
  };
  stage([&] {
    timed(Stage::integrate_begin, [&] {
      // Every particle of this rank is integrated (its ghosts are their owners' to move); the
      // lowest failing index is reported (the serial loop's).
      const long long failed = parallel_first_failure(threads_, owned_, [&](long long i) {
        return !integrate_begin(p, bodies, static_cast<int>(i), dt_);
      });
      if (failed < owned_) {
        throw std::runtime_error(
            scene_.file + ": particle " + std::to_string(global_ids_[failed]) +
            " spins too fast for time.step (the implicit-midpoint rotation did not converge)");
      }
    });
  });
  time_ += scene_.time_step;
  ++steps_;
  if (comm_) exchange(false);
  stage([&] {
    run_force_stages(dt_);
    ledger_.advance(scene_.time_step, contact_rates());
    const ParticleView<Real> q = view_;  // renumbered by the force stages with `reorder`
    timed(Stage::integrate_end, [&] {
      parallel_for(threads_, owned_,
                   [&](long long i) { integrate_end(q, bodies, static_cast<int>(i), dt_); });
    });
    if (scene_.domain) remove_outside();
  });
}

template <class Real>
ParticleView<Real> HostStep<Real>::owned_view() const {
  ParticleView<Real> v = view_;
  v.count = owned_;
  return v;
}

template <class Real>
bool HostStep<Real>::attributed(int a, int b) const {
  const bool own_a = a < owned_, own_b = b < owned_;
  if (own_a && own_b) return true;
  return own_a ? global_ids_[a] < global_ids_[b] : global_ids_[b] < global_ids_[a];
}

template <class Real>
StepState<Real> HostStep<Real>::export_state() const {
  if (comm_) return gathered_state();
  StepState<Real> s;
  s.time = time_;
  s.steps = steps_;
  s.forces_ready = forces_ready_;
  s.count = count_;
  s.arrays = storage_;
  s.template_ids = template_ids_;
  s.material_ids = material_ids_;
  s.global_ids = global_ids_;
  s.next_id = next_id_;
  s.removed = removed_;
  if (contacts_) s.pair_keys = contacts_->history_keys(), s.pair_histories = contacts_->histories();
  if (contacts_) contacts_->export_reference(s.list_reference, s.list_stale);
  if (walls_) s.wall_keys = walls_->history_keys(), s.wall_histories = walls_->histories();
  s.feed_states = feeding_.save();
  s.ledger = ledger_;
  return s;
}

template <class Real>
void HostStep<Real>::import_state(const StepState<Real>& s) {
  std::vector<std::string> names;
  for (const auto& entry : storage_) names.push_back(entry.first);
  feeding_.restore(s.feed_states, s.source);  // first: it refuses a checkpoint of other feeds
  // A feeding run's particles: the initial ones and those inserted by the checkpoint's step; a
  // run with a domain box: less those removed. A step built for a resume holds none of the
  // scene's initial particles (left_out_, once): the checkpoint brings them.
  const long long initial = count_ + static_cast<long long>(left_out_);
  left_out_ = 0;
  if (!checkpoint_count_fits(s.count, initial, scene_, !feeding_.empty(), comm_ != nullptr))
    check_state_fits(s, scene_, static_cast<int>(initial), names);  // refuses the count
  if (s.count != count_) grow(s.count);
  check_state_fits(s, scene_, count_, names);
  // Copied into the arrays in place: view_ keeps pointing at them.
  for (std::size_t k = 0; k < storage_.size(); ++k)
    std::copy(s.arrays[k].second.begin(), s.arrays[k].second.end(), storage_[k].second.begin());
  template_ids_ = s.template_ids;
  material_ids_ = s.material_ids;
  global_ids_ = s.global_ids;
  next_id_ = s.next_id >= 0 ? s.next_id : s.count;
  removed_ = s.removed;
  bind_view();
  if (contacts_) contacts_->set_histories(s.pair_keys, s.pair_histories);
  if (contacts_) contacts_->import_reference(s.list_reference, s.list_stale, count_);
  if (walls_) walls_->set_histories(s.wall_keys, s.wall_histories);
  time_ = s.time;
  steps_ = s.steps;
  forces_ready_ = s.forces_ready;
  ledger_ = s.ledger;
  owned_ = count_;
  if (comm_) {
    // Every rank read one process's state: the totals stay with rank 0, and each rank keeps the
    // particles of its box in a bisection of them (whatever the rank count that wrote it).
    if (comm_->rank() != 0) ledger_ = EnergyLedger(), removed_ = 0;
    decompose();
  }
}

template class HostStep<double>;
template class HostStep<float>;

}  // namespace talus
