// The orthographic projection of `talus render`: world coordinates (m) to image pixels. The
// camera looks along one of the world axes; `right` and `up` span the image plane and
// toward_viewer = right x up points out of the image, at the camera.
//
//   column = origin_column + pixels_per_metre * (right . x)
//   row    = origin_row    - pixels_per_metre * (up . x)      (rows grow downwards)
//   depth  = toward_viewer . x                                (m; larger is nearer the camera)
//
// Pixel (c, r) is the unit square centred at integer (c, r), as in OpenCV. render.json records
// every number here, so that a tracker can go from pixels back to metres.
#pragma once

#include <string>
#include <vector>

#include "solver/core/vec3.hpp"

namespace talus {

struct ViewAxes {
  std::string name;  // "x", "-x", "y", "-y", "z", "-z": the direction the camera looks along
  Vec3d right, up, toward_viewer;
};

// The view names, for messages: "x, -x, y, -y, z, -z".
const char* view_names();

// Looking along a horizontal axis, up is +z; looking along +-z, up is +y. right = up x toward.
// Throws std::invalid_argument for another name.
ViewAxes view_axes(const std::string& name);

struct PixelPoint {
  double column = 0, row = 0;
  double depth = 0;  // m
};

struct Projection {
  ViewAxes axes;
  double pixels_per_metre = 1;
  double origin_column = 0, origin_row = 0;  // where the world origin lands, px
  int width = 0, height = 0;                 // px

  PixelPoint project(const Vec3d& x) const {
    return {origin_column + pixels_per_metre * dot(axes.right, x),
            origin_row - pixels_per_metre * dot(axes.up, x), dot(axes.toward_viewer, x)};
  }
};

// The largest scale at which every point lands inside the width x height image at least
// `margin` pixels from its edges, the points' extent centred. Throws std::invalid_argument when
// the image is not larger than twice the margin; no points (or one) give 1 px per mm about
// the first point (or the origin).
Projection fit_projection(const ViewAxes& axes, const std::vector<Vec3d>& points, int width,
                          int height, int margin);

}  // namespace talus
