// The raster of a FrameDrawing (OpenCV: core, imgproc, imgcodecs): white background, the
// polygons filled back to front without anti-aliasing (each pixel takes one polygon's colour,
// exactly; an outline is a 1 px closed line), corners placed to 1/16 px; the walls' outline as
// anti-aliased dark grey lines on top; a label in the top-left corner. Also which particle each
// pixel shows.
#pragma once

#include <string>
#include <vector>

#include "solver/render/frame_drawing.hpp"

namespace talus {

struct FrameImage {
  std::string png;  // the encoded file
  // Per row of the frame: the pixels where the particle is seen (not hidden by a nearer one,
  // before the wall lines are drawn over it).
  std::vector<long long> visible_pixels;
};

// Throws std::runtime_error when OpenCV cannot encode the PNG.
FrameImage render_frame_image(const FrameDrawing& drawing, int width, int height,
                              std::size_t particles, const std::string& label);

}  // namespace talus
