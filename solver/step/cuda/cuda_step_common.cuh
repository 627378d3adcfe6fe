// What the CUDA step's parts share (cuda_step.cu and the stages it owns: cuda_pair_list,
// cuda_pair_stage, cuda_wall_stage): the launch shape, the flags kernels raise, the per-slot
// records the pair stage writes and the accumulation reads, the double-buffered history store,
// and DeviceStepShared, the device state every stage reads. Included only from .cu files.
#pragma once

#include <array>

#include <chrono>
#include <climits>
#include <vector>

#include "solver/contact/tangential_history.hpp"
#include "solver/core/cuda_check.hpp"
#include "solver/core/device_buffer.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/host/contact_stage.hpp"
#include "solver/step/pair_report.hpp"
#include "solver/step/particle_state.hpp"

namespace talus {

constexpr int kBlock = 128;

inline int blocks_for(long long n) {
  return static_cast<int>((n + kBlock - 1) / kBlock);
}

inline double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

template <class T>
std::vector<T> download(const T* device, std::size_t count) {
  std::vector<T> host(count);
  if (count > 0) {
    TALUS_CUDA_CHECK(cudaMemcpy(host.data(), device, count * sizeof(T), cudaMemcpyDeviceToHost));
  }
  return host;
}

// Flags the kernels raise (the lowest index wins: atomicMin) or count in (atomicAdd). A stage
// reads what it needs to go on (a count it must size launches by); the failures and the counts
// only reported are read once, all together, at the end of the step (read_all): every read waits
// for the device, and a small scene's step is made of such waits.
enum Flag {
  failed_rotation = 0,
  degenerate_pair = 1,
  degenerate_wall = 2,
  selected = 3,
  touching_pairs = 4,
  touching_walls = 5,
  outside_particles = 6,
  wall_candidates = 7,
  flags
};

// A graph step's guard (cuda_step_impl.cuh, "Graph steps"): the step cannot finish in the graph
// when the wall stage's facets overran their room (the counter past the capacity); the kernels
// after that stage then do nothing, and the step finishes outside the graph. Empty (never aborted)
// in a step launched stage by stage, which grows the room and runs the wall kernels again instead.
struct AbortCheck {
  const int* counter = nullptr;
  int capacity = 0;
  __device__ bool aborted() const { return counter != nullptr && *counter > capacity; }
};

class DeviceFlags {
 public:
  // On the device once the scene's checks have passed (the step allocates nothing before).
  void allocate() { values_.resize(flags); }
  // Before each evaluation: no failure (INT_MAX, as atomicMin wants), no counts.
  // By a one-thread kernel on `stream`: a copy from host memory would wait for the device.
  void reset(cudaStream_t stream = 0);
  // Every flag into `host` (pinned, `flags` entries) without waiting: the step's report.
  void copy_to(int* host, cudaStream_t stream) const {
    TALUS_CUDA_CHECK(
        cudaMemcpyAsync(host, values_.data(), sizeof(int) * flags, cudaMemcpyDeviceToHost, stream));
  }
  // Every flag, in one copy.
  std::array<int, flags> read_all() const {
    std::array<int, flags> all{};
    TALUS_CUDA_CHECK(
        cudaMemcpy(all.data(), values_.data(), sizeof(int) * flags, cudaMemcpyDeviceToHost));
    return all;
  }
  int read(Flag which) const {
    int value = 0;
    TALUS_CUDA_CHECK(
        cudaMemcpy(&value, values_.data() + which, sizeof(int), cudaMemcpyDeviceToHost));
    return value;
  }
  void clear(Flag which) { TALUS_CUDA_CHECK(cudaMemset(values_.data() + which, 0, sizeof(int))); }
  int* data() { return values_.data(); }
  int* at(Flag which) { return values_.data() + which; }

 private:
  DeviceBuffer<int> values_;
};

// A template, so that every .cu file including this header may instantiate it.
template <class Int>
__global__ void reset_flags_kernel(Int* values) {
  const Int none[flags] = {INT_MAX, INT_MAX, INT_MAX, 0, 0, 0, 0, 0};
  for (int k = 0; k < flags; ++k) values[k] = none[k];
}

inline void DeviceFlags::reset(cudaStream_t stream) {
  reset_flags_kernel<int><<<1, 1, 0, stream>>>(values_.data());
  TALUS_CUDA_LAUNCH_CHECK();
}

// What a touching candidate slot k holds for the accumulation (deterministic mode): the force on
// its ordered A, the contact point and the patch's couple; slot_state[k] says whether it touches
// and which of pairs[k].a, pairs[k].b is A.
template <class Real>
struct SlotForce {
  Vec3<Real> force_on_a;  // N; B gets the opposite
  Vec3<Real> point;       // m
  Vec3<Real> couple;      // N m, on A besides (point - x_a) x force_on_a (B: -couple)
};
enum SlotState : unsigned char { slot_apart = 0, slot_a_first = 1, slot_b_first = 2 };

struct KeyLess {
  __host__ __device__ bool operator()(const PairKey& p, const PairKey& q) const {
    return key_less(p, q);
  }
};
struct KeyEqual {
  __host__ __device__ bool operator()(const PairKey& p, const PairKey& q) const {
    return key_equal(p, q);
  }
};

// A history store as a kernel reads it: its keys and their number (on the device, at
// `count_at`, in a graph step, where the host does not know it when the graph is launched).
struct HistoryIn {
  const PairKey* keys;
  int count;
  const int* count_at = nullptr;
  __device__ int size() const { return count_at ? *count_at : count; }
};

// A sorted history store (keys and their histories) in device memory, double-buffered: a stage
// reads the current one while the next is written into the other.
template <class Real>
struct DeviceHistory {
  DeviceBuffer<PairKey> keys[2];
  DeviceBuffer<ContactHistoryData<Real>> histories[2];
  int current = 0, count = 0;
  DeviceBuffer<int> device_count;  // a graph step's count (HistoryIn::count_at)
  HistoryIn in() const { return {keys[current].data(), count, nullptr}; }
  const ContactHistoryData<Real>* values() const { return histories[current].data(); }
  // The buffers of the next store, with room for n entries.
  PairKey* next_keys(int n) {
    keys[1 - current].grow_to(n);
    return keys[1 - current].data();
  }
  ContactHistoryData<Real>* next_histories(int n) {
    histories[1 - current].grow_to(n);
    return histories[1 - current].data();
  }
  // The next store, once filled with n entries (sorted), becomes the current one.
  void flip(int n) {
    current = 1 - current;
    count = n;
  }
  std::size_t bytes() const {
    return (keys[0].size() + keys[1].size()) * sizeof(PairKey) +
           (histories[0].size() + histories[1].size()) * sizeof(ContactHistoryData<Real>);
  }
};

// The buffers of a history selection (history_select.cuh), kept between rebuilds: a rebuild of a
// million-particle rank selects from a store of millions of entries, and allocating and freeing
// that much each time (cudaFree waits for the device) is avoidable.
template <class Real>
struct HistorySelection {
  DeviceBuffer<long long> ids;
  DeviceBuffer<unsigned char> flags;
  DeviceBuffer<PairKey> keys;
  DeviceBuffer<ContactHistoryData<Real>> histories;
  DeviceBuffer<int> count;
  std::size_t bytes() const {
    return ids.size() * sizeof(long long) + flags.size() + keys.size() * sizeof(PairKey) +
           histories.size() * sizeof(ContactHistoryData<Real>) + count.size() * sizeof(int);
  }
};

// The device state every stage of the CUDA step reads, owned by the step: the particles (device
// pointers), the pair-law tables (device pointers), the flags, CUB's scratch and the global ids
// (for error messages and history keys).
// The entries of DeviceStepShared::energy_sums.
enum EnergySum : int {
  sum_dissipation = 0,  // W
  sum_normal = 1,       // J
  sum_tangential = 2,   // J
  sum_wall_power = 3,   // W
  kEnergySums = 4
};

template <class Real>
struct DeviceStepShared {
  explicit DeviceStepShared(const Scene& s) : scene(s) {}
  const Scene& scene;
  // The local domain (the step's; domain/domain.hpp): the broad phase's grid origin, removal.
  const Domain* domain = nullptr;
  int count = 0;
  // Decomposed over ranks (docs/parallel.md): particles [0, owned) are this rank's, the rest its
  // ghosts (others' particles within the halo), which the pair list sees and nothing else
  // moves. -1: one process, every particle its own.
  int owned = -1;
  int own_count() const { return owned < 0 ? count : owned; }
  // Above every global id held (the CSR's sort by partner ids reads this many bits).
  long long id_bound = 1;
  ParticleView<Real> view;
  PairLawTables<Real> tables;
  DeviceFlags flags;
  DeviceBuffer<unsigned char> temp;
  // The stream every stage of a step runs on (a blocking one: the legacy default stream's copies
  // and the set-up's launches order themselves with it), so that a step can be captured as a
  // CUDA graph; owned by the step.
  cudaStream_t stream = nullptr;
  // True while a step is captured into a graph (cuda_step_impl.cuh, "Graph steps"): the stages then
  // read nothing back and size their launches by their capacities, reading the counts on the
  // device; `abort` is the wall stage's guard for the kernels after it.
  bool graph_mode = false;
  AbortCheck abort;
  DeviceBuffer<long long> global_ids;
  // The templates as the device sees them (device shape views), and their region of constant
  // memory (-1: none): each stage whose kernels read templates fills its own unit's copy.
  std::vector<BodyProperties<Real>> device_bodies;
  int constant_region = -1;
  // GJK before the culling of polyhedron pairs (CudaStepOptions::gjk_filter).
  bool gjk_filter = true;
  // The energy probe's sums over the contacts of an evaluation (null when the scene asks neither
  // for the energy probe nor has moving walls): kEnergySums doubles, by atomic additions (the
  // order of the additions varies, so their last bits do; the motion does not depend on them).
  DeviceBuffer<double> energy_sums;

  long long global_id(int i) const { return download(global_ids.data() + i, 1)[0]; }

  // Particle i's id, template and pose, downloaded (pair_report.hpp; an error path only).
  ParticlePoseReport pose_report(int i) const {
    ParticlePoseReport r;
    r.id = global_id(i);
    if (view.template_id) r.template_id = download(view.template_id + i, 1)[0];
    const Real* position[3] = {view.position.x, view.position.y, view.position.z};
    for (int c = 0; c < 3; ++c) r.position[c] = double(download(position[c] + i, 1)[0]);
    const Real* orientation[4] = {view.orientation.w, view.orientation.x, view.orientation.y,
                                  view.orientation.z};
    for (int c = 0; c < 4; ++c) r.orientation[c] = double(download(orientation[c] + i, 1)[0]);
    return r;
  }
};

// While alive, `count` and the view's count name this rank's own particles only (a decomposed
// step's per-particle stages: integration, forces, walls, accumulation, removal, which its
// ghosts' owners do); the particles must not change meanwhile.
template <class Real>
class OwnParticlesOnly {
 public:
  explicit OwnParticlesOnly(DeviceStepShared<Real>& s) : s_(s), count_(s.count) {
    s.count = s.view.count = s.own_count();
  }
  ~OwnParticlesOnly() { s_.count = s_.view.count = count_; }
  OwnParticlesOnly(const OwnParticlesOnly&) = delete;
  OwnParticlesOnly& operator=(const OwnParticlesOnly&) = delete;

 private:
  DeviceStepShared<Real>& s_;
  int count_;
};

}  // namespace talus
