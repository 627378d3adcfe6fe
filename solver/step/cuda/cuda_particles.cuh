// The CUDA step's particle arrays: the named structure of arrays the plan needs (the names and
// order of HostStep's), the template and material ids, and the global ids (kept in
// DeviceStepShared, which every stage reads). The arrays hold room for more particles than there
// are, growing by doubling with the particles kept, so that a feed's insertions reallocate
// rarely; the shared view (DeviceStepShared::view and count) always points at the current
// arrays, and whoever holds those pointers elsewhere (the broad phase) is told by the step.
// Included only from .cu files.
#pragma once

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "solver/scene/scene.hpp"
#include "solver/step/cuda/cuda_step_common.cuh"
#include "solver/step/particle_kernels.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/step/step_state.hpp"

namespace talus {

template <class Real>
class DeviceParticles {
 public:
  // The plan's arrays, with no particle yet (room for one, so that no array of the plan has a
  // null pointer: present() tells the arrays apart).
  DeviceParticles(DeviceStepShared<Real>& shared, const StepPlan& plan);

  // Appends `added` with the next global ids (= their indices), each set as HostStep sets a
  // particle (normalised orientation, body-frame angular velocity, the template's bounding
  // radius and material). `bodies`: the templates' properties (host). With `body_forces`, their
  // forces are set at once as HostStep::feed sets them (zero, then gravity and drag; torque
  // zero), for the first half-step of a particle fed between steps; every other array starts at
  // zero.
  // `ids`: their global ids instead (a decomposed step's feed numbers every rank's insertions).
  void append(const std::vector<ParticleState>& added,
              const std::vector<BodyProperties<Real>>& bodies, bool body_forces,
              const std::vector<long long>* ids = nullptr);
  // Whole particles in host memory, as a decomposed step moves them between ranks: every array's
  // value (row-major, names().size() numbers a particle) and the ids.
  struct Rows {
    int count = 0;
    std::vector<Real> values;
    std::vector<int> template_ids, material_ids;
    std::vector<long long> global_ids;
  };
  // The particles at `indices` (gathered on the device, then downloaded), and appended after
  // the present particles.
  Rows gather_rows(const std::vector<int>& indices);
  void append_rows(const Rows& rows);
  // Whole particles packed on the device, as a decomposed step sends its ghosts: `count` rows
  // (the particles at device `index`) into `out` (device, packed_bytes(count) bytes, 8-aligned):
  // the global ids, then each array's values, then the template and the material ids, each a
  // block of `count`; one kernel on `stream`. append_packed appends such a block (device) after
  // the present particles, likewise. The same values as gather_rows/append_rows without a host
  // copy per array.
  std::size_t packed_bytes(int count) const;
  void pack_rows(const int* index, int count, char* out, cudaStream_t stream) const;
  void append_packed(const char* in, int count, cudaStream_t stream);
  // `count` particles: the arrays grow (or the count shrinks), the particles' contents are left
  // for the caller to set (import_from).
  void resize(int count);
  // Keeps the particles at device_order[0 .. kept) in that order and drops the rest (a
  // renumbering by cell, a removal): every array and id gathered into a scratch array of its size
  // that is then swapped in. The arrays move: the caller tells whoever holds their pointers (the
  // pair list).
  void keep(const int* device_order, int kept);
  // The global id the next appended particle gets (ids are never reused), and setting it (a
  // restart).
  long long next_id() const { return next_id_; }
  void set_next_id(long long id) {
    next_id_ = id;
    shared_.id_bound = std::max<long long>(1, id);
  }

  // The real arrays' names (as HostStep::allocated_arrays, without the ids) and the device bytes
  // held (capacity, not count).
  std::vector<std::string> names() const;
  std::size_t bytes() const;

  // Every array and the ids downloaded into `s` (count, arrays, ids), and set from a state that
  // fits (check_state_fits with count()): copied into the arrays in place.
  // `count` >= 0: the first `count` particles only (a decomposed step's own).
  void export_to(StepState<Real>& s, int count = -1) const;
  void import_from(const StepState<Real>& s);

  // A feed's inputs: the positions in double and the template ids, downloaded.
  std::vector<Vec3d> positions() const;
  std::vector<int> template_ids() const;

  // The state the outputs read (positions, velocities, orientations, angular velocities, ids) in
  // host memory, as a host ParticleView over the copy's vectors.
  struct HostCopy {
    std::vector<std::vector<Real>> arrays;
    std::vector<int> template_ids;
    std::vector<long long> global_ids;
    ParticleView<Real> view;
  };
  HostCopy host_copy(int count = -1) const;  // count >= 0: the first `count` particles only

  int count() const { return shared_.count; }
  int capacity() const { return capacity_; }

 private:
  void allocate(const std::string& name);
  void reserve(int count);  // room for `count`, doubling; the present particles kept
  void bind();              // the shared view's pointers and count

  DeviceStepShared<Real>& shared_;
  const StepPlan& plan_;
  int capacity_ = 1;
  long long next_id_ = 0;
  std::vector<std::pair<std::string, DeviceBuffer<Real>>> storage_;
  DeviceBuffer<int> template_ids_, material_ids_;
  // keep()'s scratch, one array of each type at the capacity (allocated on the first keep, then
  // swapped with the arrays in turn).
  DeviceBuffer<Real> real_scratch_;
  DeviceBuffer<int> int_scratch_;
  DeviceBuffer<long long> id_scratch_;
  DeviceBuffer<int> row_index_;    // gather_rows' indices
  DeviceBuffer<Real> row_values_;  // gather_rows' one array
};

}  // namespace talus
