// The CUDA step's pair list and its slots (cuda_pair_list.cuh): the rebuild test, the rebuild
// with the carry-over of the touching histories, and the CSR of the deterministic accumulation.
#include "solver/step/cuda/cuda_pair_list.cuh"

#include <cub/cub.cuh>

#include <cstring>

#include "solver/contact/contact_laws.hpp"
#include "solver/core/cub_call.cuh"
#include "solver/dynamics/integrator.hpp"
#include "solver/step/cuda/history_select.cuh"
#include "solver/step/particle_kernels.hpp"

namespace talus {

namespace {

// The largest squared displacement since the list was built, as the bits of a non-negative
// double (their integer order is their numeric order): one atomicMax per block.
template <class Real>
__global__ void max_displacement_kernel(ParticleView<Real> p, const Real* __restrict__ x0,
                                        const Real* __restrict__ y0, const Real* __restrict__ z0,
                                        unsigned long long* largest) {
  using BlockReduce = cub::BlockReduce<double, kBlock>;
  __shared__ typename BlockReduce::TempStorage temp;
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  double d2 = 0;
  if (i < p.count) {
    const double dx = double(p.position.x[i]) - double(x0[i]);
    const double dy = double(p.position.y[i]) - double(y0[i]);
    const double dz = double(p.position.z[i]) - double(z0[i]);
    d2 = dx * dx + dy * dy + dz * dz;
  }
  const double block_max =
      BlockReduce(temp).Reduce(d2, [](double u, double v) { return u < v ? v : u; });
  if (threadIdx.x == 0)
    atomicMax(largest, static_cast<unsigned long long>(__double_as_longlong(block_max)));
}

// As max_displacement_kernel, for the positions the next integrate_begin will give (the same
// begin_translation on copies of the present state), from the reference x0, y0, z0 and, where
// x1 is not null, the larger of that and the move from x1, y1, z1 (a mirrored reference).
template <class Real>
__global__ void predicted_displacement_kernel(
    ParticleView<Real> p, const BodyProperties<Real>* __restrict__ bodies, Real dt,
    const Real* __restrict__ x0, const Real* __restrict__ y0, const Real* __restrict__ z0,
    const Real* __restrict__ x1, const Real* __restrict__ y1, const Real* __restrict__ z1,
    AbortCheck abort, unsigned long long* largest) {
  using BlockReduce = cub::BlockReduce<double, kBlock>;
  __shared__ typename BlockReduce::TempStorage temp;
  if (abort.aborted()) return;  // the whole block returns together
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  double d2 = 0;
  if (i < p.count) {
    Vec3<Real> x = p.position.get(i), v = p.velocity.get(i), a0;
    begin_translation(x, v, force_or_zero(p, i), bodies[p.template_id[i]].mass, dt, a0);
    const auto moved2 = [&](const Real* xr, const Real* yr, const Real* zr) {
      const double dx = double(x.x) - double(xr[i]);
      const double dy = double(x.y) - double(yr[i]);
      const double dz = double(x.z) - double(zr[i]);
      return dx * dx + dy * dy + dz * dz;
    };
    d2 = moved2(x0, y0, z0);
    if (x1) d2 = fmax(d2, moved2(x1, y1, z1));
  }
  const double block_max =
      BlockReduce(temp).Reduce(d2, [](double u, double v) { return u < v ? v : u; });
  if (threadIdx.x == 0)
    atomicMax(largest, static_cast<unsigned long long>(__double_as_longlong(block_max)));
}

// Each old slot's key (the pair's global ids) and whether it touches.
__global__ void key_slots(const long long* __restrict__ global_id,
                          const ContactPair* __restrict__ pairs, int count,
                          const unsigned char* __restrict__ slot_state, PairKey* __restrict__ keys,
                          unsigned char* __restrict__ touching) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  keys[k] = make_pair_key(global_id[pairs[k].a], global_id[pairs[k].b]);
  touching[k] = slot_state[k] != slot_apart;
}

// Each slot of the new list takes its pair's history from the store (sorted by key; the default
// for a pair that was not touching), and starts apart.
template <class Real>
__global__ void carry_histories_kernel(const long long* __restrict__ global_id,
                                       const ContactPair* __restrict__ pairs, int count,
                                       const PairKey* __restrict__ store_keys,
                                       const ContactHistoryData<Real>* __restrict__ store_histories,
                                       int stored, ContactHistoryData<Real>* __restrict__ histories,
                                       unsigned char* __restrict__ slot_state) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  if (histories) {
    const int at = find_pair_key(store_keys, stored,
                                 make_pair_key(global_id[pairs[k].a], global_id[pairs[k].b]));
    histories[k] = at >= 0 ? store_histories[at] : ContactHistoryData<Real>();
  }
  slot_state[k] = slot_apart;
}

// Two CSR entries per candidate slot k: (a, k) and (b, k), each with its partner's global id and
// its own index.
__global__ void emit_entries(const ContactPair* __restrict__ pairs, int count,
                             const long long* __restrict__ global_id, int* __restrict__ particle,
                             int* __restrict__ slot, long long* __restrict__ partner,
                             int* __restrict__ entry) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  particle[2 * k] = pairs[k].a;
  particle[2 * k + 1] = pairs[k].b;
  slot[2 * k] = slot[2 * k + 1] = k;
  partner[2 * k] = global_id[pairs[k].b];
  partner[2 * k + 1] = global_id[pairs[k].a];
  entry[2 * k] = 2 * k;
  entry[2 * k + 1] = 2 * k + 1;
}

// The entries in the order `order` gives: particle_out[j] = particle[order[j]], likewise slot.
__global__ void gather_entries(const int* __restrict__ order, int n,
                               const int* __restrict__ particle, const int* __restrict__ slot,
                               int* __restrict__ particle_out, int* __restrict__ slot_out) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= n) return;
  particle_out[j] = particle[order[j]];
  slot_out[j] = slot[order[j]];
}

// A candidate a decomposed step computes: not two ghosts (docs/parallel.md).
struct NotTwoGhosts {
  int owned;
  __host__ __device__ bool operator()(const ContactPair& c) const {
    return c.a < owned || c.b < owned;
  }
};

// A candidate of two own particles (the inner region's).
struct TwoOwn {
  int owned;
  __host__ __device__ bool operator()(const ContactPair& c) const {
    return c.a < owned && c.b < owned;
  }
};

// begin[i], end[i]: particle i's range of the sorted entries (both 0 when it has none).
__global__ void entry_ranges(const int* __restrict__ sorted_particle, int n, int* begin, int* end) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n) return;
  const int i = sorted_particle[s];
  if (s == 0 || sorted_particle[s - 1] != i) begin[i] = s;
  if (s == n - 1 || sorted_particle[s + 1] != i) end[i] = s + 1;
}

}  // namespace

template <class Real>
DevicePairList<Real>::DevicePairList(DeviceStepShared<Real>& shared, Real skin)
    : shared_(shared),
      tangential_history_(
          with_contact_law(*shared.scene.effects.contact,
                           [](auto law) { return decltype(law)::kTangentialHistory; })),
      skin_(skin) {
  bind_particles();
  largest_move_.resize(1);
}

template <class Real>
void DevicePairList<Real>::bind_particles() {
  const int n = shared_.count;
  const ParticleView<Real>& v = shared_.view;
  NeighborInput<Real> in;
  in.x = v.position.x, in.y = v.position.y, in.z = v.position.z;
  in.radius = v.bounding_radius;
  in.count = n;
  in.skin = skin_;
  if (shared_.domain) {  // the grid anchored at the local domain's reach box when it is bounded
    const Box reach = shared_.domain->reach_box();
    if (reach.bounded()) {
      in.fixed_origin = true;
      in.origin[0] = Real(reach.min.x), in.origin[1] = Real(reach.min.y);
      in.origin[2] = Real(reach.min.z);
    }
  }
  broad_phase_.set_device_particles(in);
  // Contents are set at each build (the CSR's ranges, the positions built from).
  if (deterministic()) entry_begin_.grow_to(n), entry_end_.grow_to(n);
  if (skin_ > 0) built_x_.grow_to(n), built_y_.grow_to(n), built_z_.grow_to(n);
}

template <class Real>
void DevicePairList<Real>::particles_changed() {
  bind_particles();
  stale_ = true;
  due_ = -1;
}

// True when some particle has moved more than (a little less than) skin / 2 from x0, y0, z0 (the
// positions the list was built at): a pair outside the list (centres beyond r_a + r_b + skin
// then) could now touch. The 10% margin covers the round-off of the distances the broad phase
// compared.
template <class Real>
bool DevicePairList<Real>::moved_beyond(const Real* x0, const Real* y0, const Real* z0) {
  TALUS_CUDA_CHECK(cudaMemset(largest_move_.data(), 0, sizeof(unsigned long long)));
  max_displacement_kernel<<<blocks_for(shared_.count), kBlock>>>(shared_.view, x0, y0, z0,
                                                                 largest_move_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  unsigned long long bits = 0;
  TALUS_CUDA_CHECK(cudaMemcpy(&bits, largest_move_.data(), sizeof(bits), cudaMemcpyDeviceToHost));
  double moved2 = 0;
  std::memcpy(&moved2, &bits, sizeof(moved2));
  const double limit = 0.45 * double(skin_);
  return moved2 > limit * limit;
}

template <class Real>
void DevicePairList<Real>::predict_move(const BodyProperties<Real>* bodies, Real dt,
                                        unsigned long long* out, AbortCheck abort,
                                        cudaStream_t stream) {
  TALUS_CUDA_CHECK(cudaMemsetAsync(out, 0, sizeof(unsigned long long), stream));
  if (!steady() || shared_.count == 0) return;
  // Mirroring, measure() rebuilds on a move beyond the mirrored reference too: the larger of the
  // two moves, from one pass over the particles.
  predicted_displacement_kernel<<<blocks_for(shared_.count), kBlock, 0, stream>>>(
      shared_.view, bodies, dt, built_x_.data(), built_y_.data(), built_z_.data(),
      mirror_ ? mirror_x_.data() : nullptr, mirror_ ? mirror_y_.data() : nullptr,
      mirror_ ? mirror_z_.data() : nullptr, abort, out);
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
bool DevicePairList<Real>::keeps(unsigned long long predicted_bits) const {
  if (!steady()) return false;
  double moved2 = 0;
  std::memcpy(&moved2, &predicted_bits, sizeof(moved2));
  const double limit = 0.9 * 0.45 * double(skin_);
  return moved2 < limit * limit;  // false for a NaN
}

// The rebuild an uninterrupted run makes (renumber_due_): the first build, changed particles, a
// move beyond the reference (the mirrored one after a restart). A rebuild besides: an imported
// store, or the list's own reference passed while it mirrors another.
template <class Real>
void DevicePairList<Real>::measure() {
  if (due_ >= 0) return;
  const bool no_skin = !(skin_ > 0);
  if (stale_ || no_skin) {
    renumber_due_ = true;
  } else if (mirror_) {
    renumber_due_ = moved_beyond(mirror_x_.data(), mirror_y_.data(), mirror_z_.data());
  } else {
    renumber_due_ = builds_ == 0 || moved_beyond(built_x_.data(), built_y_.data(), built_z_.data());
  }
  bool rebuild = renumber_due_ || imported_ >= 0 || builds_ == 0;
  if (!rebuild && mirror_)
    rebuild = moved_beyond(built_x_.data(), built_y_.data(), built_z_.data());
  due_ = rebuild ? 1 : 0;
}

// The touching slots' keys and histories, sorted by key, into the store; returns their number.
template <class Real>
int DevicePairList<Real>::store_touching_histories() {
  const int old = builds_ > 0 ? candidates_ : 0;
  if (!tangential_history_ || old == 0) return 0;
  old_keys_.grow_to(old), old_touching_.grow_to(old);
  store_keys_.grow_to(old), store_histories_.grow_to(old);
  key_slots<<<blocks_for(old), kBlock>>>(shared_.global_ids.data(), pairs(), old,
                                         slot_state_.data(), old_keys_.data(),
                                         old_touching_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  int* selected_count = shared_.flags.at(selected);
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::Flagged(t, b, old_keys_.data(), old_touching_.data(),
                                      store_keys_.data(), selected_count, old);
  });
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::Flagged(t, b, slot_history_.data(), old_touching_.data(),
                                      store_histories_.data(), selected_count, old);
  });
  const int stored = shared_.flags.read(selected);
  if (stored > 0) {
    cub_call(shared_.temp, [&](void* t, std::size_t& b) {
      return cub::DeviceMergeSort::SortPairs(t, b, store_keys_.data(), store_histories_.data(),
                                             stored, KeyLess());
    });
  }
  return stored;
}

// The new slots: the stored histories carried over (a law with a tangential history), every slot
// apart.
template <class Real>
void DevicePairList<Real>::carry_histories(int stored) {
  slot_state_.grow_to(candidates_);
  if (tangential_history_) slot_history_.grow_to(candidates_);
  if (candidates_ == 0) return;
  carry_histories_kernel<<<blocks_for(candidates_), kBlock>>>(
      shared_.global_ids.data(), pairs(), candidates_, store_keys_.data(), store_histories_.data(),
      stored, histories(), slot_state_.data());
  TALUS_CUDA_LAUNCH_CHECK();
}

// Each particle's slots in the order of their partners' global ids, as the host step sums them
// (contact_stage.hpp): the same sums whatever the particles' order in memory, the list's order or
// the ranks the particles are spread over. Two stable radix sorts: by partner id, then by
// particle.
template <class Real>
void DevicePairList<Real>::build_csr() {
  const int count = shared_.count;
  const int entries = 2 * candidates_;
  slot_forces_.grow_to(candidates_);
  entry_particle_.grow_to(entries), entry_slot_.grow_to(entries);
  sorted_particle_.grow_to(entries), sorted_slot_.grow_to(entries);
  entry_partner_.grow_to(entries), sorted_partner_.grow_to(entries);
  entry_index_.grow_to(entries), sorted_index_.grow_to(entries);
  emit_entries<<<blocks_for(candidates_), kBlock>>>(pairs(), candidates_, shared_.global_ids.data(),
                                                    entry_particle_.data(), entry_slot_.data(),
                                                    entry_partner_.data(), entry_index_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  int id_bits = 1;
  while (id_bits < 63 && (1LL << id_bits) < shared_.id_bound) ++id_bits;
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceRadixSort::SortPairs(t, b, entry_partner_.data(), sorted_partner_.data(),
                                           entry_index_.data(), sorted_index_.data(), entries, 0,
                                           id_bits);
  });
  gather_entries<<<blocks_for(entries), kBlock>>>(sorted_index_.data(), entries,
                                                  entry_particle_.data(), entry_slot_.data(),
                                                  sorted_particle_.data(), sorted_slot_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  int bits = 1;
  while (bits < 31 && (1 << bits) < count) ++bits;
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceRadixSort::SortPairs(t, b, sorted_particle_.data(), entry_particle_.data(),
                                           sorted_slot_.data(), entry_slot_.data(), entries, 0,
                                           bits);
  });
  entry_particle_.swap(sorted_particle_);
  entry_slot_.swap(sorted_slot_);
  TALUS_CUDA_CHECK(cudaMemset(entry_begin_.data(), 0, count * sizeof(int)));
  TALUS_CUDA_CHECK(cudaMemset(entry_end_.data(), 0, count * sizeof(int)));
  entry_ranges<<<blocks_for(entries), kBlock>>>(sorted_particle_.data(), entries,
                                                entry_begin_.data(), entry_end_.data());
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
void DevicePairList<Real>::export_histories(std::vector<PairKey>& keys,
                                            std::vector<ContactHistoryData<Real>>& histories) {
  const int stored = imported_ >= 0 ? imported_ : store_touching_histories();
  keys = download(store_keys_.data(), stored);
  histories = download(store_histories_.data(), stored);
}

template <class Real>
void DevicePairList<Real>::import_histories(
    const std::vector<PairKey>& keys, const std::vector<ContactHistoryData<Real>>& histories) {
  imported_ = tangential_history_ ? static_cast<int>(keys.size()) : 0;
  due_ = -1;
  if (imported_ == 0) return;
  store_keys_.grow_to(imported_), store_histories_.grow_to(imported_);
  TALUS_CUDA_CHECK(cudaMemcpy(store_keys_.data(), keys.data(), imported_ * sizeof(PairKey),
                              cudaMemcpyHostToDevice));
  TALUS_CUDA_CHECK(cudaMemcpy(store_histories_.data(), histories.data(),
                              imported_ * sizeof(ContactHistoryData<Real>),
                              cudaMemcpyHostToDevice));
}

template <class Real>
void DevicePairList<Real>::histories_with(const std::vector<long long>& ids,
                                          std::vector<PairKey>& keys,
                                          std::vector<ContactHistoryData<Real>>& histories) {
  const int stored = imported_ >= 0 ? imported_ : 0;
  select_histories_with<true>(store_keys_.data(), store_histories_.data(), stored, ids, selection_,
                              shared_.temp, keys, histories);
}

template <class Real>
void DevicePairList<Real>::add_histories(const std::vector<PairKey>& keys,
                                         const std::vector<ContactHistoryData<Real>>& histories) {
  if (!tangential_history_ || keys.empty()) return;
  const int stored = imported_ >= 0 ? imported_ : 0;
  const int n = stored + static_cast<int>(keys.size());
  store_keys_.grow_keeping(n, stored);
  store_histories_.grow_keeping(n, stored);
  TALUS_CUDA_CHECK(cudaMemcpy(store_keys_.data() + stored, keys.data(),
                              keys.size() * sizeof(PairKey), cudaMemcpyHostToDevice));
  TALUS_CUDA_CHECK(cudaMemcpy(store_histories_.data() + stored, histories.data(),
                              keys.size() * sizeof(ContactHistoryData<Real>),
                              cudaMemcpyHostToDevice));
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceMergeSort::SortPairs(t, b, store_keys_.data(), store_histories_.data(), n,
                                           KeyLess());
  });
  imported_ = n;
  due_ = -1;
}

template <class Real>
bool DevicePairList<Real>::due() {
  measure();
  return due_ == 1;
}

template <class Real>
bool DevicePairList<Real>::renumber_due() {
  measure();
  return renumber_due_;
}

template <class Real>
void DevicePairList<Real>::keep_histories() {
  if (imported_ < 0) imported_ = store_touching_histories();
}

template <class Real>
void DevicePairList<Real>::export_reference(std::vector<Real>& reference, bool& stale) {
  stale = stale_;
  reference.clear();
  if (!(skin_ > 0) || (builds_ == 0 && !mirror_)) return;
  const int n = shared_.count;
  const DeviceBuffer<Real>* from[3] = {&built_x_, &built_y_, &built_z_};
  if (mirror_) from[0] = &mirror_x_, from[1] = &mirror_y_, from[2] = &mirror_z_;
  for (const DeviceBuffer<Real>* axis : from) {
    const std::vector<Real> values = download(axis->data(), n);
    reference.insert(reference.end(), values.begin(), values.end());
  }
}

template <class Real>
void DevicePairList<Real>::import_reference(const std::vector<Real>& reference, bool stale) {
  const int n = shared_.count;
  stale_ = stale;  // as the uninterrupted run had it (a resize at the import set it)
  due_ = -1;
  mirror_ = skin_ > 0 && reference.size() == 3 * static_cast<std::size_t>(n) && n > 0;
  if (!mirror_) return;
  DeviceBuffer<Real>* to[3] = {&mirror_x_, &mirror_y_, &mirror_z_};
  for (int axis = 0; axis < 3; ++axis) {
    to[axis]->resize(n);
    TALUS_CUDA_CHECK(cudaMemcpy(to[axis]->data(), reference.data() + axis * std::size_t(n),
                                n * sizeof(Real), cudaMemcpyHostToDevice));
  }
}

template <class Real>
void DevicePairList<Real>::update() {
  const bool rebuild = due();
  due_ = -1;
  if (!rebuild) return;
  if (renumber_due_) mirror_ = false;  // the uninterrupted run rebuilds here too: in step again
  const int stored = imported_ >= 0 ? imported_ : store_touching_histories();
  imported_ = -1;
  stale_ = false;
  broad_phase_.build();
  candidates_ = static_cast<int>(broad_phase_.pair_count());
  pairs_ = broad_phase_.device_pairs();
  const int owned = shared_.owned;
  if (owned >= 0 && owned < shared_.count && candidates_ > 0) {
    // Decomposed: pairs of two ghosts are their owners' (and may lack partners here).
    own_pairs_.grow_to(candidates_);
    int* selected_count = shared_.flags.at(selected);
    cub_call(shared_.temp, [&](void* t, std::size_t& b) {
      return cub::DeviceSelect::If(t, b, pairs_, own_pairs_.data(), selected_count, candidates_,
                                   NotTwoGhosts{owned});
    });
    candidates_ = shared_.flags.read(selected);
    // Those of two own particles first (in the broad phase's order), then those with a ghost
    // (in reverse order: cub's partition): the inner slots, computed while the ghosts travel.
    split_pairs_.grow_to(candidates_);
    cub_call(shared_.temp, [&](void* t, std::size_t& b) {
      return cub::DevicePartition::If(t, b, own_pairs_.data(), split_pairs_.data(), selected_count,
                                      candidates_, TwoOwn{owned});
    });
    inner_ = shared_.flags.read(selected);
    pairs_ = split_pairs_.data();
  } else {
    inner_ = candidates_;
  }
  ++builds_;
  carry_histories(stored);
  if (deterministic() && candidates_ > 0) build_csr();
  if (skin_ > 0) {  // the positions the next steps' displacements are measured from
    const ParticleView<Real>& v = shared_.view;
    const std::size_t bytes = shared_.count * sizeof(Real);
    TALUS_CUDA_CHECK(cudaMemcpy(built_x_.data(), v.position.x, bytes, cudaMemcpyDeviceToDevice));
    TALUS_CUDA_CHECK(cudaMemcpy(built_y_.data(), v.position.y, bytes, cudaMemcpyDeviceToDevice));
    TALUS_CUDA_CHECK(cudaMemcpy(built_z_.data(), v.position.z, bytes, cudaMemcpyDeviceToDevice));
  }
}

template <class Real>
std::vector<std::pair<const char*, std::size_t>> DevicePairList<Real>::parts() const {
  using History = ContactHistoryData<Real>;
  return {
      {"slot states", slot_state_.size()},
      {"slot histories", slot_history_.size() * sizeof(History)},
      {"slot forces", slot_forces_.size() * sizeof(SlotForce<Real>)},
      {"history carry-over", (old_keys_.size() + store_keys_.size()) * sizeof(PairKey) +
                                 old_touching_.size() + store_histories_.size() * sizeof(History)},
      {"reference positions", (built_x_.size() + built_y_.size() + built_z_.size() +
                               mirror_x_.size() + mirror_y_.size() + mirror_z_.size()) *
                                      sizeof(Real) +
                                  largest_move_.size() * sizeof(unsigned long long)},
      {"slot CSR", (entry_particle_.size() + entry_slot_.size() + sorted_particle_.size() +
                    sorted_slot_.size() + entry_begin_.size() + entry_end_.size() +
                    entry_index_.size() + sorted_index_.size()) *
                           sizeof(int) +
                       (entry_partner_.size() + sorted_partner_.size()) * sizeof(long long)},
      {"own pairs", own_pairs_.size() * sizeof(ContactPair)},
      {"migration's history selection", selection_.bytes()},
      {"broad phase", broad_phase_.allocated_bytes()},
  };
}

template <class Real>
std::size_t DevicePairList<Real>::bytes() const {
  std::size_t bytes = 0;
  for (const auto& part : parts()) bytes += part.second;
  return bytes;
}

template class DevicePairList<double>;
template class DevicePairList<float>;

}  // namespace talus
