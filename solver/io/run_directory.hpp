// An output root belongs to one run (docs/scenes.md, "Output files"): while a run or a resume
// writes into it, it holds an exclusive lock on `<root>/.talus.lock` (flock, released by the
// kernel however the process ends, so a killed run never leaves a stale lock); a second run or
// resume into the same root is refused with the holder's description. A new run also refuses a
// root where files named like the outputs its scene writes are already there (an earlier run's),
// unless it is told to remove them first. Both runners (solver/run/production_run,
// reference/run/scene_run) claim their root this way.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "solver/io/output_names.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

// An output root that another run holds, or that holds an earlier run's outputs.
class OutputConflict : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OutputLock {
 public:
  OutputLock() = default;
  // Creates the root when missing and takes the lock, writing `holder` (who holds it: process,
  // host, start time, run id, scene) into the lock file. Throws OutputConflict naming the root
  // and the holder's description when another process holds it, std::runtime_error when the
  // lock file cannot be created.
  OutputLock(const std::string& root, const std::string& holder);
  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

// A new run's id: 16 hexadecimal digits from the clock, the process id and std::random_device.
// Every checkpoint carries it (`run.id`), so that pruning removes only the run's own.
std::string new_run_id();

// "pid 4242 on host, started 2026-11-26T07:01:27Z, run 1f..., scene <its file>": what a lock holder
// says of itself.
std::string run_holder_description(const std::string& run_id, const std::string& scene_file);

// The files under `root` named like an output of `scene` (trajectory frames and run.json in
// its trajectory directory, the probe file, ParaView files in its vtk directory, checkpoints in
// its checkpoint directory, and their temporary files), sorted. Other files are not the run's
// business and are left alone.
std::vector<std::string> existing_outputs(const Scene& scene, const std::string& root);

// Locks `root` for a run of `scene` (OutputLock) and, for a new run (`resume` false), refuses
// (OutputConflict) a root with earlier outputs (existing_outputs) or, when `overwrite` is set,
// removes them first. The lock is held until the returned object is destroyed. A scene without
// outputs writes nothing and claims nothing (an unheld lock).
OutputLock claim_output_root(const Scene& scene, const std::string& root, const std::string& run_id,
                             bool resume, bool overwrite);

}  // namespace talus
