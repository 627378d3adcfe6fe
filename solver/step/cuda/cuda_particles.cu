// The CUDA step's particle arrays (cuda_particles.cuh): allocation by the plan, appending
// particles (the initial ones, then a feed's), growth, the state's download and upload.
#include "solver/step/cuda/cuda_particles.cuh"

#include <algorithm>
#include <stdexcept>

namespace talus {

namespace {

template <class T>
void upload_at(T* device, const std::vector<T>& host) {
  if (!host.empty()) {
    TALUS_CUDA_CHECK(
        cudaMemcpy(device, host.data(), host.size() * sizeof(T), cudaMemcpyHostToDevice));
  }
}

template <class T>
__global__ void gather_kernel(const T* __restrict__ from, const int* __restrict__ order, int n,
                              T* __restrict__ to) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < n) to[k] = from[order[k]];
}

// values[k] = values[order[k]] for k < n, through `scratch` (of values' size exactly, so that the
// swap leaves every array its size) swapped in.
template <class T>
void gather_in_place(DeviceBuffer<T>& values, const int* order, int n, DeviceBuffer<T>& scratch) {
  scratch.resize(values.size());
  if (n > 0) {
    gather_kernel<<<blocks_for(n), kBlock>>>(values.data(), order, n, scratch.data());
    TALUS_CUDA_LAUNCH_CHECK();
  }
  values.swap(scratch);
}

// The arrays of a packed block (DeviceParticles::pack_rows): at most kPackedArrays real arrays
// (the plan's are fewer: particle_array_names).
constexpr int kPackedArrays = 32;

template <class Real>
struct PackedColumns {
  Real* column[kPackedArrays] = {};
  int arrays = 0;
  int* template_id = nullptr;
  int* material_id = nullptr;
  long long* global_id = nullptr;
};

// A block of `count` rows: ids (8 bytes each), then `arrays` blocks of reals, then the template
// and material ids; the offsets of each part.
template <class Real>
struct PackedLayout {
  std::size_t values, templates, materials, bytes;
  __host__ __device__ PackedLayout(int count, int arrays) {
    const std::size_t n = static_cast<std::size_t>(count);
    values = n * sizeof(long long);
    templates = values + n * arrays * sizeof(Real);
    materials = templates + n * sizeof(int);
    bytes = (materials + n * sizeof(int) + 7) / 8 * 8;  // the next block 8-aligned
  }
};

template <class Real>
__global__ void pack_rows_kernel(PackedColumns<Real> c, const int* __restrict__ index, int count,
                                 char* __restrict__ out) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  const int i = index[k];
  const PackedLayout<Real> at(count, c.arrays);
  reinterpret_cast<long long*>(out)[k] = c.global_id[i];
  Real* values = reinterpret_cast<Real*>(out + at.values);
  for (int a = 0; a < c.arrays; ++a)
    values[static_cast<std::size_t>(a) * count + k] = c.column[a][i];
  reinterpret_cast<int*>(out + at.templates)[k] = c.template_id[i];
  reinterpret_cast<int*>(out + at.materials)[k] = c.material_id[i];
}

template <class Real>
__global__ void unpack_rows_kernel(PackedColumns<Real> c, const char* __restrict__ in, int count,
                                   int first) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  const int i = first + k;
  const PackedLayout<Real> at(count, c.arrays);
  c.global_id[i] = reinterpret_cast<const long long*>(in)[k];
  const Real* values = reinterpret_cast<const Real*>(in + at.values);
  for (int a = 0; a < c.arrays; ++a)
    c.column[a][i] = values[static_cast<std::size_t>(a) * count + k];
  c.template_id[i] = reinterpret_cast<const int*>(in + at.templates)[k];
  c.material_id[i] = reinterpret_cast<const int*>(in + at.materials)[k];
}

}  // namespace

template <class Real>
std::size_t DeviceParticles<Real>::packed_bytes(int count) const {
  return PackedLayout<Real>(count, static_cast<int>(storage_.size())).bytes;
}

template <class Real>
void DeviceParticles<Real>::pack_rows(const int* index, int count, char* out,
                                      cudaStream_t stream) const {
  if (count == 0) return;
  PackedColumns<Real> c;
  if (storage_.size() > static_cast<std::size_t>(kPackedArrays))
    throw std::logic_error("pack_rows: more particle arrays than kPackedArrays");
  for (const auto& entry : storage_) c.column[c.arrays++] = const_cast<Real*>(entry.second.data());
  c.template_id = const_cast<int*>(template_ids_.data());
  c.material_id = const_cast<int*>(material_ids_.data());
  c.global_id = const_cast<long long*>(shared_.global_ids.data());
  pack_rows_kernel<<<blocks_for(count), kBlock, 0, stream>>>(c, index, count, out);
  TALUS_CUDA_LAUNCH_CHECK();
}

template <class Real>
void DeviceParticles<Real>::append_packed(const char* in, int count, cudaStream_t stream) {
  if (count == 0) return;
  const int first = shared_.count;
  reserve(first + count);
  PackedColumns<Real> c;
  if (storage_.size() > static_cast<std::size_t>(kPackedArrays))
    throw std::logic_error("append_packed: more particle arrays than kPackedArrays");
  for (auto& entry : storage_) c.column[c.arrays++] = entry.second.data();
  c.template_id = template_ids_.data();
  c.material_id = material_ids_.data();
  c.global_id = shared_.global_ids.data();
  unpack_rows_kernel<<<blocks_for(count), kBlock, 0, stream>>>(c, in, count, first);
  TALUS_CUDA_LAUNCH_CHECK();
  shared_.count = first + count;
  bind();
}

template <class Real>
DeviceParticles<Real>::DeviceParticles(DeviceStepShared<Real>& shared, const StepPlan& plan)
    : shared_(shared), plan_(plan) {
  shared.count = 0;
  // HostStep's arrays in HostStep's order (the state's arrays are matched by name and order).
  for (const std::string& name : particle_array_names(plan.arrays)) allocate(name);
  template_ids_.resize(capacity_);
  material_ids_.resize(capacity_);
  shared.global_ids.resize(capacity_);
  bind();
}

template <class Real>
void DeviceParticles<Real>::allocate(const std::string& name) {
  storage_.emplace_back(name, DeviceBuffer<Real>(capacity_));
}

template <class Real>
void DeviceParticles<Real>::bind() {
  ParticleView<Real>& v = shared_.view;
  v = view_over<Real>([&](const std::string& name) -> Real* {
    for (auto& entry : storage_)
      if (entry.first == name) return entry.second.data();
    return nullptr;
  });
  v.count = shared_.count;
  v.template_id = template_ids_.data();
  v.material_id = material_ids_.data();
  v.global_id = shared_.global_ids.data();
}

template <class Real>
void DeviceParticles<Real>::reserve(int count) {
  if (count <= capacity_) return;
  capacity_ = std::max(count, 2 * capacity_);
  const std::size_t keep = shared_.count;
  for (auto& entry : storage_) entry.second.grow_keeping(capacity_, keep);
  template_ids_.grow_keeping(capacity_, keep);
  material_ids_.grow_keeping(capacity_, keep);
  shared_.global_ids.grow_keeping(capacity_, keep);
  bind();
}

template <class Real>
void DeviceParticles<Real>::resize(int count) {
  reserve(count);
  shared_.count = count;
  bind();
}

template <class Real>
void DeviceParticles<Real>::keep(const int* device_order, int kept) {
  for (auto& entry : storage_) gather_in_place(entry.second, device_order, kept, real_scratch_);
  gather_in_place(template_ids_, device_order, kept, int_scratch_);
  gather_in_place(material_ids_, device_order, kept, int_scratch_);
  gather_in_place(shared_.global_ids, device_order, kept, id_scratch_);
  shared_.count = kept;
  bind();
}

template <class Real>
void DeviceParticles<Real>::append(const std::vector<ParticleState>& added,
                                   const std::vector<BodyProperties<Real>>& bodies,
                                   bool body_forces, const std::vector<long long>* ids) {
  const int first = shared_.count, k = static_cast<int>(added.size());
  if (k == 0) return;
  reserve(first + k);
  // The new particles in host memory, every array of the plan (zero unless set below), set by
  // the host's functions on a host view over them, then uploaded after the present particles.
  std::vector<std::vector<Real>> columns(storage_.size(), std::vector<Real>(k, Real(0)));
  std::vector<int> template_id(k), material_id(k);
  std::vector<long long> global_id(k);
  ParticleView<Real> h = view_over<Real>([&](const std::string& name) -> Real* {
    for (std::size_t a = 0; a < storage_.size(); ++a)
      if (storage_[a].first == name) return columns[a].data();
    return nullptr;
  });
  h.count = k;
  h.template_id = template_id.data();
  h.material_id = material_id.data();
  h.global_id = global_id.data();
  const Effects& fx = shared_.scene.effects;
  for (int j = 0; j < k; ++j) {
    const ParticleState& p = added[j];
    const BodyProperties<Real>& body = bodies.at(p.template_index);
    template_id[j] = p.template_index;
    material_id[j] = body.material;
    global_id[j] = ids ? ids->at(j) : next_id_ + j;
    h.position.set(j, Vec3<Real>(p.position));
    h.velocity.set(j, Vec3<Real>(p.velocity));
    const Quatd q = p.orientation.normalized();
    h.orientation.set(j, Quat<Real>(q));
    // The scene gives the angular velocity in the world frame; Euler's equations want the body's.
    if (h.angular_velocity.present())
      h.angular_velocity.set(j, Vec3<Real>(rotate_inverse(q, p.angular_velocity)));
    if (h.bounding_radius) h.bounding_radius[j] = body.bounding_radius;
    if (!body_forces) continue;
    // HostStep::feed's body forces: the particle touches nothing (the feed places it clear of
    // particles and walls), so its first half-step takes gravity and drag alone.
    if (h.force.present()) {
      clear_forces(h, j);
      if (plan_.gravity) add_gravity(h, bodies.data(), j, Vec3<Real>(*fx.gravity));
      if (plan_.drag) add_drag(h, j, Real(*fx.drag_alpha));
    } else if (h.torque.present()) {
      h.torque.set(j, Vec3<Real>());
    }
  }
  for (std::size_t a = 0; a < storage_.size(); ++a)
    upload_at(storage_[a].second.data() + first, columns[a]);
  upload_at(template_ids_.data() + first, template_id);
  upload_at(material_ids_.data() + first, material_id);
  upload_at(shared_.global_ids.data() + first, global_id);
  shared_.count = first + k;
  if (!ids) set_next_id(next_id_ + k);
  bind();
}

template <class Real>
typename DeviceParticles<Real>::Rows DeviceParticles<Real>::gather_rows(
    const std::vector<int>& indices) {
  Rows rows;
  const int n = rows.count = static_cast<int>(indices.size());
  if (n == 0) return rows;
  row_index_.upload(indices);
  const std::size_t arrays = storage_.size();
  rows.values.resize(n * arrays);
  row_values_.grow_to(n);
  for (std::size_t a = 0; a < arrays; ++a) {
    gather_kernel<<<blocks_for(n), kBlock>>>(storage_[a].second.data(), row_index_.data(), n,
                                             row_values_.data());
    TALUS_CUDA_LAUNCH_CHECK();
    const std::vector<Real> column = download(row_values_.data(), n);
    for (int i = 0; i < n; ++i) rows.values[i * arrays + a] = column[i];
  }
  const auto gather_ints = [&](const DeviceBuffer<int>& from, DeviceBuffer<int>& scratch) {
    scratch.grow_to(n);
    gather_kernel<<<blocks_for(n), kBlock>>>(from.data(), row_index_.data(), n, scratch.data());
    TALUS_CUDA_LAUNCH_CHECK();
    return download(scratch.data(), n);
  };
  rows.template_ids = gather_ints(template_ids_, int_scratch_);
  rows.material_ids = gather_ints(material_ids_, int_scratch_);
  id_scratch_.grow_to(n);
  gather_kernel<<<blocks_for(n), kBlock>>>(shared_.global_ids.data(), row_index_.data(), n,
                                           id_scratch_.data());
  TALUS_CUDA_LAUNCH_CHECK();
  rows.global_ids = download(id_scratch_.data(), n);
  return rows;
}

template <class Real>
void DeviceParticles<Real>::append_rows(const Rows& rows) {
  const int first = shared_.count, n = rows.count;
  if (n == 0) return;
  reserve(first + n);
  const std::size_t arrays = storage_.size();
  std::vector<Real> column(n);
  for (std::size_t a = 0; a < arrays; ++a) {
    for (int i = 0; i < n; ++i) column[i] = rows.values[i * arrays + a];
    upload_at(storage_[a].second.data() + first, column);
  }
  upload_at(template_ids_.data() + first, rows.template_ids);
  upload_at(material_ids_.data() + first, rows.material_ids);
  upload_at(shared_.global_ids.data() + first, rows.global_ids);
  shared_.count = first + n;
  bind();
}

template <class Real>
std::vector<std::string> DeviceParticles<Real>::names() const {
  std::vector<std::string> names;
  for (const auto& entry : storage_) names.push_back(entry.first);
  return names;
}

template <class Real>
std::size_t DeviceParticles<Real>::bytes() const {
  std::size_t bytes = (template_ids_.size() + material_ids_.size()) * sizeof(int) +
                      shared_.global_ids.size() * sizeof(long long);
  for (const auto& entry : storage_) bytes += entry.second.size() * sizeof(Real);
  return bytes + real_scratch_.size() * sizeof(Real) + int_scratch_.size() * sizeof(int) +
         id_scratch_.size() * sizeof(long long);
}

template <class Real>
void DeviceParticles<Real>::export_to(StepState<Real>& s, int own) const {
  const int n = own >= 0 ? own : count();
  s.count = n;
  s.arrays.clear();
  for (const auto& [name, values] : storage_)
    s.arrays.emplace_back(name, download(values.data(), n));
  s.template_ids = download(template_ids_.data(), n);
  s.material_ids = download(material_ids_.data(), n);
  s.global_ids = download(shared_.global_ids.data(), n);
}

template <class Real>
void DeviceParticles<Real>::import_from(const StepState<Real>& s) {
  // The sizes fit (check_state_fits): the arrays stay where the view points.
  for (std::size_t a = 0; a < storage_.size(); ++a)
    upload_at(storage_[a].second.data(), s.arrays[a].second);
  upload_at(template_ids_.data(), s.template_ids);
  upload_at(material_ids_.data(), s.material_ids);
  upload_at(shared_.global_ids.data(), s.global_ids);
}

template <class Real>
std::vector<Vec3d> DeviceParticles<Real>::positions() const {
  const int n = count();
  const ParticleView<Real>& v = shared_.view;
  const std::vector<Real> x = download(v.position.x, n), y = download(v.position.y, n),
                          z = download(v.position.z, n);
  std::vector<Vec3d> positions(n);
  for (int i = 0; i < n; ++i) positions[i] = Vec3d(Vec3<Real>(x[i], y[i], z[i]));
  return positions;
}

template <class Real>
std::vector<int> DeviceParticles<Real>::template_ids() const {
  return download(template_ids_.data(), count());
}

template <class Real>
typename DeviceParticles<Real>::HostCopy DeviceParticles<Real>::host_copy(int own) const {
  const int n = own >= 0 ? own : count();
  const ParticleView<Real>& v = shared_.view;
  HostCopy c;
  c.view.count = n;
  c.template_ids = download(template_ids_.data(), n);
  c.global_ids = download(shared_.global_ids.data(), n);
  c.view.template_id = c.template_ids.data();
  c.view.global_id = c.global_ids.data();
  c.arrays.reserve(13);  // no reallocation: the view points into them
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

template class DeviceParticles<double>;
template class DeviceParticles<float>;

}  // namespace talus
