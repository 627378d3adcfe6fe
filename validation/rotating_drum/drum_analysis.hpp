// What the quasi-2D drum case (method paper §3.4, Fig. 15) measures from particle centres in the
// image plane, the same way whether the centres come from the DEM (the trajectories, projected)
// or from the pictures (image_tracking.hpp): the velocity field on a grid of cells, the agreement
// of two fields (R^2), the dynamic angle of repose of the free surface and the highest lift on the
// rising side. Plain numbers, no OpenCV.
//
// Coordinates: a along the image's right, b along its up (m), both measured from the drum's
// axis; the camera looks along the axis, so b is height.
#pragma once

#include <utility>
#include <vector>

namespace talus::validation {

struct PlanePoint {
  double a = 0, b = 0;  // m from the drum's axis: right, up
};

// Velocities averaged per cell of a square grid centred on the drum's axis.
class VelocityField {
 public:
  // cells x cells cells of side `cell` (m), centred on the axis.
  VelocityField(int cells, double cell);
  // A sample: the velocity (u along a, w along b; m/s) seen at `at`; outside the grid, ignored.
  void add(const PlanePoint& at, double u, double w);
  int cells() const { return cells_; }
  double cell() const { return cell_; }
  // The cell's centre, its sample count and its mean velocity (0 where it has no sample).
  PlanePoint centre(int i, int j) const;
  long long count(int i, int j) const { return count_[index(i, j)]; }
  double mean_u(int i, int j) const;
  double mean_w(int i, int j) const;

 private:
  int index(int i, int j) const { return j * cells_ + i; }
  int cells_;
  double cell_;
  std::vector<double> sum_u_, sum_w_;
  std::vector<long long> count_;
};

// The coefficient of determination of `measured` against `truth` over the cells where both have
// at least `min_samples` samples, both components together:
//   R^2 = 1 - sum (v_measured - v_truth)^2 / sum (v_truth - mean v_truth)^2,
// the mean taken per component. `used` (optional) receives the number of cells used. NaN when no
// cell qualifies or the truth does not vary.
double field_r_squared(const VelocityField& measured, const VelocityField& truth, int min_samples,
                       int* used = nullptr);

// The dynamic angle of repose (degrees, 0 to 90) of one frame's bed: the bed's surface in each
// strip of width `strip` (m) across |a| <= `half_width` is the highest centre in the strip that
// has another centre within `neighbour` (m) — a particle of the bed touches others, one in flight
// over it mostly does not —; the angle is that of the least-squares line through those tops.
// NaN with fewer than three strips.
double repose_angle(const std::vector<PlanePoint>& centres, double strip, double half_width,
                    double neighbour);

// The highest lift (degrees): the largest elevation atan2(b, |a|) above the horizontal through the
// axis of a centre within `band` (m) of the drum's wall (radius `radius`) on the rising side (a > 0
// when `rising_right`), -90 when none is there.
double highest_lift(const std::vector<PlanePoint>& centres, double radius, double band,
                    bool rising_right);

// Detections of two consecutive frames matched one to one: pairs (k in `from`, m in `to`) where
// each is the other's nearest and they are at most `max_distance` apart (the same units).
// Nearest-neighbour particle tracking, valid while a particle moves less between frames than half
// the distance between neighbours.
std::vector<std::pair<int, int>> match_nearest(const std::vector<PlanePoint>& from,
                                               const std::vector<PlanePoint>& to,
                                               double max_distance);

}  // namespace talus::validation
