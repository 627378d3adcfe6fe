#include "validation/rotating_drum/image_tracking.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace talus::validation {
namespace {

struct Seed {
  double column, row, depth;
};

// Local maxima of the distance image at least `min_depth` deep and the highest within `radius`
// px (a square window); a flat top (several equal pixels) gives one seed at its centroid, and of
// two seeds closer than `radius` the shallower goes.
std::vector<Seed> find_seeds(const cv::Mat& distance, double min_depth, double radius) {
  const int r = std::max(1, static_cast<int>(std::lround(radius)));
  cv::Mat dilated, peaks;
  cv::dilate(distance, dilated,
             cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1)));
  cv::compare(distance, dilated, peaks, cv::CMP_GE);
  cv::Mat deep;
  cv::compare(distance, min_depth, deep, cv::CMP_GE);
  cv::bitwise_and(peaks, deep, peaks);
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(peaks, labels, stats, centroids, 8, CV_32S);
  std::vector<Seed> seeds;
  for (int k = 1; k < count; ++k) {  // 0: the background
    const double c = centroids.at<double>(k, 0), w = centroids.at<double>(k, 1);
    const int ci = std::clamp(static_cast<int>(std::lround(c)), 0, distance.cols - 1);
    const int ri = std::clamp(static_cast<int>(std::lround(w)), 0, distance.rows - 1);
    seeds.push_back({c, w, distance.at<float>(ri, ci)});
  }
  std::sort(seeds.begin(), seeds.end(),
            [](const Seed& x, const Seed& y) { return x.depth > y.depth; });
  std::vector<Seed> kept;
  for (const Seed& s : seeds) {
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const Seed& k) {
      return std::hypot(k.column - s.column, k.row - s.row) < radius;
    });
    if (!near) kept.push_back(s);
  }
  return kept;
}

}  // namespace

std::vector<ImageDetection> detect_particles(const std::string& path,
                                             const DetectionSettings& settings) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty())
    throw std::runtime_error(path + ": cannot be read as an image (expected a PNG frame)");
  std::vector<cv::Mat> channels;
  cv::split(image, channels);  // B, G, R
  cv::Mat excess, mask;
  cv::subtract(channels[0], channels[2], excess);  // saturates at 0
  cv::threshold(excess, mask, settings.min_blue_excess, 255, cv::THRESH_BINARY);
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::Mat::ones(3, 3, CV_8U));

  cv::Mat distance;
  cv::distanceTransform(mask, distance, cv::DIST_L2, cv::DIST_MASK_5);
  const std::vector<Seed> seeds =
      find_seeds(distance, 0.4 * settings.inradius, 0.8 * settings.inradius);
  if (seeds.empty()) return {};

  // Each particle pixel to its nearest seed: the distance transform of the seeds' complement
  // labels every pixel with the seed (a one-pixel component each) nearest to it.
  cv::Mat not_seed(image.rows, image.cols, CV_8U, cv::Scalar(255));
  for (const Seed& s : seeds)
    not_seed.at<unsigned char>(static_cast<int>(std::lround(s.row)),
                               static_cast<int>(std::lround(s.column))) = 0;
  cv::Mat to_seed, owner;
  cv::distanceTransform(not_seed, to_seed, owner, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_CCOMP);
  double highest = 0;
  cv::minMaxLoc(owner, nullptr, &highest);
  std::vector<double> sum_c(static_cast<std::size_t>(highest) + 1, 0.0), sum_r(sum_c);
  std::vector<long long> pixels(sum_c.size(), 0);
  for (int r = 0; r < image.rows; ++r) {
    const unsigned char* m = mask.ptr<unsigned char>(r);
    const int* o = owner.ptr<int>(r);
    for (int c = 0; c < image.cols; ++c)
      if (m[c] && o[c] > 0) {
        sum_c[o[c]] += c;
        sum_r[o[c]] += r;
        ++pixels[o[c]];
      }
  }
  std::vector<ImageDetection> found;
  for (std::size_t k = 1; k < pixels.size(); ++k)
    if (pixels[k] > 0)
      found.push_back({sum_c[k] / double(pixels[k]), sum_r[k] / double(pixels[k]), pixels[k]});
  return found;
}

}  // namespace talus::validation
