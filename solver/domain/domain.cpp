#include "solver/domain/domain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "solver/domain/communicator.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

namespace {

double component(const Vec3d& v, int axis) {
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

void set_component(Vec3d& v, int axis, double value) {
  (axis == 0 ? v.x : (axis == 1 ? v.y : v.z)) = value;
}

}  // namespace

bool Box::bounded() const {
  return std::isfinite(min.x) && std::isfinite(min.y) && std::isfinite(min.z) &&
         std::isfinite(max.x) && std::isfinite(max.y) && std::isfinite(max.z);
}

bool Box::contains(const Vec3d& x) const {
  return x.x >= min.x && x.x < max.x && x.y >= min.y && x.y < max.y && x.z >= min.z && x.z < max.z;
}

Box Box::expanded(double margin) const {
  Box b;
  b.min = min - Vec3d(margin, margin, margin);
  b.max = max + Vec3d(margin, margin, margin);
  return b;
}

SlabDomain::SlabDomain(const Box& region, int axis, int ranks, int rank, double halo_width)
    : region_(region), axis_(axis), ranks_(ranks), rank_(rank), halo_(halo_width) {
  if (!region.bounded() ||
      !(region.min.x < region.max.x && region.min.y < region.max.y && region.min.z < region.max.z))
    throw std::invalid_argument("SlabDomain: the region must be a bounded, non-empty box");
  if (axis < 0 || axis > 2) throw std::invalid_argument("SlabDomain: axis must be 0, 1 or 2");
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("SlabDomain: rank " + std::to_string(rank) + " of " +
                                std::to_string(ranks));
}

int SlabDomain::owner(const Vec3d& x) const {
  if (!region_.contains(x)) return -1;
  // The slab whose upper face, computed as local_box computes it, lies above x: owner and
  // local_box agree to the bit (a division would round a point near a face to either side).
  const double lo = component(region_.min, axis_), hi = component(region_.max, axis_);
  for (int r = 0; r + 1 < ranks_; ++r)
    if (component(x, axis_) < lo + (hi - lo) * (r + 1) / ranks_) return r;
  return ranks_ - 1;
}

Box SlabDomain::local_box() const {
  const double lo = component(region_.min, axis_), hi = component(region_.max, axis_);
  Box b = region_;
  set_component(b.min, axis_, rank_ == 0 ? lo : lo + (hi - lo) * rank_ / ranks_);
  set_component(b.max, axis_, rank_ + 1 == ranks_ ? hi : lo + (hi - lo) * (rank_ + 1) / ranks_);
  return b;
}

RcbDomain::RcbDomain(const std::vector<Vec3d>& points, const Box& region, int ranks, int rank,
                     double halo_width, const Communicator* comm)
    : region_(region), rank_(rank), halo_(halo_width), comm_(comm) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("RcbDomain: rank " + std::to_string(rank) + " of " +
                                std::to_string(ranks));
  boxes_.resize(ranks);
  std::vector<Vec3d> inside;
  inside.reserve(points.size());
  for (const Vec3d& x : points)
    if (region.contains(x)) inside.push_back(x);
  build(std::move(inside), region, 0, ranks);
}

int RcbDomain::build(std::vector<Vec3d> points, const Box& box, int first_rank, int ranks) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (ranks == 1) {
    nodes_[index].rank = first_rank;
    boxes_[first_rank] = box;
    return index;
  }
  const int below_ranks = ranks / 2;
  // The axis of the points' widest extent; without points, the box's widest finite one (x when
  // none is finite).
  Vec3d lo = box.max, hi = box.min;
  for (const Vec3d& x : points) {
    for (int a = 0; a < 3; ++a) {
      set_component(lo, a, std::min(component(lo, a), component(x, a)));
      set_component(hi, a, std::max(component(hi, a), component(x, a)));
    }
  }
  if (points.empty()) lo = box.min, hi = box.max;
  int axis = 0;
  double widest = -1;
  for (int a = 0; a < 3; ++a) {
    const double extent = component(hi, a) - component(lo, a);
    if (std::isfinite(extent) && extent > widest) widest = extent, axis = a;
  }
  // The cut: below it the lower half's share of the points (rounded down), midway between the
  // last point below and the first above; ties all go above.
  std::vector<double> c;
  c.reserve(points.size());
  for (const Vec3d& x : points) c.push_back(component(x, axis));
  std::sort(c.begin(), c.end());
  const std::size_t k = c.size() * below_ranks / ranks;
  double cut;
  if (c.empty()) {
    const double a = component(box.min, axis), b = component(box.max, axis);
    cut = std::isfinite(a) && std::isfinite(b) ? 0.5 * (a + b)
          : std::isfinite(a)                   ? a
          : std::isfinite(b)                   ? b
                                               : 0.0;
  } else if (k == 0) {
    cut = c.front();
  } else if (k == c.size()) {
    cut = std::nextafter(c.back(), HUGE_VAL);
  } else {
    cut = 0.5 * (c[k - 1] + c[k]);
    if (!(cut > c[k - 1])) cut = c[k];  // neighbours one ulp apart
  }
  std::vector<Vec3d> below, above;
  for (const Vec3d& x : points) (component(x, axis) < cut ? below : above).push_back(x);
  Box below_box = box, above_box = box;
  set_component(below_box.max, axis, cut);
  set_component(above_box.min, axis, cut);
  nodes_[index].axis = axis;
  nodes_[index].cut = cut;
  const int b = build(std::move(below), below_box, first_rank, below_ranks);
  const int a = build(std::move(above), above_box, first_rank + below_ranks, ranks - below_ranks);
  nodes_[index].below = b;
  nodes_[index].above = a;
  return index;
}

int RcbDomain::owner(const Vec3d& x) const {
  if (!region_.contains(x)) return -1;
  int n = 0;
  while (nodes_[n].rank < 0)
    n = component(x, nodes_[n].axis) < nodes_[n].cut ? nodes_[n].below : nodes_[n].above;
  return nodes_[n].rank;
}

double RcbDomain::sum(double local) const {
  return comm_ ? comm_->sum(local) : local;
}
double RcbDomain::max(double local) const {
  return comm_ ? comm_->max(local) : local;
}

double squared_distance(const Box& b, const Vec3d& x) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double v = component(x, a);
    const double d = std::max({component(b.min, a) - v, 0.0, v - component(b.max, a)});
    d2 += d * d;
  }
  return d2;
}

double scene_halo_width(const Scene& scene) {
  double largest = 0;
  for (const ParticleTemplate& t : scene.templates) largest = std::max(largest, t.bounding_radius);
  const double skin = scene.skin ? *scene.skin : 0.2 * largest;
  return 2 * largest + skin;
}

std::unique_ptr<Domain> make_scene_domain(const Scene& scene) {
  return std::make_unique<SingleDomain>(scene.domain ? *scene.domain : Box(),
                                        scene_halo_width(scene));
}

}  // namespace talus
