// The probe file: CSV with the header time,step,<columns>, one row per probe step, appended and
// flushed at once so that an interrupted run keeps every row it wrote. Columns, in the order the
// scene lists its quantities: kinetic_energy; contact_count; bed_height; wall_forces expands to
// wall_<name>_fx, _fy, _fz, _tx, _ty, _tz for every wall in scene order; energy expands to
// energy_probe_columns().
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

// The columns the energy probe expands to (J): the kinetic, gravitational and elastic energies
// held, the totals dissipated, given by moving walls and brought by feeds, and the balance
// held + dissipated - given, constant in an exact run (solver/step/energy.hpp).
const std::vector<std::string>& energy_probe_columns();

// The columns after time and step, for the scene's probe quantities and walls.
std::vector<std::string> probe_columns(const ProbeOutput& probes,
                                       const std::vector<WallSpec>& walls);

// Where a resumed probe file continues (ProbeWriter below).
struct ProbeResume {
  long long step = 0;      // the checkpoint's step
  long long bytes = -1;    // the file's length at the checkpoint; -1: not recorded
  std::uint64_t hash = 0;  // FNV-1a of those bytes (checkpoint.hpp)
  std::string checkpoint;  // the checkpoint file, named first in the messages (empty: none)
};

class ProbeWriter {
 public:
  // Creates the file's directory when missing, creates (or empties) the file and writes the
  // header. Throws std::runtime_error naming the path and the reason.
  ProbeWriter(const std::string& path, std::vector<std::string> columns);
  // Continues the file of a run resumed after the checkpoint `resume` describes. With the
  // checkpoint's length and hash of what its run had written (`bytes` >= 0), the file must begin
  // with exactly those bytes: it is cut back to them (rows the interrupted run wrote after its
  // checkpoint go), then rows are appended. A file that is shorter (it does not reach the
  // checkpoint's step), or whose first bytes differ (another run's file), is refused with a
  // CheckpointError naming it. Without them (a checkpoint of an older talus), the rows of steps
  // up to `step` and no partial last line are kept. Throws std::runtime_error naming the path when
  // the file is missing or its header is not time,step and `columns`.
  ProbeWriter(const std::string& path, std::vector<std::string> columns, const ProbeResume& resume);
  ~ProbeWriter();
  ProbeWriter(const ProbeWriter&) = delete;
  ProbeWriter& operator=(const ProbeWriter&) = delete;

  // One row: time (s), step, then one value per column (%.17g). Throws std::invalid_argument
  // when the count of values differs from the columns', std::runtime_error when writing fails.
  void write_row(double time, long long step, const std::vector<double>& values);

  // fsync: the rows written so far are on the disk.
  void sync();
  // The file's length so far and the FNV-1a of its bytes (a checkpoint's record of it).
  long long bytes() const { return bytes_; }
  std::uint64_t hash() const { return hash_; }

  const std::string& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::FILE* file_ = nullptr;
  long long bytes_ = 0;
  std::uint64_t hash_ = 0;
  void count(const std::string& text);  // adds written bytes to bytes_ and hash_
};

// A probe file read back: the header's names (time and step included) and the rows' numbers.
struct ProbeTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};
// Throws std::runtime_error "<path>:<line>: ..." on a malformed file.
ProbeTable read_probe_file(const std::string& path);

}  // namespace talus
