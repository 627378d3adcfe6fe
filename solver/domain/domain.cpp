#include "solver/domain/domain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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
