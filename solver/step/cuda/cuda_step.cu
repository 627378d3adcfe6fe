// The production step on the CUDA backend (see cuda_step.hpp): its set-up from a scene, the
// feeds, removal at the domain box, the state's export and import, and the public interface over
// its state and the order of its stages (CudaStep::Impl, cuda_step_impl.cuh).
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
#include <exception>
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
#include "solver/step/cuda/cuda_step_impl.cuh"
#include "solver/step/gathered_state.hpp"
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

// A rank of a decomposed run takes the GPU of its local rank (several ranks on one GPU share it):
// the launcher's local rank (Open MPI, MPICH, Slurm) modulo the devices.
void select_local_device() {
  int local = 0;
  for (const char* name : {"OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "SLURM_LOCALID"}) {
    if (const char* v = std::getenv(name)) {
      local = std::atoi(v);
      break;
    }
  }
  int devices = 0;
  TALUS_CUDA_CHECK(cudaGetDeviceCount(&devices));
  if (devices > 0) TALUS_CUDA_CHECK(cudaSetDevice(local % devices));
}

bool graphs_allowed_by_environment() {
  const char* v = std::getenv("TALUS_CUDA_GRAPHS");
  return v == nullptr || std::string(v) != "0";
}

}  // namespace

template <class Real>
CudaStep<Real>::Impl::~Impl() {
  if (graph) cudaGraphExecDestroy(graph);  // no throw from a destructor
  if (report) cudaFreeHost(report);
  if (shared.stream) cudaStreamDestroy(shared.stream);
  if (walls_stream) cudaStreamDestroy(walls_stream);
  if (walls_fork) cudaEventDestroy(walls_fork);
  if (walls_join) cudaEventDestroy(walls_join);
  release_template_region(shared.constant_region);
}

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
  std::vector<ParticleState> added;
  std::vector<long long> ids;
  if (decomposition) {
    // Every rank runs the feeds on every rank's particles (the same insertions, the same feed
    // states), numbers every insertion some rank owns as one process would, and keeps its own.
    std::vector<Vec3d> positions;
    std::vector<int> templates;
    const double start = clock_seconds();
    decomposition->gather_all(positions, templates);
    decomposition->add_exchange_seconds(clock_seconds() - start);
    const std::vector<ParticleState> all =
        feeding.insert_all(time, std::move(positions), templates);
    if (all.empty()) return;
    long long next = particles->next_id();
    const RcbDomain& d = decomposition->domain();
    for (const ParticleState& p : all) {
      const int owner = d.owner(p.position);
      if (owner < 0) continue;
      const long long id = next++;
      if (owner == d.rank()) added.push_back(p), ids.push_back(id);
    }
    particles->set_next_id(next);
    decomposition->drop_ghosts();
  } else {
    added = feeding.insert(time, particles->positions(), particles->template_ids(), *domain);
  }
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
  particles->append(added, host_bodies, true, decomposition ? &ids : nullptr);
  if (decomposition) shared.owned = count();
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
  const OwnParticlesOnly<Real> own(shared);  // decomposed: the own particles; the ghosts' owners
  const int n = count();
  if (n == 0 || !scene.domain) return;
  const Box box = decomposition ? decomposition->domain().region() : domain->local_box();
  grow_outside_buffers();  // a no-op in a graph's capture (capture_graph grew them before)
  const Vec3d g = scene.effects.gravity ? *scene.effects.gravity : Vec3d();
  outside_kernel<<<blocks_for(n), kBlock, 0, shared.stream>>>(
      view(), bodies.data(), box.min, box.max, g, scene.effects.gravity.has_value(),
      keep_flags.data(), removed_energy.data(), index.data(), shared.flags.at(outside_particles));
  TALUS_CUDA_LAUNCH_CHECK();
}

// The removal's per-particle buffers, room for every particle: before a graph's capture too, as
// nothing may be allocated while a stream is captured (the first capture of a scene with a
// domain box, and the first after a feed, found them short: "operation not permitted when
// stream is capturing").
template <class Real>
void CudaStep<Real>::Impl::grow_outside_buffers() {
  const int n = count();
  if (n == 0 || !scene.domain) return;
  keep_flags.grow_to(n), removed_energy.grow_to(n), index.grow_to(n), order.grow_to(n);
}

template <class Real>
void CudaStep<Real>::Impl::remove_outside(int outside) {
  const int n = own_count();  // decomposed: the ghosts are dropped with the removed
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
  if (decomposition) shared.owned = count(), decomposition->particles_changed();
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
CudaStep<Real>::CudaStep(const Scene& scene, CudaStepOptions options,
                         std::shared_ptr<const Communicator> comm)
    : impl_(std::make_unique<Impl>(scene)) {
  Impl& m = *impl_;
  const bool decomposed = comm && comm->size() > 1;
  if (decomposed) select_local_device();  // before the step's first allocation
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
  m.left_out = scene.left_out_particles;
  if (host_pairs) m.set_up_pairs(host_pairs->tables());
  if (host_walls) {
    m.walls = std::make_unique<DeviceWallStage<Real>>(m.shared, std::move(host_walls), m.time);
  }
  m.create_walls_stream();
  if (decomposed) {
    // Every rank made every initial particle (the same ids); each keeps those its box owns. A
    // decomposed step exchanges ghosts in the middle of each step: no graph steps.
    m.graphs_on = false;
    m.decomposition = std::make_unique<DeviceDecomposition<Real>>(
        m.shared, *m.particles, m.list.get(), m.walls.get(), std::move(comm));
    m.decomposition->decompose();
  }
}

// One step on several ranks: as step(), with the ghosts' exchange after integrate_begin, and a
// failure on any rank raised on every rank (agree_on_failure) before the next exchange.
template <class Real>
CudaStep<Real>::~CudaStep() = default;

template <class Real>
void CudaStep<Real>::evaluate_forces() {
  Impl& m = *impl_;
  if (m.decomposition) {
    m.decomposition->exchange(true);
    std::exception_ptr failure;
    try {
      m.shared.abort = AbortCheck{};
      m.shared.flags.reset(m.shared.stream);
      m.run_force_stages_with_energy(Real(0));
      m.copy_report();
      m.report_and_wait();
      m.check_flags(m.report_flags());
      m.take_energy(true);
    } catch (...) {
      failure = std::current_exception();
    }
    agree_on_failure(m.decomposition->comm(), failure);
    m.forces_ready = true;
    return;
  }
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
  if (m.decomposition) return m.decomposed_step();
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
  m.particles->export_to(s, m.own_count());
  s.next_id = m.particles->next_id();
  s.removed = m.removed;
  if (m.list) m.list->export_histories(s.pair_keys, s.pair_histories);
  if (m.list && !m.decomposition) m.list->export_reference(s.list_reference, s.list_stale);
  if (m.walls) m.walls->export_histories(s.wall_keys, s.wall_histories);
  s.feed_states = m.feeding.save();
  s.ledger = m.ledger;
  // Decomposed: every rank's share gathered into one process's state, on every rank.
  if (m.decomposition) return gather_step_states(m.decomposition->comm(), s);
  return s;
}

template <class Real>
void CudaStep<Real>::import_state(const StepState<Real>& s) {
  Impl& m = *impl_;
  m.feeding.restore(s.feed_states, s.source);  // first: it refuses a checkpoint of other feeds
  // Decomposed: every rank reads one process's state, then keeps its own (decompose below).
  if (m.decomposition) m.shared.owned = -1;
  // A feeding run's particles: the initial ones and those inserted by the checkpoint's step; a
  // run with a domain box: less those removed. A step built for a resume holds none of the
  // scene's initial particles (left_out, once): the checkpoint brings them.
  const long long initial = m.count() + static_cast<long long>(m.left_out);
  m.left_out = 0;
  if (!checkpoint_count_fits(s.count, initial, m.scene, !m.feeding.empty(),
                             m.decomposition != nullptr))
    check_state_fits(s, m.scene, static_cast<int>(initial), m.particles->names());  // refuses
  const bool resized = s.count != m.count();
  if (resized) m.particles->resize(s.count);
  check_state_fits(s, m.scene, m.count(), m.particles->names());
  m.particles->import_from(s);
  m.particles->set_next_id(s.next_id >= 0 ? s.next_id : s.count);
  m.removed = s.removed;
  if (m.list && resized) m.list->particles_changed();
  if (m.list) m.list->import_histories(s.pair_keys, s.pair_histories);
  if (m.list && !m.decomposition) m.list->import_reference(s.list_reference, s.list_stale);
  if (m.walls) m.walls->import_histories(s.wall_keys, s.wall_histories);
  m.time = s.time;
  m.steps = s.steps;
  m.forces_ready = s.forces_ready;
  m.ledger = s.ledger;
  m.report->predicted_move = ~0ULL;  // measured again by the next step
  m.recapture = true;
  if (m.decomposition) {
    // The totals stay with rank 0; each rank keeps the particles of its box in a bisection of
    // them (whatever the rank count that wrote the state).
    if (m.decomposition->comm().rank() != 0) m.ledger = EnergyLedger(), m.removed = 0;
    m.decomposition->decompose();
  }
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
  return impl_->own_count();
}
template <class Real>
const Domain& CudaStep<Real>::domain() const {
  return *impl_->shared.domain;
}
template <class Real>
long long CudaStep<Real>::removed_count() const {
  return impl_->removed;
}
template <class Real>
std::vector<FeedCount> CudaStep<Real>::feed_counts() const {
  return impl_->feeding.counts(impl_->time);
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
std::vector<std::pair<std::string, std::string>> CudaStep<Real>::stages_beside() const {
  if (impl_->walls_stream == nullptr) return {};
  return {{to_string(Stage::wall_contacts), to_string(Stage::pair_contacts)}};
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
std::vector<std::pair<std::string, std::size_t>> CudaStep<Real>::memory_parts() const {
  const Impl& m = *impl_;
  std::vector<std::pair<std::string, std::size_t>> parts;
  parts.emplace_back("particles", m.particles->bytes());
  if (m.list) {
    for (const auto& part : m.list->parts()) parts.emplace_back(part.first, part.second);
  }
  parts.emplace_back("overlap scratch", m.pairs ? m.pairs->bytes() : 0);
  parts.emplace_back("wall stage", m.walls ? m.walls->bytes() : 0);
  parts.emplace_back("CUB scratch", m.shared.temp.size());
  parts.emplace_back("renumbering and removal",
                     (m.order.size() + m.index.size()) * sizeof(int) + m.keep_flags.size() +
                         (m.removed_energy.size() + m.removed_sum.size()) * sizeof(double) +
                         m.predicted.size() * sizeof(unsigned long long));
  std::size_t shapes =
      m.bodies.size() * sizeof(BodyProperties<Real>) + m.table_values.size() * sizeof(Real);
  for (const auto& shape : m.device_shapes) shapes += shape ? shape->bytes() : 0;
  parts.emplace_back("shapes and law tables", shapes);
  return parts;
}

template <class Real>
std::size_t CudaStep<Real>::allocated_bytes() const {
  std::size_t bytes = 0;
  for (const auto& part : memory_parts()) bytes += part.second;
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

std::unique_ptr<AnyStep> make_cuda_step(const Scene& scene) {
  if (scene.precision == Precision::float32) {
    return std::make_unique<StepAdapter<CudaStep<float>>>(scene, "cuda");
  }
  return std::make_unique<StepAdapter<CudaStep<double>>>(scene, "cuda");
}

template class CudaStep<double>;
template class CudaStep<float>;

}  // namespace talus
