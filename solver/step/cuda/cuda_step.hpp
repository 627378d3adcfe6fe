// The production step on the CUDA backend: the host step's stages (host_step.hpp) as kernels
// over device arrays, one thread per particle, per candidate pair or per (particle, wall), each
// calling the same TALUS_HD functions (particle_kernels.hpp, pair_kernels.hpp,
// wall_kernels.hpp). The broad phase is ContactPairsGpu on the step's own position arrays, with
// a Verlet skin (Scene::skin): the candidate list is kept, and each candidate keeps its slot,
// until some particle has moved skin / 2, so most steps skip the broad phase. Polyhedron pairs
// of the volume model with at most 64 faces together go through the phased stage: a culling
// kernel (GJK, the kept planes as a 64-bit mask), the slots sorted by their number of kept
// planes, and one polytope kernel per workspace size (8, 16, 32, 64 planes), so that a warp's
// pairs do similar work in little local memory; other pairs (spheres, the linear model, larger
// templates) run whole in one thread with the workspace of their templates' capacity (one
// launch per capacity the scene has). The tangential history lives in the slots, read and replaced
// in place; a rebuild carries the touching slots' histories to the new list by global ids (sorted
// keys, binary search). Accumulation (Scene::deterministic, the default) uses no atomics: each
// contact is written to its slot, then one thread per particle sums its touching slots in pair
// order (a CSR over the list, built with it), then its wall contacts in wall order, as the host
// does, so both backends agree to round-off; with deterministic: false the pair kernel adds the
// forces to the particles by atomics instead. Feeds run as on the host: before a step's
// integrate_begin the same Feeder calls with the same inputs (the positions downloaded only at a
// step where a particle is due); the inserted particles are appended to the device arrays, which
// grow by doubling, and the pair list is rebuilt.
//
// Host-facing: no CUDA types; the implementation exists only in CUDA builds (talus_cuda), where
// TALUS_HAVE_CUDA is defined: cuda_step.cu, with the pair list, the pair stage and the wall
// stage in cuda_pair_list, cuda_pair_stage and cuda_wall_stage.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "solver/domain/communicator.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/run/any_step.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/energy.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/step/step_state.hpp"
#include "solver/walls/facet_grid.hpp"

namespace talus {

struct CudaStepOptions {
  // The templates' properties in constant memory when they fit and a region is free
  // (template_table.hpp); false: always global memory (the benchmark compares the two).
  bool constant_templates = true;
  // The facet grid, or brute force (the same results; for the benchmarks).
  WallSearch wall_search = WallSearch::grid;
  // GJK (Algorithm I) before the culling of each polyhedron pair of the volume model, as the
  // host step's polyhedra_volume_geometry does; false: the culling's separating planes and the
  // overlap's own status decide alone. The paper's filter saves the overlap on separated
  // candidates; in a dense bed nearly every candidate touches and GJK only proves it (the
  // benchmark measures what it costs). The contacts are the same up to round-off at touching.
  bool gjk_filter = true;
  // Graph steps (cuda_step_impl.cuh): a step that needs no decision from the host in its middle is
  // launched as one captured CUDA graph (the same results; a small scene's step is mostly launch
  // overhead). false, or TALUS_CUDA_GRAPHS=0 in the environment, or TALUS_CUDA_SYNC=1: every
  // step stage by stage.
  bool graphs = true;
};

// What the graph steps did: steps launched as a graph, captures of the graph (after each step
// launched stage by stage), graph steps that overran the wall stage's room and finished stage by
// stage; of the captures, those made into a new executable graph (the first, and each whose
// nodes differ from the executable one's: a kernel, a copy's kind, a memset's element size, the
// edges), the others updating it in place; updates the driver refused all the same (each then made
// anew: none is expected, since a capture whose nodes differ is never offered as an update).
struct CudaGraphCounts {
  long long steps = 0, captures = 0, aborted = 0, instantiations = 0, refused_updates = 0;
};

template <class Real>
class CudaStep {
 public:
  using real_type = Real;
  // As HostStep: the scene's initial particles (global id = index), copied to the device, and
  // its feeds. Throws StepNotSupported for what the step cannot simulate, std::runtime_error
  // from CUDA.
  // Decomposed over the ranks of `comm` (docs/parallel.md) when it has more than one, as
  // HostStep's: each rank on the GPU of its local rank (modulo the GPUs), its own particles and
  // its ghosts in its device arrays; step(), evaluate_forces(), export_state() and import_state()
  // are then collectives, and the accessors report this rank's share. No graph steps then.
  explicit CudaStep(const Scene& scene, CudaStepOptions options = CudaStepOptions(),
                    std::shared_ptr<const Communicator> comm = nullptr);
  ~CudaStep();
  CudaStep(const CudaStep&) = delete;
  CudaStep& operator=(const CudaStep&) = delete;

  // As HostStep::step and HostStep::evaluate_forces (the same errors, the same messages; the
  // same particles fed at the same steps).
  void step();
  void evaluate_forces();

  // As HostStep's (step_state.hpp): the arrays downloaded, the pair histories from the touching
  // slots (the store a rebuild of the list carries over), the wall histories from the wall
  // stage's store, the feeds' states; an imported pair store is carried over by the next build
  // of the list. A feeding run's state may hold more particles than the scene starts with.
  StepState<Real> export_state() const;
  void import_state(const StepState<Real>& state);

  double time() const;
  long long steps() const;
  const StepPlan& plan() const;
  int particle_count() const;  // this rank's (ghosts are not counted)
  // Decomposed: seconds in the exchanges between ranks so far (waits included), and how many
  // times the boxes were cut again (as HostStep's).
  double exchange_seconds() const;
  double exchange_vote_seconds() const;     // of exchange_seconds: the rebuild vote's
  double exchange_rebuild_seconds() const;  // of exchange_seconds: the rebuild steps'
  double exchange_bytes() const;            // this rank's sent to the others
  long long rebalances() const;
  // As HostStep's: the local domain, the particles removed so far.
  const Domain& domain() const;
  long long removed_count() const;
  // The scene's feeds' progress now (Feeding::counts; the same on every rank).
  std::vector<FeedCount> feed_counts() const;

  // The device arrays that exist (names as HostStep's) and the device bytes the step holds.
  std::vector<std::string> allocated_arrays() const;
  std::size_t allocated_bytes() const;
  // allocated_bytes() by part, in the order of the step's work: the particles, the pair list's
  // parts (the broad phase, slot states, histories and forces, the history carry-over of a
  // rebuild, the reference positions, the slot CSR), the overlap scratch, the wall stage, CUB's
  // scratch, the renumbering and the shapes. The parts sum to allocated_bytes().
  std::vector<std::pair<std::string, std::size_t>> memory_parts() const;
  // Device seconds per stage (CUDA events around each stage's work), indexed by Stage.
  const StageSeconds& stage_seconds() const;
  // Graph steps so far (CudaStepOptions::graphs).
  CudaGraphCounts graph_counts() const;
  // The stages that run on a stream of their own beside another, each with that stage: the wall
  // stage beside the pair stage (cuda_step_impl.cuh, "The walls beside the pairs"), unless the
  // scene has no walls or TALUS_WALLS_BESIDE_PAIRS=0. Their seconds overlap that stage's.
  std::vector<std::pair<std::string, std::string>> stages_beside() const;
  std::size_t pair_contact_count() const;
  std::size_t wall_contact_count() const;
  // The pair list: how many times it was built, its length, and the device bytes of the list
  // and its slots (the broad phase's arrays, histories, forces, the CSR, the built positions).
  long long pair_list_builds() const;
  bool templates_in_constant_memory() const;
  std::size_t candidate_pair_count() const;
  std::size_t pair_list_bytes() const;
  // Wall w's force and torque about the origin at the last evaluation (the wall contacts are
  // downloaded and summed in double, in order, on the first call after an evaluation).
  Vec3d wall_force(int w) const;
  Vec3d wall_torque(int w) const;

  // Downloaded and computed as HostStep's (particle_rows etc.).
  std::vector<TrajectoryRow> trajectory_rows() const;
  double kinetic_energy() const;
  // The energy balance (energy.hpp): the contacts' energies and the ledger only when the scene
  // asks for the energy probe (dissipation) or has moving walls (their work); else zero.
  EnergyTerms energy() const;
  double bed_height(const Vec3d& gravity) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The CUDA step in the scene's precision, for ProductionSettings::make_step.
std::unique_ptr<AnyStep> make_cuda_step(const Scene& scene);

// `mpirun -np N talus run --backend cuda`: make_decomposed_step and serve_decomposed_step
// (parallel/decomposed_step.hpp) over the CUDA step, each rank on the GPU of its local rank.
std::unique_ptr<AnyStep> make_decomposed_cuda_step(const Scene& scene,
                                                   std::shared_ptr<const Communicator> comm);
void serve_decomposed_cuda_step(const Scene& scene, std::shared_ptr<const Communicator> comm);

}  // namespace talus
