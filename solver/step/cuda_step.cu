// The production step on the CUDA backend (see cuda_step.hpp): the device particle state and its
// set-up from a scene, the per-particle stages and the accumulation (their kernels in
// cuda_particle_kernels.cuh), and the order of the stages.
// The pair list, the pair contacts and the wall contacts are parts of their own
// (cuda_pair_list.cuh, cuda_pair_stage.cuh, cuda_wall_stage.cuh) over the state they share
// (DeviceStepShared, cuda_step_common.cuh).
#include "solver/step/cuda_step.hpp"

#include <algorithm>
#include <array>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/geometry/device_shape.cuh"
#include "solver/scene/initial_particles.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "solver/step/cuda_pair_stage.cuh"
#include "solver/step/cuda_particle_kernels.cuh"
#include "solver/step/cuda_wall_stage.cuh"
#include "solver/step/host_step.hpp"
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
  std::vector<std::pair<std::string, DeviceBuffer<Real>>> storage;
  DeviceBuffer<int> template_ids, material_ids;
  DeviceBuffer<Real> table_values;  // the pair-law tables' numbers
  // The stages the plan names (null when absent).
  std::unique_ptr<DevicePairList<Real>> list;
  std::unique_ptr<DevicePairStage<Real>> pairs;
  std::unique_ptr<DeviceWallStage<Real>> walls;

  std::array<double, 9> stage_seconds{};
  double time = 0;
  long long steps = 0;
  bool forces_ready = false;

  explicit Impl(const Scene& s) : plan(plan_step(s)), dt(Real(s.time_step)), shared(s), scene(s) {}
  ~Impl() { release_template_region(shared.constant_region); }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  int count() const { return shared.count; }
  ParticleView<Real>& view() { return shared.view; }

  Real* allocate(const std::string& name) {
    storage.emplace_back(name, DeviceBuffer<Real>(count()));
    Real* data = storage.back().second.data();
    if (count() > 0) TALUS_CUDA_CHECK(cudaMemset(data, 0, count() * sizeof(Real)));
    return data;
  }

  void upload_templates(const CudaStepOptions& options);
  void upload_particles();
  void set_up_pairs(const PairLawTables<Real>& host_tables);

  template <class Body>
  void timed(Stage stage, Body&& body) {
    const double start = clock_seconds();
    body();
    TALUS_CUDA_CHECK(cudaDeviceSynchronize());
    stage_seconds[static_cast<int>(stage)] += clock_seconds() - start;
  }

  void accumulate() {
    const bool slots = scene.deterministic && list && list->candidates() > 0;
    accumulate_kernel<<<blocks_for(count()), kBlock>>>(
        view(), slots ? list->pairs() : nullptr, slots ? list->slot_state() : nullptr,
        slots ? list->forces() : nullptr, slots ? list->sorted_slot() : nullptr,
        slots ? list->entry_begin() : nullptr, slots ? list->entry_end() : nullptr,
        walls ? walls->contacts() : nullptr, walls ? walls->slots() : nullptr,
        walls ? walls->walls() : 0);
    TALUS_CUDA_LAUNCH_CHECK();
  }

  void run_force_stages(Real spring_dt) {
    if (count() == 0) return;
    const BodyProperties<Real>* b = bodies.data();
    const int blocks = blocks_for(count());
    for (const Stage stage : plan.stages) {
      switch (stage) {
        case Stage::clear_forces:
          timed(stage, [&] {
            clear_forces_kernel<<<blocks, kBlock>>>(view());
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::gravity:
          timed(stage, [&] {
            const Vec3<Real> g(*scene.effects.gravity);
            gravity_kernel<<<blocks, kBlock>>>(view(), b, g);
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::drag:
          timed(stage, [&] {
            drag_kernel<<<blocks, kBlock>>>(view(), Real(*scene.effects.drag_alpha));
            TALUS_CUDA_LAUNCH_CHECK();
          });
          break;
        case Stage::candidate_pairs:
          timed(stage, [&] { list->update(); });
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

  // The particle arrays in host memory, as a host ParticleView over the copy's vectors.
  struct HostCopy {
    std::vector<std::vector<Real>> arrays;
    std::vector<int> template_ids;
    std::vector<long long> global_ids;
    ParticleView<Real> view;
  };
  HostCopy host_copy() const {
    const int n = shared.count;
    const ParticleView<Real>& v = shared.view;
    HostCopy c;
    c.view.count = n;
    c.template_ids = download(template_ids.data(), n);
    c.global_ids = download(shared.global_ids.data(), n);
    c.view.template_id = c.template_ids.data();
    c.view.global_id = c.global_ids.data();
    c.arrays.reserve(13);
    const auto get = [&](const Real* device) {
      c.arrays.push_back(download(device, n));
      return c.arrays.back().data();
    };
    const auto get3 = [&](const Soa3<Real>& s) {
      Soa3<Real> h;
      if (s.present()) h.x = get(s.x), h.y = get(s.y), h.z = get(s.z);
      return h;
    };
    c.view.position = get3(v.position);
    c.view.velocity = get3(v.velocity);
    c.view.angular_velocity = get3(v.angular_velocity);
    c.view.orientation.w = get(v.orientation.w);
    c.view.orientation.x = get(v.orientation.x);
    c.view.orientation.y = get(v.orientation.y);
    c.view.orientation.z = get(v.orientation.z);
    return c;
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

// The particle arrays the plan needs, with the initial state made on the host as HostStep makes
// it, then uploaded array by array.
template <class Real>
void CudaStep<Real>::Impl::upload_particles() {
  const std::vector<ParticleState> initial = initial_particles(scene);
  shared.count = static_cast<int>(initial.size());
  const int n = shared.count;
  ParticleView<Real>& v = shared.view;
  v.count = n;
  const auto soa3 = [&](const std::string& name) {
    Soa3<Real> s;
    s.x = allocate(name + ".x"), s.y = allocate(name + ".y"), s.z = allocate(name + ".z");
    return s;
  };
  v.position = soa3("position");
  v.velocity = soa3("velocity");
  v.orientation.w = allocate("orientation.w");
  v.orientation.x = allocate("orientation.x");
  v.orientation.y = allocate("orientation.y");
  v.orientation.z = allocate("orientation.z");
  if (plan.arrays.force) {
    v.force = soa3("force");
    v.step_start_acceleration = soa3("step_start_acceleration");
  }
  if (plan.arrays.angular_velocity) v.angular_velocity = soa3("angular_velocity");
  if (plan.arrays.torque) {
    v.torque = soa3("torque");
    v.step_start_torque = soa3("step_start_torque");
  }
  if (plan.arrays.bounding_radius) v.bounding_radius = allocate("bounding_radius");

  std::vector<int> template_id(n), material_id(n);
  std::vector<long long> global_id(n);
  std::vector<std::vector<Real>> columns(14, std::vector<Real>(n));
  for (int i = 0; i < n; ++i) {
    const ParticleState& p = initial[i];
    const BodyProperties<Real>& body = host_bodies.at(p.template_index);
    template_id[i] = p.template_index;
    material_id[i] = body.material;
    global_id[i] = i;
    const Quatd q = p.orientation.normalized();
    const Vec3<Real> x(p.position), u(p.velocity);
    const Quat<Real> qr(q);
    // The scene gives the angular velocity in the world frame; Euler's equations want the body's.
    const Vec3<Real> w(rotate_inverse(q, p.angular_velocity));
    const Real values[14] = {x.x,  x.y,  x.z,  u.x, u.y, u.z, qr.w,
                             qr.x, qr.y, qr.z, w.x, w.y, w.z, body.bounding_radius};
    for (int c = 0; c < 14; ++c) columns[c][i] = values[c];
  }
  Real* const targets[14] = {v.position.x,         v.position.y,         v.position.z,
                             v.velocity.x,         v.velocity.y,         v.velocity.z,
                             v.orientation.w,      v.orientation.x,      v.orientation.y,
                             v.orientation.z,      v.angular_velocity.x, v.angular_velocity.y,
                             v.angular_velocity.z, v.bounding_radius};
  for (int c = 0; c < 14; ++c) {
    if (targets[c] && n > 0) {
      TALUS_CUDA_CHECK(
          cudaMemcpy(targets[c], columns[c].data(), n * sizeof(Real), cudaMemcpyHostToDevice));
    }
  }
  template_ids.upload(template_id);
  material_ids.upload(material_id);
  shared.global_ids.upload(global_id);
  v.template_id = template_ids.data();
  v.material_id = material_ids.data();
  v.global_id = shared.global_ids.data();
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
  m.shared.flags.allocate();
  m.upload_particles();
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
  m.shared.flags.reset();
  m.run_force_stages(Real(0));
  m.forces_ready = true;
}

template <class Real>
void CudaStep<Real>::step() {
  Impl& m = *impl_;
  if (!m.forces_ready) evaluate_forces();  // F_0, T_0 for the first half-step
  if (m.walls) m.walls->open_outlets(m.time);
  m.shared.flags.reset();
  if (m.count() > 0) {
    m.timed(Stage::integrate_begin, [&] {
      integrate_begin_kernel<<<blocks_for(m.count()), kBlock>>>(m.view(), m.bodies.data(), m.dt,
                                                                m.shared.flags.data());
      TALUS_CUDA_LAUNCH_CHECK();
    });
    const int failed = m.shared.flags.read(failed_rotation);
    if (failed != INT_MAX) {
      throw std::runtime_error(
          m.scene.file + ": particle " + std::to_string(m.shared.global_id(failed)) +
          " spins too fast for time.step (the implicit-midpoint rotation did not converge)");
    }
  }
  m.time += m.scene.time_step;
  ++m.steps;
  m.run_force_stages(m.dt);
  if (m.count() > 0) {
    m.timed(Stage::integrate_end, [&] {
      integrate_end_kernel<<<blocks_for(m.count()), kBlock>>>(m.view(), m.bodies.data(), m.dt);
      TALUS_CUDA_LAUNCH_CHECK();
    });
  }
}

template <class Real>
StepState<Real> CudaStep<Real>::export_state() const {
  const Impl& m = *impl_;
  const int n = m.count();
  StepState<Real> s;
  s.time = m.time;
  s.steps = m.steps;
  s.forces_ready = m.forces_ready;
  s.count = n;
  for (const auto& [name, values] : m.storage)
    s.arrays.emplace_back(name, download(values.data(), n));
  s.template_ids = download(m.template_ids.data(), n);
  s.material_ids = download(m.material_ids.data(), n);
  s.global_ids = download(m.shared.global_ids.data(), n);
  if (m.list) m.list->export_histories(s.pair_keys, s.pair_histories);
  if (m.walls) m.walls->export_histories(s.wall_keys, s.wall_histories);
  return s;
}

template <class Real>
void CudaStep<Real>::import_state(const StepState<Real>& s) {
  Impl& m = *impl_;
  const int n = m.count();
  std::vector<std::string> names;
  for (const auto& entry : m.storage) names.push_back(entry.first);
  check_state_fits(s, n, names, static_cast<int>(m.host_bodies.size()));
  for (std::size_t k = 0; k < m.storage.size() && n > 0; ++k) {
    TALUS_CUDA_CHECK(cudaMemcpy(m.storage[k].second.data(), s.arrays[k].second.data(),
                                n * sizeof(Real), cudaMemcpyHostToDevice));
  }
  // Same sizes: the buffers stay where the view points.
  m.template_ids.upload(s.template_ids);
  m.material_ids.upload(s.material_ids);
  m.shared.global_ids.upload(s.global_ids);
  if (m.list) m.list->import_histories(s.pair_keys, s.pair_histories);
  if (m.walls) m.walls->import_histories(s.wall_keys, s.wall_histories);
  m.time = s.time;
  m.steps = s.steps;
  m.forces_ready = s.forces_ready;
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
const std::array<double, 9>& CudaStep<Real>::stage_seconds() const {
  return impl_->stage_seconds;
}
template <class Real>
std::size_t CudaStep<Real>::pair_contact_count() const {
  return impl_->pairs ? static_cast<std::size_t>(impl_->pairs->touching_count()) : 0;
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
  std::vector<std::string> names;
  for (const auto& [name, values] : impl_->storage) names.push_back(name);
  names.insert(names.end(), {"template_id", "material_id", "global_id"});
  return names;
}

template <class Real>
std::size_t CudaStep<Real>::allocated_bytes() const {
  const Impl& m = *impl_;
  std::size_t bytes = m.count() * (2 * sizeof(int) + sizeof(long long));
  for (const auto& entry : m.storage) bytes += entry.second.size() * sizeof(Real);
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
  return particle_rows(impl_->host_copy().view);
}

template <class Real>
double CudaStep<Real>::kinetic_energy() const {
  return particle_kinetic_energy(impl_->host_copy().view, impl_->host_bodies);
}

template <class Real>
double CudaStep<Real>::bed_height(const Vec3d& gravity) const {
  return particle_bed_height(impl_->host_copy().view, impl_->host_bodies, gravity);
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
