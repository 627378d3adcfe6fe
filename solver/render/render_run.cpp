#include "solver/render/render_run.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "solver/io/input_files.hpp"
#include "solver/io/json.hpp"
#include "solver/io/output_files.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/io/vtk_output.hpp"
#include "solver/render/frame_image.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;

// DIR itself when it holds run.json, else its one subdirectory that does.
std::string trajectory_directory(const std::string& dir) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) {
    const std::string problem = input_file_problem(dir);  // what it is instead
    throw std::runtime_error(
        dir + ": " +
        (problem == "does not exist" ? "no such directory"
         : problem.empty()           ? "a regular file, not a directory"
                                     : "not a directory: it " + problem) +
        " (expected the trajectory directory of a run: outputs.trajectories.directory of its "
        "scene)");
  }
  if (fs::exists(fs::path(dir) / "run.json")) return dir;
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir, error))
    if (entry.is_directory() && fs::exists(entry.path() / "run.json"))
      found.push_back(entry.path().string());
  if (found.size() == 1) return found.front();
  if (found.empty())
    throw std::runtime_error(dir +
                             ": no run.json in it or in a directory inside it (expected the "
                             "trajectory directory of a run: outputs.trajectories.directory "
                             "of its scene)");
  std::sort(found.begin(), found.end());
  std::string listed;
  for (const std::string& f : found) listed += (listed.empty() ? "" : ", ") + f;
  throw std::runtime_error(dir + ": several runs inside it (" + listed + "); name one");
}

std::vector<Vec3d> fit_points(const Scene& scene, const ViewAxes& axes,
                              const std::vector<const TrajectoryFrame*>& frames,
                              const std::vector<WallMesh>& meshes, double time_step,
                              bool with_walls) {
  std::vector<Vec3d> points;
  for (const TrajectoryFrame* frame : frames) {
    add_particle_extent(scene, axes, frame->rows, points);
    if (with_walls)
      for (const TriangleMesh& wall : walls_at(scene, meshes, frame->step * time_step))
        points.insert(points.end(), wall.vertices.begin(), wall.vertices.end());
  }
  return points;
}

struct FrameEntry {
  long long step;
  double time;
  std::string image, table;
};

std::string render_json(const RenderReport& report, const RenderSettings& settings,
                        const std::vector<FrameEntry>& frames) {
  const Projection& p = report.projection;
  Json json;
  json["trajectory_directory"] = report.trajectory_directory;
  json["scene"] = report.scene_file;
  json["view"] = p.axes.name;
  json["color"] = to_string(settings.color);
  json["width"] = p.width;
  json["height"] = p.height;
  json["right"] = p.axes.right;
  json["up"] = p.axes.up;
  json["toward_viewer"] = p.axes.toward_viewer;
  json["pixels_per_metre"] = p.pixels_per_metre;
  json["origin_pixel"] = {p.origin_column, p.origin_row};
  json["pixel_rule"] =
      "column = origin_pixel[0] + pixels_per_metre * (right . x); row = origin_pixel[1] - "
      "pixels_per_metre * (up . x); pixel (c, r) is centred at integer (c, r)";
  json["max_speed"] = report.max_speed;
  json["frames"] = Json::array();
  for (const FrameEntry& f : frames)
    json["frames"].push_back(
        {{"step", f.step}, {"time", f.time}, {"image", f.image}, {"particles", f.table}});
  return json_text(json);
}

std::string centres_csv(const Projection& projection, const std::vector<TrajectoryRow>& rows,
                        const std::vector<long long>& visible) {
  std::string text = "id,template,column,row,depth,visible_pixels\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const PixelPoint p = projection.project(rows[k].position);
    text += std::to_string(rows[k].id) + "," + std::to_string(rows[k].template_index) + "," +
            exact_decimal(p.column) + "," + exact_decimal(p.row) + "," + exact_decimal(p.depth) +
            "," + std::to_string(visible[k]) + "\n";
  }
  return text;
}

}  // namespace

void add_particle_extent(const Scene& scene, const ViewAxes& axes,
                         const std::vector<TrajectoryRow>& rows, std::vector<Vec3d>& points) {
  for (const TrajectoryRow& row : rows) {
    const double r = scene.templates.at(row.template_index).bounding_radius;
    for (const Vec3d& d : {axes.right, axes.up}) {
      points.push_back(row.position + d * r);
      points.push_back(row.position - d * r);
    }
  }
}

RenderReport render_run(const RenderSettings& settings,
                        const std::function<void(const std::string&)>& progress) {
  if (settings.every < 1) throw std::invalid_argument("every: expected a whole number >= 1");
  RenderReport report;
  report.trajectory_directory = trajectory_directory(settings.run_directory);
  const RunInfo info = read_run_info(report.trajectory_directory);
  report.scene_file = settings.scene_file.empty() ? info.scene_file : settings.scene_file;
  if (!fs::exists(report.scene_file))
    throw std::runtime_error(
        report.trajectory_directory + "/run.json: the scene '" + report.scene_file +
        "' is not found from the working directory; run talus render from where the run was "
        "started, or name the scene with --scene FILE");
  const Scene scene = load_scene(report.scene_file);

  const std::vector<TrajectoryFrame> all = read_trajectory(report.trajectory_directory);
  if (all.empty())
    throw std::runtime_error(report.trajectory_directory +
                             ": no trajectory_<step>.csv or .h5 files (the run wrote no frame "
                             "yet)");
  std::vector<const TrajectoryFrame*> frames;
  for (std::size_t k = 0; k < all.size(); ++k)
    if ((!settings.last_only && k % settings.every == 0) || k + 1 == all.size())
      frames.push_back(&all[k]);
  for (const TrajectoryFrame* frame : frames)
    for (const TrajectoryRow& row : frame->rows)
      if (row.template_index >= static_cast<int>(scene.templates.size()))
        throw std::runtime_error(report.trajectory_directory + "/" +
                                 trajectory_file_name(frame->step, info.trajectory_format == "hdf5"
                                                                       ? TrajectoryFormat::hdf5
                                                                       : TrajectoryFormat::csv) +
                                 ": template id " + std::to_string(row.template_index) +
                                 " of particle " + std::to_string(row.id) + ", but the scene '" +
                                 report.scene_file + "' has " +
                                 std::to_string(scene.templates.size()) + " templates");

  const ViewAxes axes = view_axes(settings.view);
  const std::vector<WallMesh> meshes = make_wall_meshes(scene);
  report.projection = fit_projection(
      axes, fit_points(scene, axes, frames, meshes, info.time_step, settings.fit_walls),
      settings.width, settings.height, settings.margin);
  report.max_speed = settings.max_speed;
  if (report.max_speed <= 0)
    for (const TrajectoryFrame* frame : frames)
      for (const TrajectoryRow& row : frame->rows)
        report.max_speed = std::max(report.max_speed, norm(row.velocity));

  report.output_directory = settings.output_directory.empty()
                                ? report.trajectory_directory + "/render"
                                : settings.output_directory;
  create_output_directory(report.output_directory, settings.output_directory.empty()
                                                       ? "picture directory"
                                                       : "picture directory (--output)");
  std::vector<TemplateSurface> surfaces;
  for (const ParticleTemplate& t : scene.templates) surfaces.push_back(template_surface(t));
  DrawSettings draw;
  draw.color = settings.color;
  draw.max_speed = report.max_speed;
  draw.outline = settings.outline;
  std::vector<FrameEntry> entries;
  for (const TrajectoryFrame* frame : frames) {
    const double time = frame->step * info.time_step;
    const FrameDrawing drawing =
        draw_frame(report.projection, surfaces, frame->rows, walls_at(scene, meshes, time), draw);
    char label[64];
    std::snprintf(label, sizeof label, "t = %.4g s", time);
    const FrameImage image = render_frame_image(drawing, settings.width, settings.height,
                                                frame->rows.size(), settings.label ? label : "");
    FrameEntry entry{frame->step, time, numbered_file_name("frame_", frame->step, ".png"),
                     numbered_file_name("frame_", frame->step, ".csv")};
    write_file_atomically(report.output_directory + "/" + entry.image, image.png);
    write_file_atomically(report.output_directory + "/" + entry.table,
                          centres_csv(report.projection, frame->rows, image.visible_pixels));
    entries.push_back(entry);
    write_file_atomically(report.output_directory + "/render.json",
                          render_json(report, settings, entries));
    report.images.push_back(report.output_directory + "/" + entry.image);
    if (progress) progress(report.images.back());
  }
  return report;
}

}  // namespace talus
