// Trajectory output, the same for both solvers: one CSV file per output step,
// DIR/trajectory_<step, 9 digits>.csv, one row per particle, with the header kTrajectoryHeader;
// and DIR/run.json, which says what produced them. Format: docs/scenes.md, "Output files".
#pragma once

#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

constexpr const char* kTrajectoryHeader = "id,template,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

struct TrajectoryRow {
  long long id = 0;        // global particle id
  int template_index = 0;  // index into Scene::templates (run.json names them)
  Vec3d position;          // centroid, m
  Quatd orientation;       // body -> world
  Vec3d velocity;          // m/s
  Vec3d angular_velocity;  // rad/s, world frame
};

struct TrajectoryFrame {
  long long step = 0;
  std::vector<TrajectoryRow> rows;
};

// "trajectory_000001200.csv" for step 1200 (more digits past 999999999); ".h5" for HDF5.
std::string trajectory_file_name(long long step);
std::string trajectory_file_name(long long step, TrajectoryFormat format);

// Writes DIR/trajectory_<step>.csv (through a temporary file and a rename; the directory must
// exist: create_output_directory). Values are printed with %.17g, so they read back exactly.
// Throws std::runtime_error naming the file and the reason.
void write_trajectory_frame(const std::string& directory, long long step,
                            const std::vector<TrajectoryRow>& rows);

// Writes DIR/trajectory_<step>.h5 (trajectory_hdf5.cpp; docs/scenes.md, "Output files"): the
// positions exact, orientations and velocities in single precision, the step and time (s) as
// attributes; through a temporary file and a rename. Throws std::runtime_error naming the file.
void write_trajectory_frame_hdf5(const std::string& directory, long long step, double time,
                                 const std::vector<TrajectoryRow>& rows);

// One file, CSV or HDF5 by its name, its step taken from the name. Throws std::runtime_error
// "<path>:<line>: ..." (CSV) or "<path>: ..." (HDF5) when the file is not a trajectory file.
TrajectoryFrame read_trajectory_frame(const std::string& path);
// The HDF5 frame at `path` (of step `step`).
TrajectoryFrame read_trajectory_frame_hdf5(const std::string& path, long long step);

// Every trajectory_<digits>.csv or .h5 of the directory, by increasing step (temporary files and
// other files are ignored).
std::vector<TrajectoryFrame> read_trajectory(const std::string& directory);

// What run.json records.
struct RunInfo {
  std::string scene_file;
  std::string solver;                     // e.g. "talus", "reference"
  std::string precision;                  // "double" or "float"
  double time_step = 0;                   // s; the time of a frame is step * time_step
  std::vector<std::string> templates;     // names; a template's id is its index
  std::string trajectory_format = "csv";  // "csv" or "hdf5": the frames' files
};

// The run information of a scene, for the named solver.
RunInfo run_info(const Scene& scene, const std::string& solver);

// Writes DIR/run.json the same way as the frames:
// {"scene": ..., "solver": ..., "precision": ..., "time_step": ...,
//  "templates": [{"id": 0, "name": ...}, ...]}
void write_run_info(const std::string& directory, const RunInfo& info);

// Reads DIR/run.json as write_run_info writes it (scene, solver, precision, time_step, template
// names). Throws std::runtime_error "<DIR>/run.json: ..." naming what is missing.
RunInfo read_run_info(const std::string& directory);

}  // namespace talus
