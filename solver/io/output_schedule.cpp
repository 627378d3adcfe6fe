#include "solver/io/output_schedule.hpp"

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

// Trajectory frames (trajectory.hpp) and run.json beside them.
class TrajectoryWriter : public OutputWriter {
 public:
  TrajectoryWriter(const Scene& scene, const std::string& root, const std::string& solver,
                   std::size_t particles)
      : OutputWriter(scene.outputs.trajectories->every),
        directory_(joined_path(root, scene.outputs.trajectories->directory)),
        format_(trajectory_format(scene, particles)) {
    create_output_directory(directory_);
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

// The probe file (probes.hpp): one row per due step.
class ProbeFileWriter : public OutputWriter {
 public:
  ProbeFileWriter(const Scene& scene, const std::string& root, long long resume_step)
      : OutputWriter(scene.outputs.probes->every) {
    const std::string file = joined_path(root, scene.outputs.probes->file);
    std::vector<std::string> columns = probe_columns(*scene.outputs.probes, scene.walls);
    probes_ = resume_step >= 0
                  ? std::make_unique<ProbeWriter>(file, std::move(columns), resume_step)
                  : std::make_unique<ProbeWriter>(file, std::move(columns));
  }
  void write(long long step, OutputFrame& frame) override {
    probes_->write_row(frame.time(), step, frame.probe_values());
  }
  std::string path() const override { return probes_->path(); }

 private:
  std::unique_ptr<ProbeWriter> probes_;
};

// ParaView's files (vtk_output.hpp); their .pvd collections go on after a restart.
class VtkWriter : public OutputWriter {
 public:
  VtkWriter(const Scene& scene, const std::string& root, std::size_t particles)
      : OutputWriter(scene.outputs.vtk->every),
        vtk_(scene, joined_path(root, scene.outputs.vtk->directory),
             vtk_particles_for(scene, particles)) {}
  void write(long long step, OutputFrame& frame) override {
    vtk_.write_frame(step, frame.time(), frame.rows());
  }
  std::string path() const override { return vtk_.directory(); }
  std::string key() const override { return "outputs.vtk"; }
  std::string save() const override { return vtk_.save(); }
  void restore(const std::string& state) override { vtk_.restore(state); }

 private:
  VtkSeriesWriter vtk_;
};

}  // namespace

const std::vector<TrajectoryRow>& OutputFrame::rows() {
  if (!rows_) rows_ = source_.rows();
  return *rows_;
}

OutputSchedule::OutputSchedule(const Scene& scene, const std::string& output_root,
                               const std::string& solver, std::size_t particles,
                               long long resume_step) {
  const Outputs& o = scene.outputs;
  if (o.trajectories)
    writers_.push_back(std::make_unique<TrajectoryWriter>(scene, output_root, solver, particles));
  if (o.probes)
    writers_.push_back(std::make_unique<ProbeFileWriter>(scene, output_root, resume_step));
  if (o.vtk) writers_.push_back(std::make_unique<VtkWriter>(scene, output_root, particles));
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
  for (const auto& writer : writers_)
    if (!writer->key().empty()) checkpoint.put_text(writer->key(), writer->save());
}

void OutputSchedule::restore(const Checkpoint& checkpoint) {
  for (const auto& writer : writers_)
    if (!writer->key().empty()) writer->restore(checkpoint.text(writer->key()));
}

std::vector<std::string> OutputSchedule::paths() const {
  std::vector<std::string> paths;
  for (const auto& writer : writers_) paths.push_back(writer->path());
  return paths;
}

}  // namespace talus
