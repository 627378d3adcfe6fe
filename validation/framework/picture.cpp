// A picture of a case's particles (validation.hpp, write_particle_picture): talus render's
// drawing (solver/render/), where talus is built with OpenCV.
#include "validation/framework/validation.hpp"

#if TALUS_HAVE_OPENCV
#include "solver/io/output_files.hpp"
#include "solver/io/vtk_output.hpp"
#include "solver/render/frame_drawing.hpp"
#include "solver/render/frame_image.hpp"
#include "solver/render/render_run.hpp"
#include "solver/scene/wall_meshes.hpp"
#endif

namespace talus::validation {

#if TALUS_HAVE_OPENCV

bool write_particle_picture(const Scene& scene, const std::vector<TrajectoryRow>& rows, double time,
                            const std::string& view, int width, int height,
                            const std::string& path) {
  const ViewAxes axes = view_axes(view);
  std::vector<Vec3d> extent;
  add_particle_extent(scene, axes, rows, extent);
  const Projection projection = fit_projection(axes, extent, width, height, 16);
  std::vector<TemplateSurface> surfaces;
  for (const ParticleTemplate& t : scene.templates) surfaces.push_back(template_surface(t));
  const FrameDrawing drawing =
      draw_frame(projection, surfaces, rows, walls_at(scene, make_wall_meshes(scene), time), {});
  write_file_atomically(path, render_frame_image(drawing, width, height, rows.size(), "").png);
  return true;
}

#else

bool write_particle_picture(const Scene&, const std::vector<TrajectoryRow>&, double,
                            const std::string&, int, int, const std::string&) {
  return false;
}

#endif

}  // namespace talus::validation
