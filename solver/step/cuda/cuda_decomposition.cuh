// The CUDA step decomposed over MPI ranks (docs/parallel.md), as the host step is
// (host_decomposition.cpp): each rank owns the particles of its box of a recursive bisection
// (RcbDomain) and holds the others' within the halo as ghosts after its own, in the same device
// arrays. Every step the ghosts' states (position, velocity, orientation, angular velocity) are
// packed on the device by the send lists, staged through pinned host memory (Open MPI here is
// not CUDA-aware) and unpacked into the ghost slots. Where some rank's pair list has expired or
// its particles changed (agreed by one reduction), the ghosts are dropped, the particles that left
// the box migrate with their pair and wall histories (only the entries naming them leave the
// device), the boxes are cut again when one rank holds too many, the own particles are renumbered
// by cell, and the ghosts are chosen and sent again as whole particles. Included only from .cu
// files.
#pragma once

#include <chrono>
#include <memory>
#include <utility>
#include <vector>

#include "solver/domain/communicator.hpp"
#include "solver/domain/domain.hpp"
#include "solver/step/cuda/cuda_pair_list.cuh"
#include "solver/step/cuda/cuda_particles.cuh"
#include "solver/step/cuda/cuda_wall_stage.cuh"

namespace talus {

template <class Real>
class DeviceDecomposition {
 public:
  // The parts of the step it moves particles between (list and walls null when absent).
  DeviceDecomposition(DeviceStepShared<Real>& shared, DeviceParticles<Real>& particles,
                      DevicePairList<Real>* list, DeviceWallStage<Real>* walls,
                      std::shared_ptr<const Communicator> comm);
  ~DeviceDecomposition();
  DeviceDecomposition(const DeviceDecomposition&) = delete;
  DeviceDecomposition& operator=(const DeviceDecomposition&) = delete;

  // Every rank holds the same particles (the start, a restart): the boxes cut from them, each
  // rank keeping those of its own (DeviceStepShared::owned and domain set).
  void decompose();
  // The ghosts brought up to date after integrate_begin; with `rebuild` (or where any rank's
  // list is due or its particles changed) the migration and the ghosts chosen again (a
  // collective). begin_exchange then finish_exchange.
  void exchange(bool rebuild) {
    if (begin_exchange(rebuild)) finish_exchange();
  }
  // The ranks' vote, and a rebuild when due (as exchange); else the ghosts' update begun: their
  // states packed and copied to pinned host memory on the step's stream, nothing waiting.
  // Returns whether an update is pending: finish_exchange is then due, and the step may enqueue
  // work that needs no ghost (its inner slots) first, which the device does while the states
  // travel (method paper §2.6).
  bool begin_exchange(bool rebuild);
  // The pending update's messages (after the copy to the host; a collective in effect) and the
  // arrivals copied to the device and unpacked into the ghosts, on the step's stream (nothing
  // waits for that; the step's end does).
  void finish_exchange();
  // Before particles are appended or removed: the ghosts dropped, and the next exchange rebuilds.
  void drop_ghosts();
  void particles_changed() { changed_ = true; }
  // Every rank's particle positions and templates (a feed's inputs; a collective).
  void gather_all(std::vector<Vec3d>& positions, std::vector<int>& templates);

  const RcbDomain& domain() const { return *rcb_; }
  const Communicator& comm() const { return *comm_; }
  double exchange_seconds() const { return exchange_seconds_; }
  // Of exchange_seconds: the rebuild vote's (the wait for the slowest rank included) and the
  // rebuild steps' (migration, renumbering, the ghosts chosen again).
  double vote_seconds() const { return vote_seconds_; }
  double rebuild_seconds() const { return rebuild_seconds_; }
  void add_exchange_seconds(double s) { exchange_seconds_ += s; }
  long long rebalances() const { return rebalances_; }
  // Bytes sent to other ranks so far (ghosts, migrations).
  double bytes_sent() const { return bytes_sent_; }

 private:
  void cut(const std::vector<Vec3d>& points);
  void migrate();
  void reorder_own_by_cell();
  void send_ghosts();
  void begin_update();
  std::vector<Bytes> exchange_bytes(const std::vector<Bytes>& to);
  // index_[i] for the first n i with flags[i] set, in order, into `out` (on the device); their
  // number.
  int select_flagged(const unsigned char* flags, int n, int* out);

  DeviceStepShared<Real>& shared_;
  DeviceParticles<Real>& particles_;
  DevicePairList<Real>* list_;
  DeviceWallStage<Real>* walls_;
  std::shared_ptr<const Communicator> comm_;
  std::unique_ptr<RcbDomain> rcb_;
  bool changed_ = true;
  // send_count_[r]: how many own particles rank r holds as ghosts; their indices on the device in
  // send_index_, rank after rank, each rank's in its order, with the packed states and the
  // arriving ones.
  std::vector<std::size_t> send_count_;
  std::vector<int> received_;  // ghosts from each rank
  DeviceBuffer<int> send_index_, order_;
  DeviceBuffer<char> rows_out_, rows_in_;  // send_ghosts' packed rows (device)
  // The boxes as box_arrays.hpp's numbers (the region, then each rank's), and the scratch of
  // the device's classification (migrate, send_ghosts).
  DeviceBuffer<double> boxes_;
  DeviceBuffer<int> index_, destination_, selected_;
  DeviceBuffer<unsigned char> flags_;
  DeviceBuffer<Real> packed_out_, packed_in_;
  Real* pinned_out_ = nullptr;
  Real* pinned_in_ = nullptr;
  std::size_t pinned_out_size_ = 0, pinned_in_size_ = 0;  // Reals
  cudaEvent_t packed_ = nullptr;  // the sent states are in pinned_out_ (begin_update)
  double exchange_seconds_ = 0, bytes_sent_ = 0, vote_seconds_ = 0, rebuild_seconds_ = 0;
  long long rebalances_ = 0;

  // TALUS_EXCHANGE_PROFILE=1: the rebuild steps' parts timed, the stream waited for at the end
  // of each (which an unprofiled run does not do), and printed by each rank on stderr when the
  // step ends (docs/parallel.md, "Costs (GPU backend)").
  struct RebuildProfile {
    bool on = false;
    long long rebuilds = 0;
    std::vector<std::pair<const char*, double>> parts;  // in the order first marked
    std::chrono::steady_clock::time_point last;
    void start(cudaStream_t stream);
    void mark(const char* part, cudaStream_t stream);
  };
  RebuildProfile profile_;
};

}  // namespace talus
