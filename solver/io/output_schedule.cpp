#include "solver/io/output_schedule.hpp"

#include <filesystem>

#include "solver/io/output_files.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/vtk_output.hpp"
#include "solver/scene/feeder.hpp"

namespace talus {

namespace {

// The scene's trajectory format, or by the run's size: its particles at the start and all that
// its feeds insert by the end.
TrajectoryFormat trajectory_format(const Scene& scene, std::size_t particles) {
  if (scene.outputs.trajectories->format) return *scene.outputs.trajectories->format;
  long long total = static_cast<long long>(particles);
  for (std::size_t f = 0; f < scene.feeds.size(); ++f)
    total += Feeder(scene, static_cast<int>(f)).due(scene.end_time);
  return total >= static_cast<long long>(kHdf5TrajectoryParticles) ? TrajectoryFormat::hdf5
                                                                   : TrajectoryFormat::csv;
}

// Trajectory frames (trajectory.hpp) and run.json beside them. A resumed run keeps the run.json
// its start wrote (written again only where it is missing).
class TrajectoryWriter : public OutputWriter {
 public:
  TrajectoryWriter(const Scene& scene, const std::string& root, const std::string& solver,
                   std::size_t particles, bool resume)
      : OutputWriter(scene.outputs.trajectories->every),
        directory_(joined_path(root, scene.outputs.trajectories->directory)),
        format_(trajectory_format(scene, particles)) {
    create_output_directory(directory_, "trajectory directory (outputs.trajectories.directory)");
    if (resume && std::filesystem::exists(directory_ + "/run.json")) return;
    RunInfo info = run_info(scene, solver);
    info.trajectory_format = format_ == TrajectoryFormat::hdf5 ? "hdf5" : "csv";
    write_run_info(directory_, info);
  }
  void write(long long step, OutputFrame& frame) override {
    if (format_ == TrajectoryFormat::hdf5)
      write_trajectory_frame_hdf5(directory_, step, frame.time(), frame.rows());
    else
      write_trajectory_frame(directory_, step, frame.rows());
  }
  std::string path() const override { return directory_; }

 private:
  std::string directory_;
  TrajectoryFormat format_;
};

// The probe file (probes.hpp): one row per due step. Its state in a checkpoint is the length and
// hash of what was written by then, so that a resumed run continues exactly that file.
class ProbeFileWriter : public OutputWriter {
 public:
  ProbeFileWriter(const Scene& scene, const std::string& root, const Checkpoint* resume)
      : OutputWriter(scene.outputs.probes->every) {
    const std::string file = joined_path(root, scene.outputs.probes->file);
    std::vector<std::string> columns = probe_columns(*scene.outputs.probes, scene.walls);
    if (!resume) {
      probes_ = std::make_unique<ProbeWriter>(file, std::move(columns));
    } else {
      const long long step = resume->get_value<long long>("step.steps");
      ProbeResume expected{step, -1, 0, resume->path()};
      if (resume->has(kKey)) {
        const std::vector<std::uint64_t> state = resume->get<std::uint64_t>(kKey);
        if (state.size() != 2) resume->fail(kKey, "expected the probe file's length and hash");
        expected.bytes = static_cast<long long>(state[0]);
        expected.hash = state[1];
      }
      probes_ = std::make_unique<ProbeWriter>(file, std::move(columns), expected);
    }
  }
  void write(long long step, OutputFrame& frame) override {
    probes_->write_row(frame.time(), step, frame.probe_values());
  }
  std::string path() const override { return probes_->path(); }
  void save(Checkpoint& checkpoint) const override {
    checkpoint.put(kKey, std::vector<std::uint64_t>{static_cast<std::uint64_t>(probes_->bytes()),
                                                    probes_->hash()});
  }
  void sync() override { probes_->sync(); }

 private:
  static constexpr const char* kKey = "outputs.probes";
  std::unique_ptr<ProbeWriter> probes_;
};

// ParaView's files (vtk_output.hpp); their .pvd collections go on after a restart.
class VtkWriter : public OutputWriter {
 public:
  VtkWriter(const Scene& scene, const std::string& root, std::size_t particles,
            const Checkpoint* resume)
      : OutputWriter(scene.outputs.vtk->every),
        vtk_(scene, joined_path(root, scene.outputs.vtk->directory),
             vtk_particles_for(scene, particles)) {
    if (resume) vtk_.restore(resume->text(kKey));
  }
  void write(long long step, OutputFrame& frame) override {
    vtk_.write_frame(step, frame.time(), frame.rows());
  }
  std::string path() const override { return vtk_.directory(); }
  void save(Checkpoint& checkpoint) const override { checkpoint.put_text(kKey, vtk_.save()); }

 private:
  static constexpr const char* kKey = "outputs.vtk";
  VtkSeriesWriter vtk_;
};

}  // namespace

const std::vector<TrajectoryRow>& OutputFrame::rows() {
  if (!rows_) rows_ = source_.rows();
  return *rows_;
}

OutputSchedule::OutputSchedule(const Scene& scene, const std::string& output_root,
                               const std::string& solver, std::size_t particles,
                               const Checkpoint* resume) {
  const Outputs& o = scene.outputs;
  if (o.trajectories)
    writers_.push_back(
        std::make_unique<TrajectoryWriter>(scene, output_root, solver, particles, resume));
  if (o.probes) writers_.push_back(std::make_unique<ProbeFileWriter>(scene, output_root, resume));
  if (o.vtk) writers_.push_back(std::make_unique<VtkWriter>(scene, output_root, particles, resume));
}

OutputSchedule::~OutputSchedule() = default;

bool OutputSchedule::due(long long step, bool last) const {
  for (const auto& writer : writers_)
    if (writer->due(step, last)) return true;
  return false;
}

void OutputSchedule::write(long long step, bool last, const OutputSource& source) {
  OutputFrame frame(source);
  for (const auto& writer : writers_)
    if (writer->due(step, last)) writer->write(step, frame);
}

void OutputSchedule::save(Checkpoint& checkpoint) const {
  for (const auto& writer : writers_) writer->save(checkpoint);
}

void OutputSchedule::sync() {
  for (const auto& writer : writers_) writer->sync();
}

std::vector<std::string> OutputSchedule::paths() const {
  std::vector<std::string> paths;
  for (const auto& writer : writers_) paths.push_back(writer->path());
  return paths;
}

}  // namespace talus
