// `talus render [options] DIR`: the pictures of a run, where CMake found OpenCV
// (TALUS_HAVE_OPENCV); elsewhere a RunError says that talus was built without it.
#include <cstdio>
#include <stdexcept>

#include "solver/app/commands.hpp"
#include "solver/io/json.hpp"
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
  Json json;
  json["trajectory_directory"] = report.trajectory_directory;
  json["scene"] = report.scene_file;
  json["output_directory"] = report.output_directory;
  json["projection"] = report.output_directory + "/render.json";
  json["view"] = p.axes.name;
  json["pixels_per_metre"] = p.pixels_per_metre;
  json["frames"] = report.images.size();
  json["images"] = report.images;
  return json_text(json);
#else
  (void)args;
  throw RunError(
      "talus render: this talus was built without OpenCV (CMake did not find it; scripts/setup "
      "installs libopencv-dev), so it cannot draw pictures");
#endif
}

}  // namespace talus
