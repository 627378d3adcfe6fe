#include "solver/render/projection.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace talus {

const char* view_names() {
  return "x, -x, y, -y, z, -z";
}

ViewAxes view_axes(const std::string& name) {
  const bool negative = !name.empty() && name[0] == '-';
  const std::string axis = negative ? name.substr(1) : name;
  const double sign = negative ? -1.0 : 1.0;
  Vec3d look;
  if (axis == "x") {
    look = {sign, 0, 0};
  } else if (axis == "y") {
    look = {0, sign, 0};
  } else if (axis == "z") {
    look = {0, 0, sign};
  } else {
    throw std::invalid_argument("expected one of " + std::string(view_names()));
  }
  ViewAxes v;
  v.name = name;
  v.toward_viewer = -look;
  v.up = axis == "z" ? Vec3d{0, 1, 0} : Vec3d{0, 0, 1};
  v.right = cross(v.up, v.toward_viewer);
  return v;
}

Projection fit_projection(const ViewAxes& axes, const std::vector<Vec3d>& points, int width,
                          int height, int margin) {
  if (width <= 2 * margin || height <= 2 * margin)
    throw std::invalid_argument("the image (" + std::to_string(width) + " x " +
                                std::to_string(height) + " px) must exceed twice the margin of " +
                                std::to_string(margin) + " px");
  double lo_r = std::numeric_limits<double>::max(), hi_r = -lo_r;
  double lo_u = lo_r, hi_u = -lo_r;
  for (const Vec3d& p : points) {
    lo_r = std::min(lo_r, dot(axes.right, p));
    hi_r = std::max(hi_r, dot(axes.right, p));
    lo_u = std::min(lo_u, dot(axes.up, p));
    hi_u = std::max(hi_u, dot(axes.up, p));
  }
  if (points.empty()) lo_r = hi_r = lo_u = hi_u = 0;
  Projection p;
  p.axes = axes;
  p.width = width;
  p.height = height;
  const double room_c = width - 1 - 2.0 * margin, room_r = height - 1 - 2.0 * margin;
  const double extent_r = hi_r - lo_r, extent_u = hi_u - lo_u;
  p.pixels_per_metre = 1000;  // 1 px per mm when the points have no extent
  if (extent_r > 0 || extent_u > 0)
    p.pixels_per_metre = std::min(extent_r > 0 ? room_c / extent_r : room_r / extent_u,
                                  extent_u > 0 ? room_r / extent_u : room_c / extent_r);
  // The centre of the extent at the centre of the image.
  p.origin_column = 0.5 * (width - 1) - p.pixels_per_metre * 0.5 * (lo_r + hi_r);
  p.origin_row = 0.5 * (height - 1) + p.pixels_per_metre * 0.5 * (lo_u + hi_u);
  return p;
}

}  // namespace talus
