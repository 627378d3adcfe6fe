// Trajectory frames as HDF5 (trajectory.hpp): one file a frame, trajectory_<step>.h5, holding one
// dataset `particles` of N records, so that h5py or any HDF5 reader loads a frame in one call
// (`h5py.File(path)["particles"][:]`, a numpy structured array), and the attributes `step` and
// `time`. Record: id (int64), template (int32), position (3 float64: exact), orientation (4
// float32, w x y z), velocity (3 float32), angular_velocity (3 float32): 76 bytes a particle,
// 76 MB for 1e6, where a CSV frame takes about 350 MB. The file goes through a temporary name
// and a rename, as every output (output_files.hpp).
#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"
#include "solver/io/trajectory.hpp"

namespace talus {

namespace {

// The record in memory (the file's type is the same fields, packed).
struct H5Record {
  long long id;
  int template_index;
  double position[3];
  float orientation[4];
  float velocity[3];
  float angular_velocity[3];
};

// An HDF5 handle closed when it goes out of scope; `close` is H5Fclose, H5Dclose, ...
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }
  // Closes now and says whether the close succeeded (a file's close flushes it).
  bool close() {
    const herr_t status = id_ >= 0 ? close_(id_) : -1;
    id_ = -1;
    return status >= 0;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// The library prints its own error stack by default; talus throws with the path instead.
void silence_hdf5() {
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

Handle array_type(hid_t base, hsize_t n) {
  const hsize_t dims[1] = {n};
  return Handle(H5Tarray_create2(base, 1, dims), H5Tclose);
}

// The record's compound type: in memory (with the struct's padding) or packed for the file.
Handle record_type(bool packed) {
  Handle type(H5Tcreate(H5T_COMPOUND, sizeof(H5Record)), H5Tclose);
  const Handle d3 = array_type(H5T_NATIVE_DOUBLE, 3), f4 = array_type(H5T_NATIVE_FLOAT, 4),
               f3 = array_type(H5T_NATIVE_FLOAT, 3);
  H5Tinsert(type.get(), "id", HOFFSET(H5Record, id), H5T_NATIVE_LLONG);
  H5Tinsert(type.get(), "template", HOFFSET(H5Record, template_index), H5T_NATIVE_INT);
  H5Tinsert(type.get(), "position", HOFFSET(H5Record, position), d3.get());
  H5Tinsert(type.get(), "orientation", HOFFSET(H5Record, orientation), f4.get());
  H5Tinsert(type.get(), "velocity", HOFFSET(H5Record, velocity), f3.get());
  H5Tinsert(type.get(), "angular_velocity", HOFFSET(H5Record, angular_velocity), f3.get());
  if (packed) H5Tpack(type.get());
  return type;
}

void put_attribute(hid_t object, const char* name, hid_t type, const void* value) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle attribute(H5Acreate2(object, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                         H5Aclose);
  if (!attribute.ok() || H5Awrite(attribute.get(), type, value) < 0)
    throw std::runtime_error(std::string("cannot write the attribute ") + name);
}

}  // namespace

void write_trajectory_frame_hdf5(const std::string& directory, long long step, double time,
                                 const std::vector<TrajectoryRow>& rows) {
  silence_hdf5();
  const std::string path = directory + "/" + trajectory_file_name(step, TrajectoryFormat::hdf5);
  const std::string temporary = path + ".tmp";
  std::vector<H5Record> records(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const TrajectoryRow& r = rows[i];
    H5Record& h = records[i];
    h.id = r.id;
    h.template_index = r.template_index;
    const double position[3] = {r.position.x, r.position.y, r.position.z};
    const double orientation[4] = {r.orientation.w, r.orientation.x, r.orientation.y,
                                   r.orientation.z};
    const Vec3d* vectors[2] = {&r.velocity, &r.angular_velocity};
    float* targets[2] = {h.velocity, h.angular_velocity};
    for (int k = 0; k < 3; ++k) h.position[k] = position[k];
    for (int k = 0; k < 4; ++k) h.orientation[k] = static_cast<float>(orientation[k]);
    for (int v = 0; v < 2; ++v) {
      targets[v][0] = static_cast<float>(vectors[v]->x);
      targets[v][1] = static_cast<float>(vectors[v]->y);
      targets[v][2] = static_cast<float>(vectors[v]->z);
    }
  }
  const auto fail = [&](const std::string& what) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error("cannot write '" + path + "': " + what);
  };
  {
    Handle file(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.ok()) fail("cannot create '" + temporary + "' (HDF5)");
    const hsize_t count[1] = {static_cast<hsize_t>(records.size())};
    const Handle space(H5Screate_simple(1, count, nullptr), H5Sclose);
    const Handle memory = record_type(false), stored = record_type(true);
    const Handle dataset(H5Dcreate2(file.get(), "particles", stored.get(), space.get(), H5P_DEFAULT,
                                    H5P_DEFAULT, H5P_DEFAULT),
                         H5Dclose);
    if (!dataset.ok()) fail("cannot create the dataset 'particles' (HDF5)");
    if (!records.empty() &&
        H5Dwrite(dataset.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, records.data()) < 0)
      fail("the particles could not be written (disk full?)");
    try {
      put_attribute(dataset.get(), "step", H5T_NATIVE_LLONG, &step);
      put_attribute(dataset.get(), "time", H5T_NATIVE_DOUBLE, &time);
    } catch (const std::runtime_error& e) {
      fail(e.what());
    }
    if (!file.close()) fail("the file could not be closed (disk full?)");
  }
  try {
    sync_file(temporary);  // on the disk before it takes the frame's name (output_files.hpp)
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) fail(error.message());
  sync_directory_of(path);
}

TrajectoryFrame read_trajectory_frame_hdf5(const std::string& path, long long step) {
  silence_hdf5();
  TrajectoryFrame frame;
  frame.step = step;
  // HDF5 would open a FIFO or a device as readily as a file, and block or read forever.
  const std::string problem = input_file_problem(path);
  if (!problem.empty()) throw InputFileError(path, problem);
  const Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw std::runtime_error(path + ": cannot open the file as HDF5");
  const Handle dataset(H5Dopen2(file.get(), "particles", H5P_DEFAULT), H5Dclose);
  if (!dataset.ok()) throw std::runtime_error(path + ": expected a dataset 'particles'");
  const Handle space(H5Dget_space(dataset.get()), H5Sclose);
  hsize_t count[1] = {0};
  if (H5Sget_simple_extent_ndims(space.get()) != 1 ||
      H5Sget_simple_extent_dims(space.get(), count, nullptr) < 0)
    throw std::runtime_error(path + ": expected 'particles' to be a list of records");
  std::vector<H5Record> records(count[0]);
  const Handle memory = record_type(false);
  if (!records.empty() &&
      H5Dread(dataset.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, records.data()) < 0)
    throw std::runtime_error(path +
                             ": expected 'particles' records of id, template, position, "
                             "orientation, velocity, angular_velocity");
  frame.rows.resize(records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const H5Record& h = records[i];
    if (h.template_index < 0)
      throw std::runtime_error(path + ": particles[" + std::to_string(i) +
                               "]: expected a template id (non-negative), got " +
                               std::to_string(h.template_index));
    TrajectoryRow& r = frame.rows[i];
    r.id = h.id;
    r.template_index = h.template_index;
    r.position = {h.position[0], h.position[1], h.position[2]};
    r.orientation = {h.orientation[0], h.orientation[1], h.orientation[2], h.orientation[3]};
    r.velocity = {h.velocity[0], h.velocity[1], h.velocity[2]};
    r.angular_velocity = {h.angular_velocity[0], h.angular_velocity[1], h.angular_velocity[2]};
  }
  return frame;
}

}  // namespace talus
