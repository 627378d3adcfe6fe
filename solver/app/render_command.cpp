// `talus render [options] DIR`: the pictures of a run, where CMake found OpenCV
// (TALUS_HAVE_OPENCV); elsewhere a RunError says that talus was built without it.
#include <cstdio>
#include <stdexcept>

#include "solver/app/commands.hpp"
#include "solver/app/json_writer.hpp"
#include "solver/scene/scene_loader.hpp"

namespace talus {

std::string render_json(const RenderArguments& args) {
#if TALUS_HAVE_OPENCV
  RenderReport report;
  try {
    report = render_run(args.settings, [&](const std::string& image) {
      if (!args.quiet) std::fprintf(stderr, "talus render: %s\n", image.c_str());
    });
  } catch (const SceneError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw RunError(e.what());  // a directory or file it cannot draw: the user's input
  }
  const Projection& p = report.projection;
  JsonWriter json;
  json.begin_object();
  json.member("trajectory_directory", report.trajectory_directory);
  json.member("scene", report.scene_file);
  json.member("output_directory", report.output_directory);
  json.member("projection", report.output_directory + "/render.json");
  json.member("view", p.axes.name);
  json.member("pixels_per_metre", p.pixels_per_metre);
  json.member("frames", static_cast<int>(report.images.size()));
  json.key("images");
  json.begin_array(JsonWriter::Layout::multi_line);
  for (const std::string& image : report.images) json.value(image);
  json.end_array();
  json.end_object();
  return json.str();
#else
  (void)args;
  throw RunError(
      "talus render: this talus was built without OpenCV (CMake did not find it; scripts/setup "
      "installs libopencv-dev), so it cannot draw pictures");
#endif
}

}  // namespace talus
