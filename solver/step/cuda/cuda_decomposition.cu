// The CUDA step decomposed over MPI ranks (cuda_decomposition.cuh; docs/parallel.md).
#include "solver/step/cuda/cuda_decomposition.cuh"

#include <cub/cub.cuh>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "solver/core/cub_call.cuh"
#include "solver/domain/box_arrays.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/gathered_state.hpp"

namespace talus {

namespace {

// The state a ghost's partners read (put_ghost's on the host): position, velocity,
// orientation, and the angular velocity where the plan has it, as columns of the device arrays.
template <class Real>
struct GhostColumns {
  Real* column[13] = {};
  int n = 0;
};

template <class Real>
GhostColumns<Real> ghost_columns(const ParticleView<Real>& v) {
  GhostColumns<Real> c;
  const auto add = [&](Real* p) { c.column[c.n++] = p; };
  add(v.position.x), add(v.position.y), add(v.position.z);
  add(v.velocity.x), add(v.velocity.y), add(v.velocity.z);
  add(v.orientation.w), add(v.orientation.x), add(v.orientation.y), add(v.orientation.z);
  if (v.angular_velocity.present()) {
    add(v.angular_velocity.x), add(v.angular_velocity.y), add(v.angular_velocity.z);
  }
  return c;
}

// out[e * n + k] = column k of particle index[e]: the states to send, row by row.
template <class Real>
__global__ void pack_ghost_states(GhostColumns<Real> c, const int* __restrict__ index, int count,
                                  Real* __restrict__ out) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= count) return;
  const int i = index[e];
  for (int k = 0; k < c.n; ++k) out[e * c.n + k] = c.column[k][i];
}

// The arriving states into the ghosts first .. first + count.
template <class Real>
__global__ void unpack_ghost_states(GhostColumns<Real> c, const Real* __restrict__ in, int count,
                                    int first) {
  const int g = blockIdx.x * blockDim.x + threadIdx.x;
  if (g >= count) return;
  for (int k = 0; k < c.n; ++k) c.column[k][first + g] = in[g * c.n + k];
}

// The own particles classified against the boxes (box_arrays.hpp: RcbDomain's answers, to the
// bit), so that only the few that leave, or that another rank needs as ghosts, leave the device.
// index[i] = i. Migration: leaving[i] when particle i's owner is another rank (destination[i]),
// kept[i] otherwise (its own, or outside the region: the step's end removes it).
template <class Real>
__global__ void classify_owners(ParticleView<Real> p, int n, const double* __restrict__ boxes,
                                int ranks, int me, int* __restrict__ index,
                                int* __restrict__ destination, unsigned char* __restrict__ leaving,
                                unsigned char* __restrict__ kept) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const int owner = box_owner(boxes, ranks, double(p.position.x[i]), double(p.position.y[i]),
                              double(p.position.z[i]));
  const bool leaves = owner >= 0 && owner != me;
  index[i] = i;
  destination[i] = owner;
  leaving[i] = leaves;
  kept[i] = !leaves;
}

// near[i]: particle i lies within the halo (squared width h2) of `box` (send_ghosts's test).
template <class Real>
__global__ void flag_near_box(ParticleView<Real> p, int n, const double* __restrict__ box,
                              double h2, unsigned char* __restrict__ near) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  near[i] = box_squared_distance(box, double(p.position.x[i]), double(p.position.y[i]),
                                 double(p.position.z[i])) <= h2;
}

// index[i] = i.
__global__ void iota_kernel(int* __restrict__ index, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) index[i] = i;
}

// out[k] = values[at[k]].
__global__ void gather_ints(const int* __restrict__ values, const int* __restrict__ at, int n,
                            int* __restrict__ out) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < n) out[k] = values[at[k]];
}

template <class Real>
void put_rows(ByteWriter& w, const typename DeviceParticles<Real>::Rows& rows,
              const std::vector<int>& which) {
  const std::size_t arrays = rows.count > 0 ? rows.values.size() / rows.count : 0;
  w.put(static_cast<long long>(which.size()));
  for (const int i : which) {
    w.put(rows.global_ids[i]);
    w.put(rows.template_ids[i]);
    w.put(rows.material_ids[i]);
    for (std::size_t a = 0; a < arrays; ++a) w.put(rows.values[i * arrays + a]);
  }
}

template <class Real>
void get_rows(ByteReader& r, std::size_t arrays, typename DeviceParticles<Real>::Rows& rows) {
  const long long n = r.get<long long>();
  for (long long i = 0; i < n; ++i) {
    rows.global_ids.push_back(r.get<long long>());
    rows.template_ids.push_back(r.get<int>());
    rows.material_ids.push_back(r.get<int>());
    for (std::size_t a = 0; a < arrays; ++a) rows.values.push_back(r.get<Real>());
    ++rows.count;
  }
}

// A pinned host buffer of at least `n` Reals (grown by half again, contents not kept).
template <class Real>
void pinned_room(Real*& buffer, std::size_t& size, std::size_t n) {
  if (n <= size) return;
  if (buffer) TALUS_CUDA_CHECK(cudaFreeHost(buffer));
  buffer = nullptr;
  size = 0;
  const std::size_t room = n + n / 2 + 64;
  TALUS_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&buffer), room * sizeof(Real)));
  size = room;
}

}  // namespace

template <class Real>
DeviceDecomposition<Real>::DeviceDecomposition(DeviceStepShared<Real>& shared,
                                               DeviceParticles<Real>& particles,
                                               DevicePairList<Real>* list,
                                               DeviceWallStage<Real>* walls,
                                               std::shared_ptr<const Communicator> comm)
    : shared_(shared),
      particles_(particles),
      list_(list),
      walls_(walls),
      comm_(std::move(comm)),
      send_count_(comm_->size()),
      received_(comm_->size(), 0) {
  TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&packed_, cudaEventDisableTiming));
  const char* profile = std::getenv("TALUS_EXCHANGE_PROFILE");
  profile_.on = profile && std::strcmp(profile, "1") == 0;
}

template <class Real>
void DeviceDecomposition<Real>::RebuildProfile::start(cudaStream_t stream) {
  if (!on) return;
  ++rebuilds;
  TALUS_CUDA_CHECK(cudaStreamSynchronize(stream));
  last = std::chrono::steady_clock::now();
}

template <class Real>
void DeviceDecomposition<Real>::RebuildProfile::mark(const char* part, cudaStream_t stream) {
  if (!on) return;
  TALUS_CUDA_CHECK(cudaStreamSynchronize(stream));
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - last).count();
  last = now;
  for (auto& entry : parts)
    if (std::strcmp(entry.first, part) == 0) {
      entry.second += seconds;
      return;
    }
  parts.emplace_back(part, seconds);
}

template <class Real>
DeviceDecomposition<Real>::~DeviceDecomposition() {
  if (profile_.on && profile_.rebuilds > 0) {
    std::string line = "talus: rank " + std::to_string(comm_->rank()) + ", " +
                       std::to_string(profile_.rebuilds) + " rebuilds, ms each:";
    for (const auto& [part, seconds] : profile_.parts)
      line += std::string(" ") + part + " " + std::to_string(1e3 * seconds / profile_.rebuilds);
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  if (packed_) cudaEventDestroy(packed_);  // no throw from a destructor
  if (pinned_out_) cudaFreeHost(pinned_out_);
  if (pinned_in_) cudaFreeHost(pinned_in_);
}

template <class Real>
std::vector<Bytes> DeviceDecomposition<Real>::exchange_bytes(const std::vector<Bytes>& to) {
  for (int r = 0; r < comm_->size(); ++r)
    if (r != comm_->rank()) bytes_sent_ += static_cast<double>(to[r].size());
  return comm_->exchange(to);
}

template <class Real>
int DeviceDecomposition<Real>::select_flagged(const unsigned char* flags, int n, int* out) {
  int* count = shared_.flags.at(selected);
  cub_call(shared_.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::Flagged(t, b, index_.data(), flags, out, count, n, shared_.stream);
  });
  return shared_.flags.read(selected);
}

template <class Real>
void DeviceDecomposition<Real>::cut(const std::vector<Vec3d>& points) {
  const Scene& scene = shared_.scene;
  const Box region = rcb_ ? rcb_->region() : (scene.domain ? *scene.domain : Box());
  rcb_ = std::make_unique<RcbDomain>(points, region, comm_->size(), comm_->rank(),
                                     scene_halo_width(scene), comm_.get());
  shared_.domain = rcb_.get();
  boxes_.upload(box_numbers(*rcb_));
}

template <class Real>
void DeviceDecomposition<Real>::decompose() {
  shared_.owned = -1;
  const std::vector<Vec3d> points = particles_.positions();
  cut(points);
  std::vector<int> mine;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const int owner = rcb_->owner(points[i]);
    // One outside the region stays with rank 0 until the step's end removes it.
    if (owner == comm_->rank() || (owner < 0 && comm_->rank() == 0)) mine.push_back(i);
  }
  if (list_) list_->keep_histories();
  order_.upload(mine);
  particles_.keep(order_.data(), static_cast<int>(mine.size()));
  shared_.owned = shared_.count;
  if (list_) list_->particles_changed();
  changed_ = true;
}

template <class Real>
void DeviceDecomposition<Real>::drop_ghosts() {
  changed_ = true;
  // The touching histories into the store (read through the ghosts' ids too), with or without
  // ghosts: the migration takes the leaving particles' from it.
  if (list_) list_->keep_histories();
  if (shared_.owned < 0 || shared_.owned == shared_.count) return;
  particles_.resize(shared_.owned);
  if (list_) list_->particles_changed();
}

template <class Real>
void DeviceDecomposition<Real>::gather_all(std::vector<Vec3d>& positions,
                                           std::vector<int>& templates) {
  const int own = shared_.own_count();
  std::vector<Vec3d> points = particles_.positions();
  std::vector<int> ids = particles_.template_ids();
  points.resize(own), ids.resize(own);  // the ghosts are others'
  gather_positions(*comm_, points, ids, positions, templates);
}

template <class Real>
bool DeviceDecomposition<Real>::begin_exchange(bool rebuild) {
  const auto start = std::chrono::steady_clock::now();
  bool pending = false;
  // The ranks agree whether to rebuild: some rank's particles changed (feed, removal, arrival) or
  // its list is due (a particle moved 0.45 skin since the build). Without contacts there are no
  // ghosts, and particles move to their owners only when one has left its box.
  bool mine = rebuild || changed_;
  if (!mine && list_) mine = list_->due();
  if (!mine && !list_) {
    const std::vector<Vec3d> points = particles_.positions();
    for (std::size_t i = 0; i < points.size() && !mine; ++i)
      mine = rcb_->owner(points[i]) >= 0 && !rcb_->local_box().contains(points[i]);
  }
  const auto vote_start = std::chrono::steady_clock::now();
  const bool rebuilding = comm_->max(mine ? 1.0 : 0.0) > 0;
  const auto rebuild_start = std::chrono::steady_clock::now();
  vote_seconds_ += std::chrono::duration<double>(rebuild_start - vote_start).count();
  if (rebuilding) {
    profile_.start(shared_.stream);
    drop_ghosts();
    // The boxes cut again from every particle where one rank holds too many (a pour collapsing
    // to the bottom of a silo): `decomposition: {rebalance: R}`.
    const double own = shared_.own_count();
    const double most = comm_->max(own), total = comm_->sum(own);
    if (total > 0 && most > shared_.scene.rebalance * total / comm_->size()) {
      std::vector<Vec3d> points;
      std::vector<int> templates;
      gather_all(points, templates);
      cut(points);
      ++rebalances_;
    }
    profile_.mark("drop-ghosts-and-balance", shared_.stream);
    migrate();
    if (list_) {
      if (shared_.scene.reorder.value_or(true)) reorder_own_by_cell();
      profile_.mark("reorder", shared_.stream);
      send_ghosts();
      profile_.mark("ghosts", shared_.stream);
    }
    changed_ = false;
    rebuild_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - rebuild_start).count();
  } else if (list_) {
    begin_update();
    pending = true;
  }
  exchange_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return pending;
}

template <class Real>
void DeviceDecomposition<Real>::migrate() {
  const int me = comm_->rank(), ranks = comm_->size();
  // The ghosts are dropped (drop_ghosts): every particle here is this rank's. Each one's owner
  // on the device; the leaving ones' indices (in order) and destinations downloaded, the kept
  // ones' selected into order_ there.
  const int own = shared_.count;
  std::vector<int> leaving_index, destination_of;  // per leaving particle, in index order
  int kept_count = own;
  std::vector<std::pair<long long, int>> leaving;  // (global id, destination)
  if (own > 0) {
    index_.grow_to(own), destination_.grow_to(own), selected_.grow_to(own);
    flags_.grow_to(2 * static_cast<std::size_t>(own));
    unsigned char* leaves = flags_.data();
    unsigned char* stays = flags_.data() + own;
    classify_owners<<<blocks_for(own), kBlock, 0, shared_.stream>>>(
        shared_.view, own, boxes_.data(), ranks, me, index_.data(), destination_.data(), leaves,
        stays);
    TALUS_CUDA_LAUNCH_CHECK();
    const int leaving_count = select_flagged(leaves, own, selected_.data());
    if (leaving_count > 0) {
      leaving_index = download(selected_.data(), leaving_count);
      order_.grow_to(leaving_count);
      gather_ints<<<blocks_for(leaving_count), kBlock, 0, shared_.stream>>>(
          destination_.data(), selected_.data(), leaving_count, order_.data());
      TALUS_CUDA_LAUNCH_CHECK();
      destination_of = download(order_.data(), leaving_count);
    }
    order_.grow_to(own);
    kept_count = select_flagged(stays, own, order_.data());
  }
  const typename DeviceParticles<Real>::Rows rows = particles_.gather_rows(leaving_index);
  profile_.mark("migrate:owners", shared_.stream);
  std::vector<std::vector<int>> rows_to(ranks);
  for (int k = 0; k < rows.count; ++k) {
    rows_to[destination_of[k]].push_back(k);
    leaving.emplace_back(rows.global_ids[k], destination_of[k]);
  }
  std::sort(leaving.begin(), leaving.end());
  // Each leaving particle's histories go with it (its pairs: keys holding its id; its walls: the
  // key's low id). Of each store only the entries naming them leave the device.
  using Entries = std::vector<std::vector<KeyedHistory<Real>>>;
  std::vector<PairKey> pair_keys, wall_keys;
  std::vector<ContactHistoryData<Real>> pair_histories, wall_histories;
  if (!leaving.empty()) {
    std::vector<long long> ids;
    for (const auto& l : leaving) ids.push_back(l.first);
    if (list_) list_->histories_with(ids, pair_keys, pair_histories);  // drop_ghosts kept it
    if (walls_) walls_->histories_with(ids, wall_keys, wall_histories);
  }
  profile_.mark("migrate:histories-out", shared_.stream);
  const Entries pair_out =
      histories_by_destination(pair_keys, pair_histories, leaving, true, ranks);
  const Entries wall_out =
      histories_by_destination(wall_keys, wall_histories, leaving, false, ranks);
  std::vector<Bytes> to(ranks);
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    ByteWriter w(to[r]);
    put_rows<Real>(w, rows, rows_to[r]);
    w.put_vector(pair_out[r]);
    w.put_vector(wall_out[r]);
  }
  if (kept_count != own) particles_.keep(order_.data(), kept_count);
  profile_.mark("migrate:pack", shared_.stream);
  const std::vector<Bytes> from = exchange_bytes(to);
  profile_.mark("migrate:all-to-all", shared_.stream);
  const std::size_t arrays = particles_.names().size();
  typename DeviceParticles<Real>::Rows arriving;
  std::vector<KeyedHistory<Real>> pair_in, wall_in;
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    ByteReader in(from[r]);
    get_rows<Real>(in, arrays, arriving);
    const auto p = in.get_vector<KeyedHistory<Real>>();
    const auto w = in.get_vector<KeyedHistory<Real>>();
    pair_in.insert(pair_in.end(), p.begin(), p.end());
    wall_in.insert(wall_in.end(), w.begin(), w.end());
  }
  particles_.append_rows(arriving);
  shared_.owned = shared_.count;
  if (arriving.count > 0) changed_ = true;
  profile_.mark("migrate:arrivals", shared_.stream);
  if (list_ && !pair_in.empty()) {
    std::vector<PairKey> keys;
    std::vector<ContactHistoryData<Real>> histories;
    for (const auto& e : pair_in) keys.push_back(e.key), histories.push_back(e.history);
    list_->add_histories(keys, histories);
  }
  if (walls_ && !wall_in.empty()) {
    std::vector<PairKey> keys;
    std::vector<ContactHistoryData<Real>> histories;
    for (const auto& e : wall_in) keys.push_back(e.key), histories.push_back(e.history);
    walls_->add_histories(keys, histories);  // merged on the device
  }
  if (list_) list_->particles_changed();
  profile_.mark("migrate:histories-in", shared_.stream);
}

template <class Real>
void DeviceDecomposition<Real>::reorder_own_by_cell() {
  // As the step's renumbering (CudaStep: reorder_by_cell) over the own particles, before the
  // ghosts are appended. The histories wait in the store (kept at drop_ghosts).
  const int own = shared_.count;
  if (own == 0) return;
  list_->keep_histories();
  order_.grow_to(own);
  list_->cell_order(order_.data());
  particles_.keep(order_.data(), own);
  list_->particles_changed();
}

// The own particles (no ghosts yet) within each other rank's halo, chosen on the device into
// send_index_ (rank by rank, in order); only their counts come to the host. Their whole rows are
// packed on the device (DeviceParticles::pack_rows, one kernel a rank), copied once into pinned
// memory and sent; the arriving blocks are copied up once and appended as ghosts (one kernel a
// rank). The counts travel first, so that each rank knows the sizes it receives.
template <class Real>
void DeviceDecomposition<Real>::send_ghosts() {
  const int me = comm_->rank(), ranks = comm_->size();
  const double h = rcb_->halo_width(), h2 = h * h;
  const int own = shared_.count;
  const cudaStream_t stream = shared_.stream;
  std::size_t sending = 0;
  if (own > 0) {
    index_.grow_to(own), flags_.grow_to(own);
    send_index_.grow_to(static_cast<std::size_t>(own) * std::max(1, ranks - 1));
    iota_kernel<<<blocks_for(own), kBlock, 0, stream>>>(index_.data(), own);
    TALUS_CUDA_LAUNCH_CHECK();
  }
  for (int r = 0; r < ranks; ++r) {
    send_count_[r] = 0;
    if (r == me || own == 0) continue;
    flag_near_box<<<blocks_for(own), kBlock, 0, stream>>>(
        shared_.view, own, boxes_.data() + kBoxNumbers * (r + 1), h2, flags_.data());
    TALUS_CUDA_LAUNCH_CHECK();
    send_count_[r] = select_flagged(flags_.data(), own, send_index_.data() + sending);
    sending += send_count_[r];
  }
  // The counts to every rank, theirs from every rank.
  std::vector<Bytes> to(ranks);
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    ByteWriter w(to[r]);
    w.put(static_cast<long long>(send_count_[r]));
  }
  const std::vector<Bytes> from = exchange_bytes(to);
  for (int r = 0; r < ranks; ++r) {
    received_[r] = 0;
    if (r == me) continue;
    ByteReader in(from[r]);
    received_[r] = static_cast<int>(in.get<long long>());
  }
  // The rows packed rank by rank (each block 8-aligned), down, across, up, appended.
  std::vector<std::size_t> out_sizes(ranks, 0), in_sizes(ranks, 0);
  std::size_t out_bytes = 0, in_bytes = 0;
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    out_sizes[r] = send_count_[r] > 0 ? particles_.packed_bytes(send_count_[r]) : 0;
    in_sizes[r] = received_[r] > 0 ? particles_.packed_bytes(received_[r]) : 0;
    out_bytes += out_sizes[r], in_bytes += in_sizes[r];
    bytes_sent_ += static_cast<double>(out_sizes[r]);
  }
  rows_out_.grow_to(out_bytes), rows_in_.grow_to(in_bytes);
  pinned_room(pinned_out_, pinned_out_size_, (out_bytes + sizeof(Real) - 1) / sizeof(Real));
  pinned_room(pinned_in_, pinned_in_size_, (in_bytes + sizeof(Real) - 1) / sizeof(Real));
  std::size_t at = 0, first = 0;
  for (int r = 0; r < ranks; ++r) {
    if (r == me || send_count_[r] == 0) continue;
    particles_.pack_rows(send_index_.data() + first, send_count_[r], rows_out_.data() + at, stream);
    first += send_count_[r], at += out_sizes[r];
  }
  if (out_bytes > 0) {
    TALUS_CUDA_CHECK(
        cudaMemcpyAsync(pinned_out_, rows_out_.data(), out_bytes, cudaMemcpyDeviceToHost, stream));
  }
  TALUS_CUDA_CHECK(cudaStreamSynchronize(stream));
  comm_->exchange_sized(reinterpret_cast<const char*>(pinned_out_), out_sizes,
                        reinterpret_cast<char*>(pinned_in_), in_sizes);
  if (in_bytes > 0) {
    TALUS_CUDA_CHECK(
        cudaMemcpyAsync(rows_in_.data(), pinned_in_, in_bytes, cudaMemcpyHostToDevice, stream));
  }
  at = 0;
  for (int r = 0; r < ranks; ++r) {
    if (r == me || received_[r] == 0) continue;
    particles_.append_packed(rows_in_.data() + at, received_[r], stream);  // owned stays
    at += in_sizes[r];
  }
  list_->particles_changed();
}

template <class Real>
void DeviceDecomposition<Real>::begin_update() {
  const GhostColumns<Real> columns = ghost_columns(shared_.view);
  const std::size_t n = columns.n;
  std::size_t sending = 0, arriving = 0;
  for (int r = 0; r < comm_->size(); ++r) sending += send_count_[r], arriving += received_[r];
  const cudaStream_t stream = shared_.stream;
  // The last step's copies from them are done: its end waited for the stream.
  pinned_room(pinned_out_, pinned_out_size_, sending * n);
  pinned_room(pinned_in_, pinned_in_size_, arriving * n);
  if (sending > 0) {
    packed_out_.grow_to(sending * n);
    pack_ghost_states<<<blocks_for(sending), kBlock, 0, stream>>>(
        columns, send_index_.data(), static_cast<int>(sending), packed_out_.data());
    TALUS_CUDA_LAUNCH_CHECK();
    TALUS_CUDA_CHECK(cudaMemcpyAsync(pinned_out_, packed_out_.data(), sending * n * sizeof(Real),
                                     cudaMemcpyDeviceToHost, stream));
  }
  packed_in_.grow_to(arriving * n);  // here: no allocation between the step's launches later
  TALUS_CUDA_CHECK(cudaEventRecord(packed_, stream));
}

template <class Real>
void DeviceDecomposition<Real>::finish_exchange() {
  const auto start = std::chrono::steady_clock::now();
  const int me = comm_->rank(), ranks = comm_->size();
  const GhostColumns<Real> columns = ghost_columns(shared_.view);
  const std::size_t n = columns.n;
  std::vector<std::size_t> out_sizes(ranks, 0), in_sizes(ranks, 0);
  std::size_t arriving = 0;
  for (int r = 0; r < ranks; ++r) {
    if (r == me) continue;
    out_sizes[r] = send_count_[r] * n * sizeof(Real);
    in_sizes[r] = received_[r] * n * sizeof(Real);
    bytes_sent_ += static_cast<double>(out_sizes[r]);
    arriving += received_[r];
  }
  // Only the pack and its copy: the work enqueued after them goes on.
  TALUS_CUDA_CHECK(cudaEventSynchronize(packed_));
  comm_->exchange_sized(reinterpret_cast<const char*>(pinned_out_), out_sizes,
                        reinterpret_cast<char*>(pinned_in_), in_sizes);
  if (arriving > 0) {
    const cudaStream_t stream = shared_.stream;
    TALUS_CUDA_CHECK(cudaMemcpyAsync(packed_in_.data(), pinned_in_, arriving * n * sizeof(Real),
                                     cudaMemcpyHostToDevice, stream));
    unpack_ghost_states<<<blocks_for(arriving), kBlock, 0, stream>>>(
        columns, packed_in_.data(), static_cast<int>(arriving), shared_.owned);
    TALUS_CUDA_LAUNCH_CHECK();
  }
  exchange_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template class DeviceDecomposition<double>;
template class DeviceDecomposition<float>;

}  // namespace talus
