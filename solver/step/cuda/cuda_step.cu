// The production step on the CUDA backend (see cuda_step.hpp): its set-up from a scene, the
// feeds, the per-particle stages and the accumulation (their kernels in
// cuda_particle_kernels.cuh), and the order of the stages.
// The particle arrays, the pair list, the pair contacts and the wall contacts are parts of their
// own (cuda_particles.cuh, cuda_pair_list.cuh, cuda_pair_stage.cuh, cuda_wall_stage.cuh) over the
// state they share (DeviceStepShared, cuda_step_common.cuh).
#include "solver/step/cuda/cuda_step.hpp"

#include <cub/cub.cuh>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/core/cub_call.cuh"
#include "solver/geometry/device_shape.cuh"
#include "solver/scene/feeder.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/step/cuda/cuda_pair_stage.cuh"
#include "solver/step/cuda/cuda_particle_kernels.cuh"
#include "solver/step/cuda/cuda_particles.cuh"
#include "solver/step/cuda/cuda_wall_stage.cuh"
#include "solver/step/cuda/stage_timer.cuh"
#include "solver/step/feeding.hpp"
#include "solver/step/host/host_step.hpp"
#include "solver/step/particle_kernels.hpp"

namespace talus {

namespace {

// Which regions of the constant bank's template share (template_table.hpp) CudaStep instances
// hold, so that two steps alive at once never read each other's templates.
std::mutex region_mutex;
std::array<bool, kTemplateRegions> region_in_use{};

int claim_template_region() {
  const std::lock_guard<std::mutex> lock(region_mutex);
  for (int r = 0; r < kTemplateRegions; ++r) {
    if (!region_in_use[r]) {
      region_in_use[r] = true;
      return r;
    }
  }
  return -1;
}

void release_template_region(int r) {
  if (r < 0) return;
  const std::lock_guard<std::mutex> lock(region_mutex);
  region_in_use[r] = false;
}

// The host law tables copied into one device buffer `storage`, in the same layout; the returned
// tables point into it and at the device template views `device_bodies`.
template <class Real>
PairLawTables<Real> upload_law_tables(const PairLawTables<Real>& h,
                                      const BodyProperties<Real>* device_bodies,
                                      DeviceBuffer<Real>& storage) {
  const int materials = h.materials, pairs = materials * materials;
  std::vector<Real> values;
  values.insert(values.end(), h.youngs_modulus, h.youngs_modulus + materials);
  values.insert(values.end(), h.poisson_ratio, h.poisson_ratio + materials);
  values.insert(values.end(), h.pair_friction, h.pair_friction + pairs);
  values.insert(values.end(), h.pair_restitution, h.pair_restitution + pairs);
  values.insert(values.end(), h.pair_damping_ratio, h.pair_damping_ratio + pairs);
  storage.upload(values);
  PairLawTables<Real> d = h;
  const Real* base = storage.data();
  d.bodies = device_bodies;
  d.youngs_modulus = base;
  d.poisson_ratio = base + materials;
  d.pair_friction = base + 2 * materials;
  d.pair_restitution = base + 2 * materials + pairs;
  d.pair_damping_ratio = base + 2 * materials + 2 * pairs;
  return d;
}

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
constexpr int kGraphParticles = 1 << 17;

bool graphs_allowed_by_environment() {
  const char* v = std::getenv("TALUS_CUDA_GRAPHS");
  return v == nullptr || std::string(v) != "0";
}

}  // namespace

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

  std::unique_ptr<Domain> domain;  // the local domain (domain/domain.hpp)
  // Renumbering and removal: the kept particles' order, flags and removed energies.
  DeviceBuffer<int> order, index;
  DeviceBuffer<unsigned char> keep_flags;
  DeviceBuffer<double> removed_energy, removed_sum;
  long long removed = 0;

  StageSeconds stage_seconds{};
  // Graph steps ("Graph steps" below).
  CudaStepOptions options;
  StepReport* report = nullptr;                // pinned
  DeviceBuffer<unsigned long long> predicted;  // the report's predicted move, on the device
  cudaGraphExec_t graph = nullptr;
  bool graphs_on = true;  // the option, the environment and no failed capture
  bool recapture = true;  // a step ran stage by stage since the graph was captured
  CudaGraphCounts graph_counts;
  double time = 0;
  long long steps = 0;
  bool forces_ready = false;
  EnergyLedger ledger;
  std::array<double, kEnergySums> energy_sums{};  // the last evaluation's

  // The force stages with the energy sums around them (when asked for): the contacts' sums
  // zeroed before and added up after; they reach the report at the end of the step.
  void run_force_stages_with_energy(Real spring_dt) {
    const bool track = shared.energy_sums.size() > 0;
    if (track) {
      TALUS_CUDA_CHECK(cudaMemsetAsync(shared.energy_sums.data(), 0, sizeof(double) * kEnergySums,
                                       shared.stream));
    }
    run_force_stages(spring_dt);
    if (track && walls) walls->add_energy_sums(shared.energy_sums.data());
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
  ~Impl() {
    if (graph) cudaGraphExecDestroy(graph);  // no throw from a destructor
    if (report) cudaFreeHost(report);
    if (shared.stream) cudaStreamDestroy(shared.stream);
    release_template_region(shared.constant_region);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  int count() const { return shared.count; }
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
    if (!graphs_on || count() == 0 || count() > kGraphParticles) return false;
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
    bool updated = false;
    if (graph) {
      cudaGraphExecUpdateResultInfo info;
      updated = cudaGraphExecUpdate(graph, captured, &info) == cudaSuccess;
      if (!updated) {
        cudaGetLastError();  // not sticky: a new executable graph instead
        TALUS_CUDA_CHECK(cudaGraphExecDestroy(graph));
        graph = nullptr;
      }
    }
    cudaError_t made = cudaSuccess;
    if (!updated) made = cudaGraphInstantiate(&graph, captured, 0);
    cudaGraphDestroy(captured);
    TALUS_CUDA_CHECK(made);
    return true;
  }

  // The step's work after the feeds, in order, on the step's stream: everything a graph holds.
  void enqueue_step() {
    shared.abort = AbortCheck{};
    shared.flags.reset(shared.stream);
    if (count() > 0) {
      timed(Stage::integrate_begin, [&] {
        integrate_begin_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
            view(), bodies.data(), dt, shared.flags.data());
        TALUS_CUDA_LAUNCH_CHECK();
      });
    }
    run_force_stages_with_energy(dt);
    finish_enqueue();
  }

  // The end of a step's work: integrate_end, the list's predicted move, the particles outside.
  void finish_enqueue() {
    if (count() > 0) {
      timed(Stage::integrate_end, [&] {
        integrate_end_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
            view(), bodies.data(), dt, shared.abort);
        TALUS_CUDA_LAUNCH_CHECK();
      });
    }
    if (list) {
      predicted.grow_to(1);
      list->predict_move(bodies.data(), dt, predicted.data(), shared.abort, shared.stream);
    }
    flag_outside();
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
    if (list) {
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
    finish_enqueue_after_abort();
    TALUS_CUDA_CHECK(cudaStreamSynchronize(shared.stream));
    recapture = true;
  }
  // As finish_enqueue, without flagging the particles outside again (the graph did; positions
  // do not change after integrate_begin).
  void finish_enqueue_after_abort() {
    if (count() > 0) {
      timed(Stage::integrate_end, [&] {
        integrate_end_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
            view(), bodies.data(), dt, shared.abort);
        TALUS_CUDA_LAUNCH_CHECK();
      });
    }
    if (list) list->predict_move(bodies.data(), dt, predicted.data(), shared.abort, shared.stream);
    copy_report();
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
    const int failed = all[failed_rotation];
    if (failed != INT_MAX) {
      throw std::runtime_error(
          scene.file + ": particle " + std::to_string(shared.global_id(failed)) +
          " spins too fast for time.step (the implicit-midpoint rotation did not converge)");
    }
    if (pairs) pairs->check_flags(all);
    collect_stage_times();
  }

  void accumulate() {
    const bool slots = scene.deterministic && list && list->candidates() > 0;
    accumulate_kernel<<<blocks_for(count()), kBlock, 0, shared.stream>>>(
        view(), slots ? list->pairs() : nullptr, slots ? list->slot_state() : nullptr,
        slots ? list->forces() : nullptr, slots ? list->sorted_slot() : nullptr,
        slots ? list->entry_begin() : nullptr, slots ? list->entry_end() : nullptr,
        walls ? walls->contacts() : nullptr, walls ? walls->slots() : nullptr,
        walls ? walls->walls() : 0, shared.abort);
    TALUS_CUDA_LAUNCH_CHECK();
  }

  void run_force_stages(Real spring_dt) {
    if (count() == 0) return;
    const BodyProperties<Real>* b = bodies.data();
    const int blocks = blocks_for(count());
    const cudaStream_t stream = shared.stream;
    for (const Stage stage : plan.stages) {
      switch (stage) {
        case Stage::clear_forces:
          timed(stage, [&] {
            clear_forces_kernel<<<blocks, kBlock, 0, stream>>>(view());
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::gravity:
          timed(stage, [&] {
            const Vec3<Real> g(*scene.effects.gravity);
            gravity_kernel<<<blocks, kBlock, 0, stream>>>(view(), b, g);
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::drag:
          timed(stage, [&] {
            drag_kernel<<<blocks, kBlock, 0, stream>>>(view(), Real(*scene.effects.drag_alpha));
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::candidate_pairs:
          // A graph step keeps the list: the step before predicted that no particle reaches
          // the rebuild distance in it (DevicePairList::keeps).
          if (shared.graph_mode) break;
          timed(stage, [&] {
            if (scene.reorder.value_or(true) && list->due() && list->renumber_due())
              reorder_by_cell();
            list->update();
          });
          break;
        case Stage::pair_contacts:
          timed(stage, [&] { pairs->compute(spring_dt); });
          break;
        case Stage::wall_contacts:
          timed(stage, [&] { walls->compute(spring_dt, time); });
          break;
        case Stage::accumulate:
          timed(stage, [&] { accumulate(); });
          break;
        case Stage::integrate_begin:
        case Stage::integrate_end:
          break;
      }
    }
  }
};

// The templates' shapes on the device, their properties in a constant-memory region when one is
// free and they fit (else in global memory only).
template <class Real>
void CudaStep<Real>::Impl::upload_templates(const CudaStepOptions& options) {
  std::vector<BodyProperties<Real>>& device_bodies = shared.device_bodies;
  device_bodies = host_bodies;
  for (std::size_t k = 0; k < device_bodies.size(); ++k) {
    device_shapes.push_back(nullptr);
    if (host_shapes[k]) {
      device_shapes.back() = std::make_unique<DeviceShape<Real>>(host_bodies[k].shape);
      device_bodies[k].shape = device_shapes.back()->view;
    }
  }
  bodies.upload(device_bodies);
  // A region is claimed here and filled by the stages that read it (fill_template_region).
  if (options.constant_templates &&
      device_bodies.size() <= static_cast<std::size_t>(templates_per_region<Real>())) {
    shared.constant_region = claim_template_region();
  }
}

// As HostStep::feed, through the same Feeding with the same inputs (the positions in double); the
// positions are downloaded only at a step where some feed has a particle due. The inserted
// particles are appended with their body forces, and the pair list is rebuilt at the next
// evaluation (the new particles have no candidates yet).
template <class Real>
void CudaStep<Real>::Impl::feed() {
  if (!feeding.due(time)) return;
  const std::vector<ParticleState> added =
      feeding.insert(time, particles->positions(), particles->template_ids(), *domain);
  if (added.empty()) return;
  // The energy the new particles bring (the energy probe's `fed`), from their states in double.
  const Vec3d* gravity = scene.effects.gravity ? &*scene.effects.gravity : nullptr;
  for (const ParticleState& p : added) {
    const BodyProperties<Real>& body = host_bodies[p.template_index];
    ledger.fed += 0.5 * double(body.mass) * norm2(p.velocity);
    if (plan.rotation) {
      const Vec3d w = rotate_inverse(p.orientation, p.angular_velocity);  // body frame
      const Vec3d inertia(body.inertia);
      ledger.fed += 0.5 * (inertia.x * w.x * w.x + inertia.y * w.y * w.y + inertia.z * w.z * w.z);
    }
    if (gravity) ledger.fed -= double(body.mass) * dot(*gravity, p.position);
  }
  particles->append(added, host_bodies, true);
  if (list) list->particles_changed();
  recapture = true;
}

// As HostStep::remove_outside, in two parts. flag_outside (on the step's stream, part of its
// work): one pass flags the particles outside the domain box, counted in flag
// outside_particles. remove_outside (after the step's report says some are): their energies
// summed (CUB, in a fixed order), the kept ones selected in order, the touching histories kept
// by global ids and the particles gathered.
template <class Real>
void CudaStep<Real>::Impl::flag_outside() {
  const int n = count();
  if (n == 0 || !scene.domain) return;
  const Box box = domain->local_box();
  keep_flags.grow_to(n), removed_energy.grow_to(n), index.grow_to(n), order.grow_to(n);
  const Vec3d g = scene.effects.gravity ? *scene.effects.gravity : Vec3d();
  outside_kernel<<<blocks_for(n), kBlock, 0, shared.stream>>>(
      view(), bodies.data(), box.min, box.max, g, scene.effects.gravity.has_value(),
      keep_flags.data(), removed_energy.data(), index.data(), shared.flags.at(outside_particles));
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
void CudaStep<Real>::Impl::remove_outside(int outside) {
  const int n = count();
  if (outside == 0 || n == 0) return;
  removed_sum.grow_to(1);
  cub_call(shared.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceReduce::Sum(t, b, removed_energy.data(), removed_sum.data(), n);
  });
  ledger.removed += download(removed_sum.data(), 1)[0];
  cub_call(shared.temp, [&](void* t, std::size_t& b) {
    return cub::DeviceSelect::Flagged(t, b, index.data(), keep_flags.data(), order.data(),
                                      shared.flags.at(selected), n);
  });
  if (list) list->keep_histories();
  particles->keep(order.data(), n - outside);
  if (list) list->particles_changed();
  removed += outside;
  recapture = true;
}

// The law tables on the device, the pair list with the scene's skin and the pair stage.
template <class Real>
void CudaStep<Real>::Impl::set_up_pairs(const PairLawTables<Real>& host_tables) {
  shared.tables = upload_law_tables(host_tables, bodies.data(), table_values);
  shared.tables.bodies.constant_region = shared.constant_region;
  double largest_radius = 0;
  for (const BodyProperties<Real>& b : host_bodies)
    largest_radius = std::max(largest_radius, double(b.bounding_radius));
  const Real skin = Real(scene.skin ? *scene.skin : 0.2 * largest_radius);  // 0.1 diameter
  list = std::make_unique<DevicePairList<Real>>(shared, skin);
  pairs = std::make_unique<DevicePairStage<Real>>(shared, *list, host_bodies);
}

template <class Real>
CudaStep<Real>::CudaStep(const Scene& scene, CudaStepOptions options)
    : impl_(std::make_unique<Impl>(scene)) {
  Impl& m = *impl_;
  m.options = options;
  m.graphs_on = options.graphs && graphs_allowed_by_environment() && !cuda_sync_after_launch();
  for (const ParticleTemplate& t : scene.templates) {
    m.host_shapes.push_back(t.kind == ParticleShapeKind::polyhedron
                                ? std::make_unique<ShapeArrays<Real>>(t.shape)
                                : nullptr);
    m.host_bodies.push_back(body_properties(scene, t, m.host_shapes.back().get()));
  }
  // The scene's checks first (StepNotSupported), as the host step makes them.
  std::unique_ptr<PairContactStage<Real>> host_pairs;
  std::unique_ptr<WallContactStage<Real>> host_walls;
  if (m.plan.contacts) host_pairs = std::make_unique<PairContactStage<Real>>(scene, m.host_bodies);
  if (m.plan.walls) {
    host_walls =
        std::make_unique<WallContactStage<Real>>(scene, m.host_bodies, 1, options.wall_search);
  }
  m.upload_templates(options);
  m.shared.gjk_filter = options.gjk_filter;
  // The energy sums cost a few atomics per contact: only for the energy probe, and for the work
  // of moving walls, which the run's watchdog needs (production_run.cpp).
  bool energy_probe = false;
  if (scene.outputs.probes)
    for (const Probe probe : scene.outputs.probes->quantities)
      energy_probe = energy_probe || probe == Probe::energy;
  if (m.plan.contacts && (energy_probe || scene.effects.moving_walls))
    m.shared.energy_sums.grow_to(kEnergySums);
  m.shared.flags.allocate();
  TALUS_CUDA_CHECK(cudaStreamCreate(&m.shared.stream));
  TALUS_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&m.report), sizeof(StepReport)));
  std::memset(m.report, 0, sizeof(StepReport));
  m.report->predicted_move = ~0ULL;  // NaN's bits: no graph step before a prediction
  m.particles = std::make_unique<DeviceParticles<Real>>(m.shared, m.plan);
  m.particles->append(initial_particles(scene), m.host_bodies, false);
  if (host_pairs) m.set_up_pairs(host_pairs->tables());
  if (host_walls) {
    m.walls = std::make_unique<DeviceWallStage<Real>>(m.shared, std::move(host_walls), m.time);
  }
}

template <class Real>
CudaStep<Real>::~CudaStep() = default;

template <class Real>
void CudaStep<Real>::evaluate_forces() {
  Impl& m = *impl_;
  m.shared.abort = AbortCheck{};
  m.shared.flags.reset(m.shared.stream);
  m.run_force_stages_with_energy(Real(0));
  if (m.list) {  // for the first step's graph_due
    m.predicted.grow_to(1);
    m.list->predict_move(m.bodies.data(), m.dt, m.predicted.data(), AbortCheck{}, m.shared.stream);
  }
  m.copy_report();
  m.report_and_wait();
  m.check_flags(m.report_flags());
  m.take_energy(true);
  m.forces_ready = true;
  m.recapture = true;
}

template <class Real>
void CudaStep<Real>::step() {
  Impl& m = *impl_;
  if (!m.forces_ready) evaluate_forces();  // F_0, T_0 for the first half-step
  if (m.walls) m.walls->open_outlets(m.time);
  if (!m.feeding.empty()) m.feed();
  m.time += m.scene.time_step;
  ++m.steps;
  const bool graph = m.graph_due() && m.launch_graph();
  if (!graph) {
    m.enqueue_step();
    m.recapture = true;
  }
  m.report_and_wait();
  std::array<int, flags> all = m.report_flags();
  if (graph) {
    ++m.graph_counts.steps;
    m.stage_timer.collect_graph(m.stage_seconds);
    if (m.walls && all[wall_candidates] > m.walls->clip_capacity()) {
      m.finish_aborted_step(all[wall_candidates]);
      all = m.report_flags();
    } else if (m.walls) {
      m.walls->after_graph(all);
    }
  }
  m.check_flags(all);
  m.take_energy(false);
  m.remove_outside(all[outside_particles]);
}

template <class Real>
StepState<Real> CudaStep<Real>::export_state() const {
  const Impl& m = *impl_;
  StepState<Real> s;
  s.time = m.time;
  s.steps = m.steps;
  s.forces_ready = m.forces_ready;
  m.particles->export_to(s);
  s.next_id = m.particles->next_id();
  s.removed = m.removed;
  if (m.list) m.list->export_histories(s.pair_keys, s.pair_histories);
  if (m.list) m.list->export_reference(s.list_reference, s.list_stale);
  if (m.walls) m.walls->export_histories(s.wall_keys, s.wall_histories);
  s.feed_states = m.feeding.save();
  s.ledger = m.ledger;
  return s;
}

template <class Real>
void CudaStep<Real>::import_state(const StepState<Real>& s) {
  Impl& m = *impl_;
  m.feeding.restore(s.feed_states, s.source);  // first: it refuses a checkpoint of other feeds
  // A feeding run's particles: the initial ones and those inserted by the checkpoint's step; a
  // run with a domain box: less those removed.
  const bool resized =
      (!m.feeding.empty() && s.count > m.count()) || (m.scene.domain && s.count < m.count());
  if (resized) m.particles->resize(s.count);
  check_state_fits(s, m.scene, m.count(), m.particles->names());
  m.particles->import_from(s);
  m.particles->set_next_id(s.next_id >= 0 ? s.next_id : s.count);
  m.removed = s.removed;
  if (m.list && resized) m.list->particles_changed();
  if (m.list) m.list->import_histories(s.pair_keys, s.pair_histories);
  if (m.list) m.list->import_reference(s.list_reference, s.list_stale);
  if (m.walls) m.walls->import_histories(s.wall_keys, s.wall_histories);
  m.time = s.time;
  m.steps = s.steps;
  m.forces_ready = s.forces_ready;
  m.ledger = s.ledger;
  m.report->predicted_move = ~0ULL;  // measured again by the next step
  m.recapture = true;
}

template <class Real>
double CudaStep<Real>::time() const {
  return impl_->time;
}
template <class Real>
long long CudaStep<Real>::steps() const {
  return impl_->steps;
}
template <class Real>
const StepPlan& CudaStep<Real>::plan() const {
  return impl_->plan;
}
template <class Real>
int CudaStep<Real>::particle_count() const {
  return impl_->count();
}
template <class Real>
const Domain& CudaStep<Real>::domain() const {
  return *impl_->domain;
}
template <class Real>
long long CudaStep<Real>::removed_count() const {
  return impl_->removed;
}
template <class Real>
const StageSeconds& CudaStep<Real>::stage_seconds() const {
  impl_->collect_stage_times();  // none left after a step; a caller between stages may see some
  return impl_->stage_seconds;
}
template <class Real>
std::size_t CudaStep<Real>::pair_contact_count() const {
  return impl_->pairs ? static_cast<std::size_t>(impl_->pairs->touching_count()) : 0;
}

template <class Real>
CudaGraphCounts CudaStep<Real>::graph_counts() const {
  return impl_->graph_counts;
}

template <class Real>
long long CudaStep<Real>::pair_list_builds() const {
  return impl_->list ? impl_->list->builds() : 0;
}

template <class Real>
std::size_t CudaStep<Real>::candidate_pair_count() const {
  return impl_->list ? static_cast<std::size_t>(impl_->list->candidates()) : 0;
}
template <class Real>
std::size_t CudaStep<Real>::wall_contact_count() const {
  return impl_->walls ? impl_->walls->contact_count() : 0;
}

template <class Real>
std::vector<std::string> CudaStep<Real>::allocated_arrays() const {
  std::vector<std::string> names = impl_->particles->names();
  names.insert(names.end(), {"template_id", "material_id", "global_id"});
  return names;
}

template <class Real>
std::size_t CudaStep<Real>::allocated_bytes() const {
  const Impl& m = *impl_;
  std::size_t bytes = m.particles->bytes();
  bytes += pair_list_bytes() + m.shared.temp.size();
  if (m.walls) bytes += m.walls->bytes();
  return bytes;
}

template <class Real>
bool CudaStep<Real>::templates_in_constant_memory() const {
  return impl_->shared.constant_region >= 0;
}

template <class Real>
std::size_t CudaStep<Real>::pair_list_bytes() const {
  const Impl& m = *impl_;
  return (m.list ? m.list->bytes() : 0) + (m.pairs ? m.pairs->bytes() : 0);
}

template <class Real>
Vec3d CudaStep<Real>::wall_force(int w) const {
  if (!impl_->walls) throw std::out_of_range("CudaStep::wall_force: the scene has no walls");
  return impl_->walls->force(w);
}

template <class Real>
Vec3d CudaStep<Real>::wall_torque(int w) const {
  if (!impl_->walls) throw std::out_of_range("CudaStep::wall_torque: the scene has no walls");
  return impl_->walls->torque(w);
}

template <class Real>
std::vector<TrajectoryRow> CudaStep<Real>::trajectory_rows() const {
  return particle_rows(impl_->particles->host_copy().view);
}

template <class Real>
double CudaStep<Real>::kinetic_energy() const {
  return particle_kinetic_energy(impl_->particles->host_copy().view, impl_->host_bodies);
}

template <class Real>
EnergyTerms CudaStep<Real>::energy() const {
  const Impl& m = *impl_;
  EnergyTerms terms;
  particle_energies(m.particles->host_copy().view, m.host_bodies,
                    m.scene.effects.gravity ? &*m.scene.effects.gravity : nullptr, terms);
  terms.elastic_normal = m.energy_sums[sum_normal];
  terms.elastic_tangential = m.energy_sums[sum_tangential];
  terms.ledger = m.ledger;
  return terms;
}

template <class Real>
double CudaStep<Real>::bed_height(const Vec3d& gravity) const {
  return particle_bed_height(impl_->particles->host_copy().view, impl_->host_bodies, gravity);
}

std::unique_ptr<AnyStep> make_cuda_step(const Scene& scene) {
  if (scene.precision == Precision::float32) {
    return std::make_unique<StepAdapter<CudaStep<float>>>(scene, "cuda");
  }
  return std::make_unique<StepAdapter<CudaStep<double>>>(scene, "cuda");
}

template class CudaStep<double>;
template class CudaStep<float>;

}  // namespace talus
