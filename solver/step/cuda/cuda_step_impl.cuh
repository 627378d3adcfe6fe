// The CUDA step's state and the order of its work (CudaStep<Real>::Impl, cuda_step.hpp's
// pimpl): the stages it owns, the force stages in the plan's order, the per-particle stages and
// the accumulation (their kernels in cuda_particle_kernels.cuh), the end-of-step report and the
// graph steps. Its set-up, feeds and removal are defined in cuda_step.cu, the only file that
// includes this one.
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/geometry/device_shape.cuh"
#include "solver/shape/shape_arrays.hpp"
#include "solver/step/cuda/cuda_decomposition.cuh"
#include "solver/step/cuda/cuda_pair_stage.cuh"
#include "solver/step/cuda/cuda_particle_kernels.cuh"
#include "solver/step/cuda/cuda_particles.cuh"
#include "solver/step/cuda/cuda_step.hpp"
#include "solver/step/cuda/cuda_wall_stage.cuh"
#include "solver/step/cuda/stage_timer.cuh"
#include "solver/step/feeding.hpp"

namespace talus {

// What the host reads at the end of each step, in one wait (pinned memory, filled by copies at
// the end of the step's work on its stream): the flags, the contacts' energy sums and the pair
// list's predicted move (DevicePairList::predict_move).
struct StepReport {
  int raised[Flag::flags];
  double energy[kEnergySums];
  unsigned long long predicted_move;
};

// Graph steps only for scenes up to this many particles: a graph's kernels are launched for
// their capacities (every slot, every particle-wall pair), which costs nothing in a small scene,
// whose step is launch overhead, and a little in a large one, whose step is arithmetic.
inline constexpr int kGraphParticles = 1 << 17;

template <class Real>
struct CudaStep<Real>::Impl {
  StepPlan plan;
  Real dt;
  DeviceStepShared<Real> shared;
  const Scene& scene;
  std::vector<std::unique_ptr<ShapeArrays<Real>>> host_shapes;  // per template (polyhedra)
  std::vector<BodyProperties<Real>> host_bodies;                // host shape views
  std::vector<std::unique_ptr<DeviceShape<Real>>> device_shapes;
  DeviceBuffer<BodyProperties<Real>> bodies;  // device shape views
  DeviceBuffer<Real> table_values;            // the pair-law tables' numbers
  std::unique_ptr<DeviceParticles<Real>> particles;
  Feeding feeding;  // the scene's feeds, as HostStep's (step/feeding.hpp)
  // The stages the plan names (null when absent).
  std::unique_ptr<DevicePairList<Real>> list;
  std::unique_ptr<DevicePairStage<Real>> pairs;
  std::unique_ptr<DeviceWallStage<Real>> walls;
  // Decomposed over MPI ranks (cuda_decomposition.cuh; null: one process).
  std::unique_ptr<DeviceDecomposition<Real>> decomposition;

  std::unique_ptr<Domain> domain;  // the local domain (domain/domain.hpp)
  // Renumbering and removal: the kept particles' order, flags and removed energies.
  DeviceBuffer<int> order, index;
  DeviceBuffer<unsigned char> keep_flags;
  DeviceBuffer<double> removed_energy, removed_sum;
  long long removed = 0;

  StageSeconds stage_seconds{};
  // Graph steps ("Graph steps" below).
  StepReport* report = nullptr;                // pinned
  DeviceBuffer<unsigned long long> predicted;  // the report's predicted move, on the device
  // The own particles' energy parts (translational, rotational, gravitational), summed on the
  // device (cuda_step_outputs.cu); the blocks' sums, then the three totals. bed_height uses the
  // same two buffers for the blocks' highest points and the highest.
  std::array<double, 3> energy_parts() const;
  mutable DeviceBuffer<double> energy_sums_by_block, energy_total;
  cudaGraphExec_t graph = nullptr;
  std::vector<unsigned long long> graph_nodes;  // graph_node_signature of the executable graph's
  bool graphs_on = true;                        // the option, the environment and no failed capture
  bool recapture = true;  // a step ran stage by stage since the graph was captured
  CudaGraphCounts graph_counts;
  double time = 0;
  long long steps = 0;
  bool forces_ready = false;
  // The scene's initial particles this step was built without (Scene::left_out_particles; a
  // resumed run's): the first import_state checks the checkpoint's count against them.
  std::size_t left_out = 0;
  EnergyLedger ledger;
  std::array<double, kEnergySums> energy_sums{};  // the last evaluation's

  // The force stages in two parts for a decomposed step whose ghosts' states travel meanwhile
  // (decomposed_step): `inner`, what needs no ghost (the body forces and the slots of two own
  // particles, DevicePairList::inner_candidates), enqueued without waiting for the device; then
  // `outer`, the slots with a ghost, the walls and the accumulation. `whole`: both at once.
  enum class ForcePart { whole, inner, outer };

  // The force stages with the energy sums around them (when asked for): the contacts' sums
  // zeroed before and added up after; they reach the report at the end of the step.
  void run_force_stages_with_energy(Real spring_dt, ForcePart part = ForcePart::whole) {
    const bool track = shared.energy_sums.size() > 0;
    if (track && part != ForcePart::outer) {
      TALUS_CUDA_CHECK(cudaMemsetAsync(shared.energy_sums.data(), 0, sizeof(double) * kEnergySums,
                                       shared.stream));
    }
    run_force_stages(spring_dt, part);
    if (track && walls && part != ForcePart::inner)
      walls->add_energy_sums(shared.energy_sums.data());
  }

  // The ledger from the report's energy sums: its start at the first evaluation, else a step.
  void take_energy(bool first) {
    if (shared.energy_sums.size() == 0) return;
    std::copy(report->energy, report->energy + kEnergySums, energy_sums.begin());
    ContactRates rates;
    rates.dissipation = energy_sums[sum_dissipation];
    rates.wall_power = energy_sums[sum_wall_power];
    rates.spring = energy_sums[sum_tangential];
    if (first) {
      ledger.start(rates);
    } else {
      ledger.advance(scene.time_step, rates);
    }
  }

  explicit Impl(const Scene& s)
      : plan(plan_step(s)),
        dt(Real(s.time_step)),
        shared(s),
        scene(s),
        feeding(s),
        domain(make_scene_domain(s)) {
    shared.domain = domain.get();
  }
  ~Impl();  // cuda_step.cu
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  int count() const { return shared.count; }
  int own_count() const { return shared.own_count(); }  // without the ghosts
  ParticleView<Real>& view() { return shared.view; }

  // As HostStep::reorder_by_cell, at a build of the list: the touching histories kept by
  // global ids, the particles gathered in cell order, the list told.
  void reorder_by_cell() {
    list->keep_histories();
    order.grow_to(count());
    list->cell_order(order.data());
    particles->keep(order.data(), count());
    list->particles_changed();
  }
  void flag_outside();
  void grow_outside_buffers();
  void remove_outside(int outside);

  // ---- Graph steps ----
  // A small scene's step is launch overhead and waits: some thirty kernels, each a few
  // microseconds of the host's time, for work the device does in less. A step that needs no
  // decision from the host in its middle is captured once as a CUDA graph and then launched
  // whole, one call per step, the host waiting once at its end for the report. Such a step:
  // the pair list is kept (the step before predicted every particle's next position short of
  // the rebuild distance, DevicePairList::keeps), no feed is due, the wall stage has room for a
  // record per particle-wall pair, and the scene is small (kGraphParticles). The stages then
  // read nothing back (DeviceStepShared::graph_mode) and are launched for their capacities; the
  // only thing a graph step can overrun is the wall stage's room for facets, which aborts the
  // kernels after it (AbortCheck), and the step then finishes stage by stage
  // (finish_aborted_step). A step launched stage by stage (a rebuild, a feed, a removal) may
  // reallocate any array, so the next graph step captures the graph again, updating the
  // executable one in place when its shape is the same. The results are the same bits as stage
  // by stage (GpuGraphStep tests).

  // Whether this step may run as a graph (before its work; the step's time is advanced).
  bool graph_due() const {
    if (!graphs_on || decomposition || count() == 0 || count() > kGraphParticles) return false;
    return !list || list->keeps(report->predicted_move);
  }

  // Launches the step's graph (capturing it first when due); false when it cannot (the step then
  // runs stage by stage).
  bool launch_graph() {
    if (recapture && !capture_graph()) return false;
    if (!recapture && walls) walls->stage_placement(time);  // the capture placed them
    TALUS_CUDA_CHECK(cudaGraphLaunch(graph, shared.stream));
    recapture = false;
    return true;
  }

  bool capture_graph() {
    if (walls && !walls->prepare_graph()) return false;
    grow_outside_buffers();
    stage_timer.release_graph();
    cudaGraph_t captured = nullptr;
    TALUS_CUDA_CHECK(cudaStreamBeginCapture(shared.stream, cudaStreamCaptureModeThreadLocal));
    shared.graph_mode = true;
    try {
      enqueue_step();
    } catch (const std::exception& e) {
      shared.graph_mode = false;
      shared.abort = AbortCheck{};
      cudaStreamEndCapture(shared.stream, &captured);  // ends the capture; its error is e
      if (captured) cudaGraphDestroy(captured);
      cudaGetLastError();
      stage_timer.release_graph();
      graphs_on = false;
      std::fprintf(stderr, "talus: cuda step: graph steps off (capture failed: %s)\n", e.what());
      return false;
    }
    shared.graph_mode = false;
    shared.abort = AbortCheck{};
    TALUS_CUDA_CHECK(cudaStreamEndCapture(shared.stream, &captured));
    ++graph_counts.captures;
    std::vector<unsigned long long> nodes;
    // A signature the runtime would not give (not expected) only costs the update: the capture
    // is then made into a new executable graph, as one whose nodes changed.
    const bool known = graph_node_signature(captured, nodes) == cudaSuccess;
    if (!known) {
      cudaGetLastError();  // not sticky
      nodes.clear();
    }
    bool updated = false;
    // An update is offered only for the same nodes: one the driver must refuse (a kernel more or
    // less after a feed, another copy) would be an API error that compute-sanitizer reports.
    if (known && graph && nodes == graph_nodes) {
      cudaGraphExecUpdateResultInfo info;
      updated = cudaGraphExecUpdate(graph, captured, &info) == cudaSuccess;
      if (!updated) {
        cudaGetLastError();  // not sticky: a new executable graph instead
        ++graph_counts.refused_updates;
      }
    }
    cudaError_t made = cudaSuccess;
    if (!updated) {
      if (graph) made = cudaGraphExecDestroy(graph);
      graph = nullptr;
      graph_nodes.clear();
      if (made == cudaSuccess) made = cudaGraphInstantiate(&graph, captured, 0);
      if (made == cudaSuccess) {
        if (known) graph_nodes = std::move(nodes);
        ++graph_counts.instantiations;
      }
    }
    cudaGraphDestroy(captured);
    TALUS_CUDA_CHECK(made);
    return true;
  }

  // What cudaGraphExecUpdate requires to be unchanged, node by node in the order of capture: the
  // node's type and its number of dependencies; a kernel's function; a memset's element size and
  // height (a 1-D memset's width may change); a copy's kind; and the number of edges.
  static cudaError_t graph_node_signature(cudaGraph_t g, std::vector<unsigned long long>& out) {
    out.clear();
    std::size_t count = 0, edges = 0;
    cudaError_t e = cudaGraphGetNodes(g, nullptr, &count);
    if (e != cudaSuccess) return e;
    std::vector<cudaGraphNode_t> nodes(count);
    if (count > 0 && (e = cudaGraphGetNodes(g, nodes.data(), &count)) != cudaSuccess) return e;
    if ((e = cudaGraphGetEdges(g, nullptr, nullptr, nullptr, &edges)) != cudaSuccess) return e;
    out.push_back(edges);
    for (cudaGraphNode_t node : nodes) {
      cudaGraphNodeType type{};
      std::size_t deps = 0;
      if ((e = cudaGraphNodeGetType(node, &type)) != cudaSuccess) return e;
      if ((e = cudaGraphNodeGetDependencies(node, nullptr, nullptr, &deps)) != cudaSuccess) {
        return e;
      }
      out.push_back(static_cast<unsigned long long>(type));
      out.push_back(deps);
      if (type == cudaGraphNodeTypeKernel) {
        cudaKernelNodeParams k{};
        if ((e = cudaGraphKernelNodeGetParams(node, &k)) != cudaSuccess) return e;
        out.push_back(reinterpret_cast<unsigned long long>(k.func));
      } else if (type == cudaGraphNodeTypeMemset) {
        cudaMemsetParams m{};
        if ((e = cudaGraphMemsetNodeGetParams(node, &m)) != cudaSuccess) return e;
        out.insert(out.end(), {m.elementSize, m.height});
      } else if (type == cudaGraphNodeTypeMemcpy) {
        cudaMemcpy3DParms c{};
        if ((e = cudaGraphMemcpyNodeGetParams(node, &c)) != cudaSuccess) return e;
        out.push_back(static_cast<unsigned long long>(c.kind));
      }
    }
    return cudaSuccess;
  }

  // The step's work after the feeds, in order, on the step's stream: everything a graph holds.
  void enqueue_step() {
    shared.abort = AbortCheck{};
    shared.flags.reset(shared.stream);
    enqueue_integrate_begin();
    run_force_stages_with_energy(dt);
    finish_enqueue();
  }

  // Decomposed: the step's integrate_begin, the ghosts' exchange beside the inner slots, the rest
  // (cuda_step.cu).
  void decomposed_step();
  // Whether a decomposed step overlaps the ghosts' update with its inner work (unless
  // TALUS_HALO_OVERLAP=0 in the environment).
  static bool overlap_halo() {
    static const bool on = [] {
      const char* v = std::getenv("TALUS_HALO_OVERLAP");
      return v == nullptr || std::string(v) != "0";
    }();
    return on;
  }

  void enqueue_integrate_begin() {
    const OwnParticlesOnly<Real> own(shared);  // a ghost is its owner's to move
    if (count() == 0) return;
    timed(Stage::integrate_begin, [&] {
      integrate_begin_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
          view(), bodies.data(), dt, shared.flags.data());
      TALUS_CUDA_LAUNCH_CHECK();
    });
  }

  // The end of a step's work: integrate_end, the list's predicted move, the particles outside
  // (not after an aborted graph step, whose graph flagged them: positions do not change after
  // integrate_begin), the report's copies.
  void finish_enqueue(bool flag_particles_outside = true) {
    {
      const OwnParticlesOnly<Real> own(shared);
      if (count() > 0) {
        timed(Stage::integrate_end, [&] {
          integrate_end_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
              view(), bodies.data(), dt, shared.abort);
          TALUS_CUDA_LAUNCH_CHECK();
        });
      }
    }
    if (list && !decomposition) {
      predicted.grow_to(1);
      list->predict_move(bodies.data(), dt, predicted.data(), shared.abort, shared.stream);
    }
    if (flag_particles_outside) flag_outside();
    copy_report();
  }

  // The report's copies (on the step's stream; part of a graph).
  void copy_report() {
    shared.flags.copy_to(report->raised, shared.stream);
    if (shared.energy_sums.size() > 0) {
      TALUS_CUDA_CHECK(cudaMemcpyAsync(report->energy, shared.energy_sums.data(),
                                       sizeof(double) * kEnergySums, cudaMemcpyDeviceToHost,
                                       shared.stream));
    }
    if (list && predicted.size() > 0) {  // none decomposed (no graph steps)
      TALUS_CUDA_CHECK(cudaMemcpyAsync(&report->predicted_move, predicted.data(),
                                       sizeof(unsigned long long), cudaMemcpyDeviceToHost,
                                       shared.stream));
    }
  }

  // The one wait of a step: for its work and its report.
  void report_and_wait() { TALUS_CUDA_CHECK(cudaStreamSynchronize(shared.stream)); }
  std::array<int, flags> report_flags() const {
    std::array<int, flags> all{};
    std::copy(report->raised, report->raised + flags, all.begin());
    return all;
  }

  // A graph step whose wall stage overran its room for facets: the pair stage is done, the wall
  // stage and what follows it did nothing; the wall stage again stage by stage with more room,
  // then the rest of the step.
  void finish_aborted_step(int facets) {
    ++graph_counts.aborted;
    walls->recover(dt, time, facets);
    if (shared.energy_sums.size() > 0) walls->add_energy_sums(shared.energy_sums.data());
    timed(Stage::accumulate, [&] { accumulate(); });
    finish_enqueue(false);
    TALUS_CUDA_CHECK(cudaStreamSynchronize(shared.stream));
    recapture = true;
  }

  void upload_templates(const CudaStepOptions& options);
  void set_up_pairs(const PairLawTables<Real>& host_tables);
  void feed();

  StageTimer stage_timer;  // stage_seconds from CUDA events (stage_timer.cuh)

  template <class Body>
  void timed(Stage stage, Body&& body) {
    stage_timer.timed(stage, shared.stream, shared.graph_mode, std::forward<Body>(body));
  }
  void collect_stage_times() { stage_timer.collect(stage_seconds); }

  // The flags the step's kernels raised (from the report, read at the step's end): a rotation
  // that did not converge, a pair whose geometry failed (the walls' are read by their stage,
  // which waits for its count anyway, or after a graph step); the pairs' touching count kept.
  void check_flags(const std::array<int, flags>& all) {
    check_rotation(all[failed_rotation]);
    if (pairs) pairs->check_flags(all);
    collect_stage_times();
  }

  // The flag failed_rotation's value: INT_MAX, or the lowest index whose rotation failed.
  void check_rotation(int failed) const {
    if (failed != INT_MAX) {
      throw std::runtime_error(
          scene.file + ": particle " + std::to_string(shared.global_id(failed)) +
          " spins too fast for time.step (the implicit-midpoint rotation did not converge)");
    }
  }

  void accumulate() {
    const OwnParticlesOnly<Real> own(shared);  // the ghosts' sums are their owners'
    if (count() == 0) return;
    const bool slots = scene.deterministic && list && list->candidates() > 0;
    accumulate_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
        view(), slots ? list->pairs() : nullptr, slots ? list->slot_state() : nullptr,
        slots ? list->forces() : nullptr, slots ? list->sorted_slot() : nullptr,
        slots ? list->entry_begin() : nullptr, slots ? list->entry_end() : nullptr,
        walls ? walls->contacts() : nullptr, walls ? walls->slots() : nullptr,
        walls ? walls->walls() : 0, shared.abort);
    TALUS_CUDA_LAUNCH_CHECK();
  }

  void wall_stage(Real spring_dt) {
    const OwnParticlesOnly<Real> own(shared);  // a ghost's walls are its owner's
    if (count() > 0) {
      walls->compute(spring_dt, time);
    } else {
      walls->import_histories({}, {});  // ghosts only: no wall history is this rank's
    }
  }

  // ---- The walls beside the pairs ----
  // The wall stage reads the particles' poses and velocities and writes only its own records;
  // the pair stage likewise its slots (or, under atomics, the particles' forces, which the wall
  // stage does not touch): neither waits for the other, and only the accumulation, which adds
  // the wall records to the forces, needs both. In a
  // small scene each is a few latency-bound kernels on a mostly idle GPU (a 4,651-pellet fixed
  // bed: about 0.55 ms each a step on an H200), so the wall stage runs on a stream of its own,
  // forked from the step's stream before the pair stage and joined after it: in a graph step
  // the two run side by side. A step launched stage by stage waits for each stage's counts on
  // the host, so there they mostly still take turns. TALUS_WALLS_BESIDE_PAIRS=0 in the
  // environment: the wall stage after the pair stage on the step's stream (to measure the gain).
  cudaStream_t walls_stream = nullptr;
  cudaEvent_t walls_fork = nullptr, walls_join = nullptr;
  static bool walls_beside_allowed() {
    static const bool on = [] {
      const char* v = std::getenv("TALUS_WALLS_BESIDE_PAIRS");
      return v == nullptr || std::string(v) != "0";
    }();
    return on;
  }
  void create_walls_stream() {
    if (!walls || !plan.contacts || !walls_beside_allowed()) return;
    TALUS_CUDA_CHECK(cudaStreamCreate(&walls_stream));
    TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&walls_fork, cudaEventDisableTiming));
    TALUS_CUDA_CHECK(cudaEventCreateWithFlags(&walls_join, cudaEventDisableTiming));
  }
  // The wall stage enqueued on walls_stream after what the step's stream holds so far (the
  // wall stage uses shared.stream for all its work, so shared.stream is that stream meanwhile;
  // its CUB scratch is its own, DeviceWallStage::temp_), its end recorded in walls_join.
  void enqueue_walls_beside(Real spring_dt) {
    const cudaStream_t step_stream = shared.stream;
    TALUS_CUDA_CHECK(cudaEventRecord(walls_fork, step_stream));
    TALUS_CUDA_CHECK(cudaStreamWaitEvent(walls_stream, walls_fork, 0));
    shared.stream = walls_stream;
    try {
      timed(Stage::wall_contacts, [&] { wall_stage(spring_dt); });
    } catch (...) {
      shared.stream = step_stream;
      throw;
    }
    shared.stream = step_stream;
    TALUS_CUDA_CHECK(cudaEventRecord(walls_join, walls_stream));
  }

  void run_force_stages(Real spring_dt, ForcePart part = ForcePart::whole) {
    const bool inner = part != ForcePart::outer, outer = part != ForcePart::inner;
    if (count() == 0) {
      if (!outer) return;
      // Decomposed, a rank that holds no particle now keeps no history of those it held.
      if (decomposition && list) list->forget_histories();
      if (decomposition && walls) walls->import_histories({}, {});
      return;
    }
    const BodyProperties<Real>* b = bodies.data();
    const cudaStream_t stream = shared.stream;
    const bool walls_beside = outer && walls && plan.contacts && walls_stream != nullptr;
    for (const Stage stage : plan.stages) {
      switch (stage) {
        case Stage::clear_forces:
          if (!inner) break;
          timed(stage, [&] {
            const OwnParticlesOnly<Real> own(shared);
            if (count() == 0) return;
            clear_forces_kernel<<<blocks_for(count()), kBlock, 0, stream>>>(view());
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::gravity:
          if (!inner) break;
          timed(stage, [&] {
            const OwnParticlesOnly<Real> own(shared);
            if (count() == 0) return;
            const Vec3<Real> g(*scene.effects.gravity);
            gravity_kernel<<<blocks_for(count()), kBlock, 0, stream>>>(view(), b, g);
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::drag:
          if (!inner) break;
          timed(stage, [&] {
            const OwnParticlesOnly<Real> own(shared);
            if (count() == 0) return;
            drag_kernel<<<blocks_for(count()), kBlock, 0, stream>>>(
                view(), Real(*scene.effects.drag_alpha));
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::candidate_pairs:
          // A graph step keeps the list: the step before predicted that no particle reaches
          // the rebuild distance in it (DevicePairList::keeps).
          if (shared.graph_mode || !inner) break;
          timed(stage, [&] {
            // Decomposed, the exchange renumbers the own particles (the ghosts follow them).
            if (!decomposition && scene.reorder.value_or(true) && list->due() &&
                list->renumber_due())
              reorder_by_cell();
            list->update();
          });
          break;
        case Stage::pair_contacts:
          if (walls_beside) enqueue_walls_beside(spring_dt);
          timed(stage, [&] {
            const int inner_slots = list->inner_candidates();
            if (part == ForcePart::whole) {
              pairs->compute(spring_dt);
            } else if (part == ForcePart::inner) {
              pairs->compute(spring_dt, 0, inner_slots, false);
            } else {
              pairs->compute(spring_dt, inner_slots, list->candidates() - inner_slots, true);
            }
          });
          // The step's stream goes on once the walls' stream is done too.
          if (walls_beside) TALUS_CUDA_CHECK(cudaStreamWaitEvent(stream, walls_join, 0));
          break;
        case Stage::wall_contacts:
          if (!outer || walls_beside) break;
          timed(stage, [&] { wall_stage(spring_dt); });
          break;
        case Stage::accumulate:
          if (!outer) break;
          timed(stage, [&] { accumulate(); });
          break;
        case Stage::integrate_begin:
        case Stage::integrate_end:
          break;
      }
    }
  }
};

}  // namespace talus
