// `talus render DIR`: pictures of a run from what `talus run` wrote. DIR is the trajectory
// directory (outputs.trajectories.directory: run.json and trajectory_<step>.csv), or a directory
// with exactly one such directory inside it. The scene comes from the file run.json names (or
// RenderSettings::scene_file), and each frame's walls from the scene at the frame's time.
//
// Writes into the output directory, each file through a temporary name and a rename:
//   frame_<step>.png   the picture (frame_drawing.hpp, frame_image.hpp);
//   frame_<step>.csv   id,template,column,row,depth,visible_pixels: each particle's centre
//                      projected to pixels (column, row; fractional), its depth (m, toward the
//                      camera) and how many pixels show it;
//   render.json        the projection (projection.hpp) and the list of frames, rewritten after
//                      each frame.
// One projection serves every frame of a render, so that positions compare across frames.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "solver/render/frame_drawing.hpp"
#include "solver/render/projection.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

struct RenderSettings {
  std::string run_directory;
  std::string scene_file;        // empty: the one run.json names
  std::string output_directory;  // empty: <trajectory directory>/render
  std::string view = "y";
  ColorMode color = ColorMode::normal;
  int width = 800, height = 800;  // px
  int margin = 16;                // px
  int every = 1;                  // every k-th trajectory frame (the last always)
  bool last_only = false;         // the last frame only
  // The image fits every rendered particle; with fit_walls also the walls at those times.
  bool fit_walls = true;
  double max_speed = 0;  // m/s, drawn red in velocity mode; 0: the fastest of the frames
  bool label = true;     // the time in the top-left corner
  bool outline = false;  // each particle's silhouette as a dark line (DrawSettings::outline)
};

struct RenderReport {
  std::string trajectory_directory, scene_file, output_directory;
  Projection projection;
  double max_speed = 0;
  std::vector<std::string> images;
};

// Each particle's bounding circle in the picture's plane, as the points (centre plus and minus
// its bounding radius along `right` and `up`) that fit_projection fits a picture to.
void add_particle_extent(const Scene& scene, const ViewAxes& axes,
                         const std::vector<TrajectoryRow>& rows, std::vector<Vec3d>& points);

// Throws std::runtime_error naming the file or directory and what was expected (no run.json,
// no trajectory files, a scene that cannot be found), SceneError for a scene that does not
// load, std::invalid_argument for a bad setting.
RenderReport render_run(const RenderSettings& settings,
                        const std::function<void(const std::string& image)>& progress = {});

}  // namespace talus
