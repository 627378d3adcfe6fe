// What one picture of `talus render` holds, before any pixel is set: the particles' faces that
// face the camera as filled polygons in pixel coordinates, ordered back to front (the painter's
// algorithm), and the walls' outline as segments. Pure geometry and colour; the raster is
// frame_image.hpp (OpenCV).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "solver/io/trajectory.hpp"
#include "solver/io/vtk_output.hpp"
#include "solver/render/projection.hpp"

namespace talus {

// normal: each face a base colour shaded by the angle between its normal and the light (over
// the camera's shoulder); velocity: the particle's speed on a blue-to-red scale, shaded the same
// way; id: one flat colour per particle id (id_color), unshaded, so a tracker can segment it.
enum class ColorMode { normal, velocity, id };
const char* to_string(ColorMode mode);

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

// A colour per id, far apart for neighbouring ids (hues stepped by the golden angle, three
// saturation-value levels); no id gets white (the background) or the walls' grey.
Rgb id_color(long long id);

// 0 (at rest) to 1 (the fastest): blue through green to red.
Rgb speed_color(double fraction);

struct DrawPolygon {
  std::vector<PixelPoint> corners;
  Rgb color;
  int particle = 0;      // the row of the frame it belongs to
  bool outline = false;  // a closed line along the corners (a silhouette), not filled
};

struct DrawSegment {
  PixelPoint a, b;
};

struct FrameDrawing {
  std::vector<DrawPolygon> polygons;  // back to front
  std::vector<DrawSegment> wall_edges;
};

struct DrawSettings {
  ColorMode color = ColorMode::normal;
  double max_speed = 0;  // m/s: the speed drawn red (velocity mode)
  // Each particle's silhouette (the convex hull of its projected corners) as a dark line over
  // its faces, so that a nearer particle's edge shows where it hides a farther one, as the
  // occluding contours of a photograph do; particles of one colour would otherwise merge.
  bool outline = false;
};

// The outline's colour: a dark neutral grey (blue equals red), which no face of the normal or
// velocity colourings has, and no id colour.
constexpr Rgb kOutlineColor{35, 35, 35};

// The particles of `rows` (their templates' surfaces: template_surface of vtk_output.hpp) and
// the walls (as they stand at the frame's time: walls_at). Particles are painted farthest first
// by their centres' depth, each particle's faces that face the camera only (for a convex body
// they do not overlap one another), then its outline where settings.outline. A wall's outline: its
// boundary edges, creases (neighbouring triangles more than 30 degrees apart) and silhouette edges
// (one neighbour facing the camera, the other not).
FrameDrawing draw_frame(const Projection& projection, const std::vector<TemplateSurface>& surfaces,
                        const std::vector<TrajectoryRow>& rows,
                        const std::vector<TriangleMesh>& walls, const DrawSettings& settings);

}  // namespace talus
