// HostStep decomposed over MPI ranks (host_step.hpp, docs/parallel.md): the boxes, the ghosts
// and their exchange, the migration of particles with their histories, and the state of one
// process gathered from every rank. The rest of the step is host_step.cpp's.
#include <algorithm>
#include <chrono>
#include <memory>
#include <utility>
#include <vector>

#include "solver/step/gathered_state.hpp"
#include "solver/step/host/contact_stage.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/step/host/wall_stage.hpp"

namespace talus {

template <class Real>
HostStep<Real>::HostStep(const Scene& scene, int threads, std::shared_ptr<const Communicator> comm)
    : HostStep(scene, threads) {
  if (!comm || comm->size() == 1) return;
  comm_ = std::move(comm);
  send_.assign(comm_->size(), {});
  // Every rank made every initial particle (the same ids); each keeps those its box owns.
  decompose();
}

template <class Real>
void HostStep<Real>::decompose() {
  // The boxes: a bisection of the particles (of the region's centre where there are none).
  std::vector<Vec3d> points;
  points.reserve(count_);
  for (int i = 0; i < count_; ++i) points.push_back(Vec3d(view_.position.get(i)));
  auto rcb =
      std::make_unique<RcbDomain>(points, scene_.domain ? *scene_.domain : Box(), comm_->size(),
                                  comm_->rank(), scene_halo_width(scene_), comm_.get());
  std::vector<int> mine;
  for (int i = 0; i < count_; ++i) {
    const int owner = rcb->owner(points[i]);
    // One outside the region stays with rank 0 until the step's end removes it.
    if (owner == comm_->rank() || (owner < 0 && comm_->rank() == 0)) mine.push_back(i);
  }
  rcb_ = rcb.get();
  domain_ = std::move(rcb);
  keep_particles(mine);  // the particles changed: the next exchange chooses the ghosts
}

template <class Real>
void HostStep<Real>::drop_ghosts() {
  if (count_ == owned_) return;
  std::vector<int> first(owned_);
  for (int i = 0; i < owned_; ++i) first[i] = i;
  keep_particles(first);
}

template <class Real>
void HostStep<Real>::gather_all(std::vector<Vec3d>& positions, std::vector<int>& templates) const {
  std::vector<Vec3d> own;
  own.reserve(owned_);
  for (int i = 0; i < owned_; ++i) own.push_back(Vec3d(view_.position.get(i)));
  gather_positions(*comm_, own,
                   std::vector<int>(template_ids_.begin(), template_ids_.begin() + owned_),
                   positions, templates);
}

template <class Real>
void HostStep<Real>::put_ghost(ByteWriter& w, int i, bool ids) const {
  if (ids) {
    w.put(global_ids_[i]);
    w.put(template_ids_[i]);
  }
  w.put(view_.position.get(i));
  w.put(view_.velocity.get(i));
  w.put(view_.orientation.get(i));
  if (view_.angular_velocity.present()) w.put(view_.angular_velocity.get(i));
}

template <class Real>
void HostStep<Real>::get_ghost(ByteReader& r, int i, bool ids) {
  if (ids) {
    global_ids_[i] = r.get<long long>();
    template_ids_[i] = r.get<int>();
    const BodyProperties<Real>& body = bodies_.at(template_ids_[i]);
    material_ids_[i] = body.material;
    if (view_.bounding_radius) view_.bounding_radius[i] = body.bounding_radius;
  }
  view_.position.set(i, r.get<Vec3<Real>>());
  view_.velocity.set(i, r.get<Vec3<Real>>());
  view_.orientation.set(i, r.get<Quat<Real>>());
  if (view_.angular_velocity.present()) view_.angular_velocity.set(i, r.get<Vec3<Real>>());
}

template <class Real>
void HostStep<Real>::exchange(bool rebuild) {
  const auto start = std::chrono::steady_clock::now();
  // The ranks agree whether to rebuild: some rank's particles changed (feed, removal, arrival) or
  // moved 0.45 skin since the list's build. Without contacts there are no ghosts, and particles
  // move to their owners only when some particle has left its box.
  bool mine = rebuild || changed_;
  if (!mine && contacts_) mine = contacts_->moved_beyond_skin(view_, owned_);
  if (!mine && !contacts_) {
    for (int i = 0; i < owned_ && !mine; ++i)
      mine = rcb_->owner(Vec3d(view_.position.get(i))) >= 0 &&
             !rcb_->local_box().contains(Vec3d(view_.position.get(i)));
  }
  const auto seconds_since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  const auto vote_start = std::chrono::steady_clock::now();
  const bool rebuilding = comm_->max(mine ? 1.0 : 0.0) > 0;
  exchange_vote_seconds_ += seconds_since(vote_start);
  const auto rebuild_start = std::chrono::steady_clock::now();
  if (rebuilding) {
    // The boxes cut again from every particle where one rank holds too many (a pour collapsing
    // to the bottom of a silo): `decomposition: {rebalance: R}`.
    const double most = comm_->max(double(owned_)), total = comm_->sum(double(owned_));
    if (total > 0 && most > scene_.rebalance * total / comm_->size()) {
      std::vector<Vec3d> points;
      std::vector<int> templates;
      gather_all(points, templates);
      auto rcb = std::make_unique<RcbDomain>(points, rcb_->region(), comm_->size(), comm_->rank(),
                                             domain_->halo_width(), comm_.get());
      rcb_ = rcb.get();
      domain_ = std::move(rcb);
      ++rebalances_;
    }
    migrate();
    if (contacts_) send_ghosts();
    changed_ = false;
    exchange_rebuild_seconds_ += seconds_since(rebuild_start);
  } else if (contacts_) {
    update_ghosts();
  }
  exchange_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <class Real>
void HostStep<Real>::migrate() {
  const int me = comm_->rank(), ranks = comm_->size();
  drop_ghosts();
  std::vector<Bytes> to(ranks);
  std::vector<int> kept;
  std::vector<std::pair<long long, int>> leaving;  // (global id, destination)
  for (int i = 0; i < owned_; ++i) {
    const int owner = rcb_->owner(Vec3d(view_.position.get(i)));
    if (owner < 0 || owner == me) {
      kept.push_back(i);
      continue;
    }
    leaving.emplace_back(global_ids_[i], owner);
    ByteWriter w(to[owner]);
    w.put(global_ids_[i]);
    w.put(template_ids_[i]);
    for (const auto& entry : storage_) w.put(entry.second[i]);
  }
  // Each leaving particle's histories go with it (its pairs: keys holding its id; its walls: the
  // key's low id), after the particles: a count, then (key, history) pairs.
  std::sort(leaving.begin(), leaving.end());
  using Entries = std::vector<std::vector<KeyedHistory<Real>>>;
  const Entries pair_out =
      contacts_ ? histories_by_destination(contacts_->history_keys(), contacts_->histories(),
                                           leaving, true, ranks)
                : Entries(ranks);
  const Entries wall_out =
      walls_ ? histories_by_destination(walls_->history_keys(), walls_->histories(), leaving, false,
                                        ranks)
             : Entries(ranks);
  for (int r = 0; r < ranks; ++r) {
    Bytes marked;
    ByteWriter w(marked);
    w.put(static_cast<long long>(to[r].size()));
    marked.insert(marked.end(), to[r].begin(), to[r].end());
    ByteWriter tail(marked);
    tail.put_vector(pair_out[r]);
    tail.put_vector(wall_out[r]);
    to[r] = std::move(marked);
  }
  if (kept.size() != static_cast<std::size_t>(owned_)) keep_particles(kept);
  const std::vector<Bytes> from = exchange_bytes(to);
  std::vector<KeyedHistory<Real>> pair_in, wall_in;
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    ByteReader in(from[r]);
    const long long particle_bytes = in.get<long long>();
    const std::size_t each = sizeof(long long) + sizeof(int) + storage_.size() * sizeof(Real);
    const long long arriving = particle_bytes / static_cast<long long>(each);
    if (arriving > 0) {
      const int first = count_;
      grow(count_ + static_cast<int>(arriving));
      owned_ = count_;
      for (int i = first; i < count_; ++i) {
        global_ids_[i] = in.get<long long>();
        template_ids_[i] = in.get<int>();
        material_ids_[i] = bodies_.at(template_ids_[i]).material;
        for (auto& entry : storage_) entry.second[i] = in.get<Real>();
      }
      changed_ = true;
      if (contacts_) contacts_->particles_changed();
    }
    const auto p = in.get_vector<KeyedHistory<Real>>();
    const auto w = in.get_vector<KeyedHistory<Real>>();
    pair_in.insert(pair_in.end(), p.begin(), p.end());
    wall_in.insert(wall_in.end(), w.begin(), w.end());
  }
  // The arrivals' histories joined to the store (a key the store holds already is the same
  // history: both ranks computed the pair).
  const auto merge = [](const std::vector<PairKey>& keys,
                        const std::vector<ContactHistoryData<Real>>& histories,
                        std::vector<KeyedHistory<Real>>& in) {
    std::vector<KeyedHistory<Real>> all;
    for (std::size_t k = 0; k < keys.size(); ++k) all.push_back({keys[k], histories[k]});
    all.insert(all.end(), in.begin(), in.end());
    std::pair<std::vector<PairKey>, std::vector<ContactHistoryData<Real>>> store;
    sorted_store(all, store.first, store.second);
    return store;
  };
  if (contacts_ && !pair_in.empty()) {
    auto [k, h] = merge(contacts_->history_keys(), contacts_->histories(), pair_in);
    contacts_->set_histories(std::move(k), std::move(h));
  }
  if (walls_ && !wall_in.empty()) {
    auto [k, h] = merge(walls_->history_keys(), walls_->histories(), wall_in);
    walls_->set_histories(std::move(k), std::move(h));
  }
}

template <class Real>
std::vector<Bytes> HostStep<Real>::exchange_bytes(const std::vector<Bytes>& to) {
  for (int r = 0; r < comm_->size(); ++r)
    if (r != comm_->rank()) exchange_bytes_ += static_cast<double>(to[r].size());
  return comm_->exchange(to);
}

template <class Real>
void HostStep<Real>::send_ghosts() {
  const int me = comm_->rank(), ranks = comm_->size();
  const double h = domain_->halo_width(), h2 = h * h;
  std::vector<Bytes> to(ranks);
  for (int r = 0; r < ranks; ++r) {
    send_[r].clear();
    if (r == me) continue;
    const Box& box = rcb_->box_of(r);
    for (int i = 0; i < owned_; ++i)
      if (squared_distance(box, Vec3d(view_.position.get(i))) <= h2) send_[r].push_back(i);
    ByteWriter w(to[r]);
    for (const int i : send_[r]) put_ghost(w, i, true);
  }
  const std::vector<Bytes> from = exchange_bytes(to);
  // put_ghost's bytes: ids, then position and velocity (3 numbers each), orientation (4), and the
  // angular velocity (3) where the plan has it.
  static_assert(sizeof(Vec3<Real>) == 3 * sizeof(Real) && sizeof(Quat<Real>) == 4 * sizeof(Real));
  std::size_t each = 2 * 3 * sizeof(Real) + 4 * sizeof(Real) + sizeof(long long) + sizeof(int);
  if (view_.angular_velocity.present()) each += 3 * sizeof(Real);
  long long arriving = 0;
  received_.assign(ranks, 0);
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    received_[r] = static_cast<int>(from[r].size() / each);
    arriving += received_[r];
  }
  grow(count_ + static_cast<int>(arriving));  // owned_ stays: these are ghosts
  int i = owned_;
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    ByteReader in(from[r]);
    while (!in.done()) get_ghost(in, i++, true);
  }
  if (contacts_) contacts_->particles_changed();
}

template <class Real>
void HostStep<Real>::update_ghosts() {
  // The sizes are known on both sides since send_ghosts: one message each way, no sizes sent.
  const int me = comm_->rank(), ranks = comm_->size();
  std::size_t each = 2 * 3 * sizeof(Real) + 4 * sizeof(Real);  // put_ghost without the ids
  if (view_.angular_velocity.present()) each += 3 * sizeof(Real);
  std::vector<std::size_t> out_sizes(ranks, 0), in_sizes(ranks, 0);
  ghost_out_.clear();
  ByteWriter w(ghost_out_);
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    for (const int i : send_[r]) put_ghost(w, i, false);
    out_sizes[r] = send_[r].size() * each;
    in_sizes[r] = static_cast<std::size_t>(received_[r]) * each;
    exchange_bytes_ += static_cast<double>(out_sizes[r]);
  }
  std::size_t arriving = 0;
  for (const std::size_t n : in_sizes) arriving += n;
  ghost_in_.resize(arriving);
  comm_->exchange_sized(ghost_out_.data(), out_sizes, ghost_in_.data(), in_sizes);
  ByteReader in(ghost_in_);
  for (int i = owned_; !in.done(); ++i) get_ghost(in, i, false);
}

template <class Real>
StepState<Real> HostStep<Real>::gathered_state() const {
  StepState<Real> mine;
  mine.time = time_;
  mine.steps = steps_;
  mine.forces_ready = forces_ready_;
  mine.count = owned_;
  for (const auto& entry : storage_)
    mine.arrays.emplace_back(
        entry.first, std::vector<Real>(entry.second.begin(), entry.second.begin() + owned_));
  mine.template_ids.assign(template_ids_.begin(), template_ids_.begin() + owned_);
  mine.material_ids.assign(material_ids_.begin(), material_ids_.begin() + owned_);
  mine.global_ids.assign(global_ids_.begin(), global_ids_.begin() + owned_);
  if (contacts_)
    mine.pair_keys = contacts_->history_keys(), mine.pair_histories = contacts_->histories();
  if (walls_) mine.wall_keys = walls_->history_keys(), mine.wall_histories = walls_->histories();
  mine.ledger = ledger_;
  mine.removed = removed_;
  mine.next_id = next_id_;
  mine.feed_states = feeding_.save();
  return gather_step_states(*comm_, mine);
}

#define TALUS_INSTANTIATE_DECOMPOSITION(Real)                                                \
  template HostStep<Real>::HostStep(const Scene&, int, std::shared_ptr<const Communicator>); \
  template void HostStep<Real>::decompose();                                                 \
  template void HostStep<Real>::drop_ghosts();                                               \
  template void HostStep<Real>::gather_all(std::vector<Vec3d>&, std::vector<int>&) const;    \
  template void HostStep<Real>::put_ghost(ByteWriter&, int, bool) const;                     \
  template void HostStep<Real>::get_ghost(ByteReader&, int, bool);                           \
  template void HostStep<Real>::exchange(bool);                                              \
  template void HostStep<Real>::migrate();                                                   \
  template void HostStep<Real>::send_ghosts();                                               \
  template std::vector<Bytes> HostStep<Real>::exchange_bytes(const std::vector<Bytes>&);     \
  template void HostStep<Real>::update_ghosts();                                             \
  template StepState<Real> HostStep<Real>::gathered_state() const;
TALUS_INSTANTIATE_DECOMPOSITION(double)
TALUS_INSTANTIATE_DECOMPOSITION(float)
#undef TALUS_INSTANTIATE_DECOMPOSITION

}  // namespace talus
