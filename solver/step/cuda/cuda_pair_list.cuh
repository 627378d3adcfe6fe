// The CUDA step's pair list (a Verlet list) and its slots. The broad phase (ContactPairsGpu, with
// the scene's skin) gives the candidate pairs; the list is kept until some particle has moved
// 0.45 skin since it was built, and each candidate keeps its slot: the pair's tangential history
// (a law with one: contact/laws/), its state and, in deterministic mode, its force. A rebuild
// carries the touching slots' histories over to the new slots of the same pairs, by global ids (a
// sorted store and find_pair_key), and in deterministic mode builds each particle's slots in the
// order of their partners' global ids (a CSR over the list) for the accumulation. Included only
// from .cu files.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "solver/neighbor/contact_pairs_gpu.hpp"
#include "solver/step/cuda/cuda_step_common.cuh"

namespace talus {

template <class Real>
class DevicePairList {
 public:
  // The list over the shared particles (positions, bounding radii) with the given skin
  // (0: rebuilt every step); the scene's deterministic mode adds the slot forces and the CSR.
  DevicePairList(DeviceStepShared<Real>& shared, Real skin);

  // Whether the next update rebuilds: the list has expired (always on the first call, after
  // import_histories, keep_histories and particles_changed). Measured once per update.
  bool due();
  // Whether this rebuild is one the run would make had it never been resumed (the first build,
  // the particles changed, a particle moved 0.45 skin since the reference): the step renumbers
  // the particles then and only then, so a resumed run renumbers at the same steps as the
  // uninterrupted one. After a restart the reference is the uninterrupted run's (import_reference)
  // until that run's next rebuild; the list's own, from its rebuild at the restart, still decides
  // its own safety rebuilds, which change no result.
  bool renumber_due();
  // Rebuilds the list when due().
  void update();

  // For graph steps (cuda_step_impl.cuh, "Graph steps"), which skip update(): whether the list is
  // built and nothing but the particles' motion can make it due (a skin, no change of the
  // particles, no imported store). A list that mirrors a resumed run's reference (after a
  // restart, until the uninterrupted run would have rebuilt) is steady too: its rebuild test is a
  // move beyond either reference, and predict_move bounds both. (Before, mirroring kept every
  // step of a resumed run at rest off graphs: such a run never moves far enough to end it.)
  bool steady() const { return skin_ > 0 && builds_ > 0 && !stale_ && imported_ < 0; }
  // On `stream`: the largest squared distance from the positions the list was built at (and,
  // while it mirrors another, from the mirrored positions) that a particle will have after the
  // next step's integrate_begin (begin_translation with its present velocity and force, as that
  // stage will compute it), as the bits of a double, into `out` (device). Nothing when `abort`
  // says the step did not finish.
  void predict_move(const BodyProperties<Real>* bodies, Real dt, unsigned long long* out,
                    AbortCheck abort, cudaStream_t stream);
  // Whether such a predicted move keeps the next step's rebuild test certainly false: below
  // 0.9 of its limit (0.45 skin), a margin far above the round-off of the two computations.
  bool keeps(unsigned long long predicted_bits) const;
  // Before the particles are renumbered or removed: the touching slots' histories into the store
  // (keyed by global ids, read through the current indices), which the next update builds the
  // list with, as after import_histories.
  void keep_histories();
  // The particles' indices in the order of their cells (ContactPairsGpu::cell_order), into
  // `device_order` (count entries).
  void cell_order(int* device_order) { broad_phase_.cell_order(device_order); }
  // The shared particles were appended to (a feed, a restart's larger state), their arrays maybe
  // moved: the broad phase reads the arrays now in the shared view, the per-particle arrays follow
  // the count, and the next update rebuilds the list (new particles have no candidates yet),
  // carrying the touching slots' histories over as any rebuild does.
  void particles_changed();

  // The touching slots' keys and histories, sorted by key (a law with a tangential history; else
  // none). After
  // import_histories and before the next update: the imported store.
  void export_histories(std::vector<PairKey>& keys,
                        std::vector<ContactHistoryData<Real>>& histories);
  // A store (sorted by key) that the next update builds the list with, as a rebuild carries the
  // touching slots' histories over (a restart).
  void import_histories(const std::vector<PairKey>& keys,
                        const std::vector<ContactHistoryData<Real>>& histories);

  // Decomposed (docs/parallel.md), between keep_histories (or import_histories) and the next
  // update: the store's entries of pairs with a particle among `ids` (sorted global ids; those
  // migrating to other ranks), downloaded; and entries added to the store (the arriving
  // particles'; a key held twice is the same history, computed by two ranks).
  void histories_with(const std::vector<long long>& ids, std::vector<PairKey>& keys,
                      std::vector<ContactHistoryData<Real>>& histories);
  void add_histories(const std::vector<PairKey>& keys,
                     const std::vector<ContactHistoryData<Real>>& histories);
  // Decomposed, a rank that holds no particle now: an empty store and list, so that no history of
  // the particles it held meets those of particles arriving later (which are newer).
  void forget_histories() {
    imported_ = 0;
    candidates_ = 0;
    inner_ = 0;
    stale_ = true;
    due_ = -1;
  }

  // The reference positions the next renumbering is decided from (3 per particle, x then y then
  // z; empty without a skin or before the first build) and whether the particles changed since
  // the last build; setting them on a resumed step (before its first update).
  void export_reference(std::vector<Real>& reference, bool& stale);
  void import_reference(const std::vector<Real>& reference, bool stale);

  int candidates() const { return candidates_; }
  // The first slots, pairs of two own particles; the pairs with a ghost follow them (decomposed:
  // the step computes these first while the ghosts' states travel). All of them in one process.
  int inner_candidates() const { return inner_; }
  long long builds() const { return builds_; }
  Real skin() const { return skin_; }
  // The candidates of the last build (decomposed: without the pairs of two ghosts).
  const ContactPair* pairs() const { return pairs_; }
  unsigned char* slot_state() { return slot_state_.data(); }
  const unsigned char* slot_state() const { return slot_state_.data(); }
  ContactHistoryData<Real>* histories() {  // a law with a tangential history only, else null
    return tangential_history_ ? slot_history_.data() : nullptr;
  }
  SlotForce<Real>* forces() {  // deterministic mode only, else null
    return deterministic() ? slot_forces_.data() : nullptr;
  }
  const SlotForce<Real>* forces() const { return deterministic() ? slot_forces_.data() : nullptr; }
  // Deterministic mode: particle i's slots are sorted_slot()[begin[i] .. end[i]), in the order of
  // the partners' global ids.
  const int* sorted_slot() const { return sorted_slot_.data(); }
  const int* entry_begin() const { return entry_begin_.data(); }
  const int* entry_end() const { return entry_end_.data(); }

  // Device bytes of the list, its slots, the carry-over's scratch, the CSR and the positions
  // the displacements are measured from.
  std::size_t bytes() const;
  // bytes() by part (CudaStep::memory_parts): name and device bytes.
  std::vector<std::pair<const char*, std::size_t>> parts() const;

 private:
  bool deterministic() const { return shared_.scene.deterministic; }
  void bind_particles();  // the broad phase's input and the per-particle arrays, from shared_
  // Some particle has moved 0.45 skin from the positions x0, y0, z0.
  bool moved_beyond(const Real* x0, const Real* y0, const Real* z0);
  void measure();  // due_ and renumber_due_, once per update
  int store_touching_histories();
  void carry_histories(int stored);
  void build_csr();

  DeviceStepShared<Real>& shared_;
  // The scene's law has a tangential history (its trait, read once through the laws' table).
  bool tangential_history_ = false;
  ContactPairsGpu<Real> broad_phase_;
  Real skin_ = 0;
  long long builds_ = 0;
  int candidates_ = 0;
  int inner_ = 0;       // inner_candidates()
  int imported_ = -1;   // entries of an imported store awaiting the next build; -1: none
  bool stale_ = false;  // the particles changed since the last build
  int due_ = -1;        // due()'s answer until the next update (-1: not measured)
  bool renumber_due_ = false;
  // After a restart: the uninterrupted run's reference positions, until its next rebuild.
  bool mirror_ = false;
  DeviceBuffer<Real> mirror_x_, mirror_y_, mirror_z_;
  DeviceBuffer<Real> built_x_, built_y_, built_z_;  // positions when the list was built
  DeviceBuffer<unsigned long long> largest_move_;   // squared, as double bits
  DeviceBuffer<unsigned char> slot_state_;
  DeviceBuffer<ContactHistoryData<Real>> slot_history_;  // volume model
  DeviceBuffer<SlotForce<Real>> slot_forces_;            // deterministic mode
  // A rebuild's carry-over: every old slot's key and touching flag, then the store of the
  // touching slots' keys and histories, sorted by key (volume model).
  DeviceBuffer<PairKey> old_keys_, store_keys_;
  DeviceBuffer<unsigned char> old_touching_;
  DeviceBuffer<ContactHistoryData<Real>> store_histories_;
  HistorySelection<Real> selection_;  // histories_with's buffers
  // Deterministic mode: each particle's slots (CSR over the list, built with it), by partner id.
  DeviceBuffer<int> entry_particle_, entry_slot_, sorted_particle_, sorted_slot_;
  DeviceBuffer<int> entry_begin_, entry_end_, entry_index_, sorted_index_;
  DeviceBuffer<long long> entry_partner_, sorted_partner_;
  // The candidates (the broad phase's list, or decomposed its pairs not of two ghosts, those of
  // two own particles first: own_pairs_ selected, split_pairs_ partitioned).
  const ContactPair* pairs_ = nullptr;
  DeviceBuffer<ContactPair> own_pairs_, split_pairs_;
};

}  // namespace talus
