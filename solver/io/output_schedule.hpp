// What a run writes and when, for both runners (solver/run/production_run and
// reference/run/scene_run): each output the scene names is an OutputWriter, due every `every`
// steps and at the last step; the schedule hands the due ones the step's frame, whose particle
// rows (a GPU download, or a walk over the reference's bodies) are gathered at most once.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

// What the writers may take of the run at a step; called only when some writer is due.
class OutputSource {
 public:
  virtual ~OutputSource() = default;
  virtual double time() const = 0;
  virtual std::vector<TrajectoryRow> rows() const = 0;
  virtual std::vector<double> probe_values() const = 0;  // the probe file's columns, in order
};

// A step's data, each part taken from the source on first use.
class OutputFrame {
 public:
  explicit OutputFrame(const OutputSource& source) : source_(source) {}
  double time() const { return source_.time(); }
  const std::vector<TrajectoryRow>& rows();
  std::vector<double> probe_values() const { return source_.probe_values(); }

 private:
  const OutputSource& source_;
  std::optional<std::vector<TrajectoryRow>> rows_;
};

class OutputWriter {
 public:
  explicit OutputWriter(long long every) : every_(every) {}
  virtual ~OutputWriter() = default;
  OutputWriter(const OutputWriter&) = delete;
  OutputWriter& operator=(const OutputWriter&) = delete;

  bool due(long long step, bool last) const { return step % every_ == 0 || last; }
  // Writes the step's output; throws std::runtime_error naming the file that cannot be written.
  virtual void write(long long step, OutputFrame& frame) = 0;
  // The file or directory, as the run's summary lists it.
  virtual std::string path() const = 0;
  // What the writer needs to go on after a restart, as checkpoint sections named after it
  // (its constructor takes them back from the checkpoint of a resumed run).
  virtual void save(Checkpoint& /*checkpoint*/) const {}
  // Files appended to in place (the probe file) on the disk, before a checkpoint counts them.
  virtual void sync() {}

 private:
  long long every_;
};

class OutputSchedule {
 public:
  // The outputs the scene names, under `output_root` (empty: the working directory): their
  // directories and first files (run.json names `solver`). `particles`: the run's particle count
  // at the start (the ParaView default and the trajectory format depend on it). `resume`: the
  // checkpoint of a run resumed after its step: each writer takes its state from it and checks
  // that its files are the ones the checkpoint's run wrote (the probe file holds the very rows it
  // had written by then; run.json is kept as it is). Throws std::runtime_error naming a path that
  // cannot be created, CheckpointError naming a file that does not continue the checkpoint's run.
  OutputSchedule(const Scene& scene, const std::string& output_root, const std::string& solver,
                 std::size_t particles, const Checkpoint* resume = nullptr);
  ~OutputSchedule();

  // Whether any output is due at `step` (`last`: the run's last step).
  bool due(long long step, bool last) const;
  // Writes every output due at `step`.
  void write(long long step, bool last, const OutputSource& source);

  // The writers' states into a checkpoint (a restart), after sync(): every file written so far
  // is on the disk (fsync) before a checkpoint says it is.
  void save(Checkpoint& checkpoint) const;
  void sync();

  // Each output's file or directory, in the scene's order: trajectories, probes, ParaView.
  std::vector<std::string> paths() const;

 private:
  std::vector<std::unique_ptr<OutputWriter>> writers_;
};

}  // namespace talus
