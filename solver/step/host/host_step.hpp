// The production step on the host backend: the scene's particles in a structure of arrays, the
// stages of its plan (step_plan.hpp) run as loops over the per-particle and per-pair functions
// that the CUDA backend launches as kernels, on several threads with OpenMP
// (core/host_parallel.hpp). Deterministic, the same bits for any thread count: every loop writes
// per-index slots, and contact forces are summed per particle in pair order, then its walls. The
// candidate pairs are a Verlet list with the CUDA step's skin rule (contact_stage.hpp), kept
// across steps; its age changes no bit of the results.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solver/domain/communicator.hpp"
#include "solver/domain/domain.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/scene.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/step/energy.hpp"
#include "solver/step/feeding.hpp"
#include "solver/step/particle_kernels.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/step/step_state.hpp"
#include "solver/walls/facet_grid.hpp"

namespace talus {

template <class Real>
class PairContactStage;  // contact_stage.hpp
template <class Real>
class WallContactStage;  // wall_stage.hpp

// Mass properties of a template with its material's density (in double, then rounded once);
// `arrays` are the template's shape arrays (null for a sphere). Shared with the CUDA step.
template <class Real>
BodyProperties<Real> body_properties(const Scene& scene, const ParticleTemplate& t,
                                     const ShapeArrays<Real>* arrays);

// The outputs of a particle view in host memory: trajectory rows (world-frame angular
// velocity; in global-id order, whatever the order in memory), kinetic energy (J), the highest
// particle point along -g (m). Shared with the CUDA step, which downloads its arrays first.
template <class Real>
std::vector<TrajectoryRow> particle_rows(const ParticleView<Real>& view);
template <class Real>
double particle_kinetic_energy(const ParticleView<Real>& view,
                               const std::vector<BodyProperties<Real>>& bodies);
template <class Real>
double particle_bed_height(const ParticleView<Real>& view,
                           const std::vector<BodyProperties<Real>>& bodies, const Vec3d& gravity);
// The particles' kinetic (translational, rotational) and gravitational energies (`gravity` null:
// none) into `terms`; the rest of `terms` is left as it is.
template <class Real>
void particle_energies(const ParticleView<Real>& view,
                       const std::vector<BodyProperties<Real>>& bodies, const Vec3d* gravity,
                       EnergyTerms& terms);
// The kinetic and gravitational energy particle i brings (a feed's insertion), J.
template <class Real>
double particle_energy(const ParticleView<Real>& view,
                       const std::vector<BodyProperties<Real>>& bodies, const Vec3d* gravity,
                       int i);

template <class Real>
class HostStep {
 public:
  using real_type = Real;
  // The scene's initial particles (global id = index), its templates and effects; the loops run
  // on `threads` threads (<= 0: OpenMP's default, all cores or OMP_NUM_THREADS; 1 in a build
  // without OpenMP). `wall_search`: the facet grid, or brute force (the same results; for the
  // benchmarks). Throws StepNotSupported naming the scene item for what the production step
  // cannot simulate.
  explicit HostStep(const Scene& scene, int threads = 0, WallSearch wall_search = WallSearch::grid);
  // Decomposed over the ranks of `comm` (docs/parallel.md) when it has more than one: this rank
  // keeps the particles its box of a recursive bisection of the initial particles owns (an
  // RcbDomain, which domain() then is) and sees the others' within the halo as ghosts, appended
  // after its own; step(), evaluate_forces(), export_state() and import_state() are then
  // collectives (every rank calls them in turn), and what the accessors report is this rank's
  // share (its particles, the contacts attributed to it: both particles its own, or its own the
  // lower global id). The trajectories are those of one process to the bit, whatever the rank
  // count: each particle's contacts are summed in the order of their partners' global ids.
  HostStep(const Scene& scene, int threads, std::shared_ptr<const Communicator> comm);
  ~HostStep();
  HostStep(const HostStep&) = delete;
  HostStep& operator=(const HostStep&) = delete;

  // One step of dt: integrate_begin, the force stages at the new state, integrate_end. The
  // first call evaluates the forces at t = 0 first (springs do not grow then). Before
  // integrate_begin the scene's feeds insert the particles due at the step's start time, as the
  // reference solver's run does (scene/feeder.hpp, the same Feeder calls in the same order):
  // appended with the next global ids, their body forces (gravity, drag) set at once, every
  // particle array grown (capacity doubling, so insertions do not reallocate every step). Throws
  // std::runtime_error when a particle's rotation does not converge (|w| dt too large), naming the
  // lowest such index whatever the thread count.
  void step();
  // The force stages alone at the current state (as the first step does): for step 0's outputs.
  void evaluate_forces();

  // Keeps the particles at indices order[0 .. k) in that order and drops the rest: a permutation
  // (the renumbering by cell) or a removal. Every array and id moves with its particle; the
  // contact histories are keyed by global ids (tangential_history.hpp), so the touching pairs of
  // the kept particles keep theirs and a removed particle's leave the store at the next
  // evaluation, which rebuilds the pair list. Between steps only (the contact records of the last
  // evaluation name indices).
  void keep_particles(const std::vector<int>& order);
  // The local domain: the scene's box (or all of space), its halo (domain/domain.hpp).
  const Domain& domain() const { return *domain_; }
  // Particles removed so far (their centroids left the domain box).
  long long removed_count() const { return removed_; }
  // The scene's feeds' progress now (Feeding::counts; the same on every rank).
  std::vector<FeedCount> feed_counts() const { return feeding_.counts(time_); }

  // The state to go on from (restart; step_state.hpp), and setting it on a step made from the
  // same scene: the next step() continues as this one's would, to the bit. import_state throws
  // CheckpointError when the state does not fit the step (particle count, arrays, feeds) or holds
  // a value no run writes (check_state_fits: ids, times, non-finite numbers, history keys).
  StepState<Real> export_state() const;
  void import_state(const StepState<Real>& state);

  double time() const { return time_; }
  long long steps() const { return steps_; }
  const StepPlan& plan() const { return plan_; }
  int threads() const { return threads_; }
  int particle_count() const { return owned_; }  // this rank's (ghosts are not counted)
  // Whether the step is decomposed over several ranks.
  bool decomposed() const { return comm_ != nullptr; }
  const Communicator* communicator() const { return comm_.get(); }
  int ghost_count() const { return count_ - owned_; }
  const ParticleView<Real>& particles() const { return view_; }
  const std::vector<BodyProperties<Real>>& bodies() const { return bodies_; }

  // The particle arrays that exist (names as in ParticleView) and their bytes.
  std::vector<std::string> allocated_arrays() const;
  std::size_t allocated_bytes() const;
  // Wall-clock seconds spent in each stage so far, indexed by Stage.
  const StageSeconds& stage_seconds() const { return stage_seconds_; }
  // Decomposed: wall-clock seconds in the exchanges between ranks so far (migration, ghosts, the
  // feeds' gathering), waiting for the other ranks included.
  double exchange_seconds() const { return exchange_seconds_; }
  // Of exchange_seconds: the rebuild vote's (the wait for the slowest rank included) and the
  // rebuild steps' (migration, the ghosts chosen again).
  double exchange_vote_seconds() const { return exchange_vote_seconds_; }
  double exchange_rebuild_seconds() const { return exchange_rebuild_seconds_; }
  // Decomposed: the bytes this rank sent to the others so far.
  double exchange_bytes() const { return exchange_bytes_; }
  // Decomposed: how many times the boxes were cut again (Scene::rebalance).
  long long rebalances() const { return rebalances_; }
  // Touching particle pairs at the last force evaluation (0 without contacts).
  std::size_t pair_contact_count() const;
  // Builds of the pair list so far (contact_stage.hpp: kept until a particle has moved 0.45 skin
  // or the particles changed) and the candidates in it now; 0 without contacts.
  long long pair_list_builds() const;
  std::size_t candidate_pair_count() const;
  // Particle-wall contacts (one per particle and wall at most) at the last force evaluation.
  std::size_t wall_contact_count() const;
  // Wall w's total contact force (N) and torque about the origin (N m) at the last evaluation.
  Vec3d wall_force(int w) const;
  Vec3d wall_torque(int w) const;

  // Output rows (world-frame angular velocity), kinetic energy (translation + rotation, J), the
  // highest particle point along -g (m; polyhedra: highest vertex, spheres: top).
  std::vector<TrajectoryRow> trajectory_rows() const;
  double kinetic_energy() const;
  double bed_height(const Vec3d& gravity) const;
  // The energy balance at the last evaluation (energy.hpp).
  EnergyTerms energy() const;

 private:
  Real* allocate(const std::string& name);
  void bind_view();      // view_'s pointers into the arrays
  void grow(int count);  // every particle array to `count`
  // Index i's state and ids from p, with global id `id` (-1: the next one).
  void set_particle(int i, const ParticleState& p, long long id = -1);
  void feed();  // the feeds' insertions at time_
  void run_force_stages(Real spring_dt);
  // Decomposed: the rank's ghosts brought up to date after the particles moved. Where any
  // rank's pair list expired or its particles changed (`rebuild`, or the ranks agree it is due):
  // the ghosts dropped, the particles that left the box sent to their owners with their
  // histories, and the ghosts chosen and sent again; otherwise the same ghosts' new states.
  void exchange(bool rebuild);
  // The boxes cut from the particles held now (every rank holds the same ones: the start, a
  // restart), each rank keeping its own.
  void decompose();
  void drop_ghosts();  // the particles from owned_ on
  // Decomposed export_state: every rank's particles (in global-id order), histories and ledger, on
  // every rank: the state of one process, which a run on any number of ranks restarts from.
  StepState<Real> gathered_state() const;
  void migrate();
  // comm_->exchange(to), the bytes sent to other ranks counted.
  std::vector<Bytes> exchange_bytes(const std::vector<Bytes>& to);
  void send_ghosts();
  void update_ghosts();
  // Ghost data: the states the pair stage reads of a partner, written and read in one order.
  void put_ghost(ByteWriter& w, int i, bool ids) const;
  void get_ghost(ByteReader& r, int i, bool ids);
  // Whether the contact is this rank's to count (both particles its own, or its own the lower id).
  bool attributed(int a, int b) const;
  // The particle view of this rank's own particles (the ghosts follow them).
  ParticleView<Real> owned_view() const;
  // Decomposed: every rank's particle positions and templates, for the feeds.
  void gather_all(std::vector<Vec3d>& positions, std::vector<int>& templates) const;
  // With `reorder`, where the pair list expires: the particles renumbered by cell
  // (neighbor/contact_pairs.hpp, cell_order).
  void reorder_by_cell();
  // With a domain box: the particles whose centroid has left it, removed, their energy to the
  // ledger's `removed`.
  void remove_outside();
  // What the contacts of the last evaluation report to the energy ledger.
  ContactRates contact_rates() const;
  template <class Body>
  void timed(Stage stage, Body&& body);

  const Scene& scene_;
  StepPlan plan_;
  Real dt_;
  int threads_;
  int count_ = 0;
  // The scene's initial particles this step was built without (Scene::left_out_particles; a
  // resumed run's): the first import_state checks the checkpoint's count against them.
  std::size_t left_out_ = 0;
  std::vector<std::unique_ptr<ShapeArrays<Real>>> shapes_;  // per template (polyhedra)
  std::vector<BodyProperties<Real>> bodies_;                // per template
  std::vector<int> template_of_particle_;
  std::vector<std::pair<std::string, std::vector<Real>>> storage_;
  std::vector<int> template_ids_, material_ids_;
  std::vector<long long> global_ids_;
  long long next_id_ = 0;  // the global id of the next particle set (ids are never reused)
  long long removed_ = 0;
  std::unique_ptr<Domain> domain_;
  ParticleView<Real> view_;
  std::unique_ptr<PairContactStage<Real>> contacts_;
  std::unique_ptr<WallContactStage<Real>> walls_;
  Feeding feeding_;  // the scene's feeds (step/feeding.hpp)
  StageSeconds stage_seconds_{};
  double time_ = 0;
  long long steps_ = 0;
  bool forces_ready_ = false;
  EnergyLedger ledger_;
  // Decomposition (null comm_: one process). Particles [0, owned_) are this rank's, the rest
  // ghosts; send_[r]: the indices whose states rank r holds as ghosts, in the order it holds them.
  std::shared_ptr<const Communicator> comm_;
  const RcbDomain* rcb_ = nullptr;  // domain_ when decomposed
  int owned_ = 0;
  bool changed_ = false;  // this rank's particles changed since the last exchange
  std::vector<std::vector<int>> send_;
  std::vector<int> received_;   // ghosts from each rank, in rank order after the own particles
  Bytes ghost_out_, ghost_in_;  // update_ghosts' packed states, kept between steps
  double exchange_seconds_ = 0, exchange_vote_seconds_ = 0, exchange_rebuild_seconds_ = 0;
  double exchange_bytes_ = 0;
  long long rebalances_ = 0;
};

}  // namespace talus
