#include "solver/render/frame_image.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace talus {
namespace {

constexpr int kShift = 4;  // fixed-point bits of the corners: 1/16 px
constexpr double kOne = 1 << kShift;

cv::Point fixed_point(const PixelPoint& p) {
  return {static_cast<int>(std::lround(p.column * kOne)),
          static_cast<int>(std::lround(p.row * kOne))};
}

}  // namespace

FrameImage render_frame_image(const FrameDrawing& drawing, int width, int height,
                              std::size_t particles, const std::string& label) {
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat owner(height, width, CV_32SC1, cv::Scalar(-1));  // the particle each pixel shows
  std::vector<cv::Point> corners;
  for (const DrawPolygon& polygon : drawing.polygons) {
    corners.clear();
    for (const PixelPoint& p : polygon.corners) corners.push_back(fixed_point(p));
    const cv::Scalar bgr(polygon.color.b, polygon.color.g, polygon.color.r);
    if (polygon.outline) {  // one pixel wide, 8-connected, part of its particle
      const std::vector<std::vector<cv::Point>> line{corners};
      cv::polylines(image, line, true, bgr, 1, cv::LINE_8, kShift);
      cv::polylines(owner, line, true, cv::Scalar(polygon.particle), 1, cv::LINE_8, kShift);
      continue;
    }
    cv::fillConvexPoly(image, corners, bgr, cv::LINE_8, kShift);
    cv::fillConvexPoly(owner, corners, cv::Scalar(polygon.particle), cv::LINE_8, kShift);
  }
  FrameImage result;
  result.visible_pixels.assign(particles, 0);
  for (int r = 0; r < height; ++r) {
    const int* row = owner.ptr<int>(r);
    for (int c = 0; c < width; ++c)
      if (row[c] >= 0 && static_cast<std::size_t>(row[c]) < particles)
        ++result.visible_pixels[row[c]];
  }
  for (const DrawSegment& s : drawing.wall_edges)
    cv::line(image, fixed_point(s.a), fixed_point(s.b), cv::Scalar(70, 70, 70), 1, cv::LINE_AA,
             kShift);
  if (!label.empty())
    cv::putText(image, label, cv::Point(6, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes))
    throw std::runtime_error("OpenCV could not encode the PNG");
  result.png.assign(bytes.begin(), bytes.end());
  return result;
}

}  // namespace talus
