#include "solver/scene/feeder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace talus {
namespace {

constexpr const char* kStateTag = "talus-feeder-v2";
constexpr const char* kStateTagWithoutWait = "talus-feeder-v1";  // before the waits

}  // namespace

Feeder::Feeder(const FeedRequest& request, double bounding_radius, double time_step)
    : request_(request),
      radius_(bounding_radius),
      total_(0),
      time_step_(time_step),
      random_(request.seed) {
  total_ = due(request.stop);
}

Feeder::Feeder(const Scene& scene, int feed_index)
    : Feeder(scene.feeds.at(feed_index),
             scene.templates.at(scene.feeds.at(feed_index).template_index).bounding_radius,
             scene.time_step) {}

long long Feeder::due(double time) const {
  if (!(time > request_.start)) return 0;
  const double until = std::min(time, request_.stop);
  return (long long)std::floor(request_.rate * (until - request_.start));
}

bool Feeder::ready(double time) const {
  return due(time) > inserted_ && !(time < next_try_);
}

bool Feeder::finished() const {
  return inserted_ >= total_;
}

PlacementGrid Feeder::walls_grid(const std::vector<TriangleMesh>& walls) const {
  const CentreSampler sampler(request_.region, radius_);
  PlacementGrid grid(sampler.low(), sampler.high(), radius_, 0);
  for (const TriangleMesh& wall : walls) grid.add_mesh(wall);
  return grid;
}

std::vector<ParticleState> Feeder::insert(double time, const std::vector<Vec3d>& positions,
                                          const std::vector<double>& bounding_radii,
                                          const std::vector<TriangleMesh>& walls) {
  if (!ready(time)) return {};
  return insert(time, positions, bounding_radii, walls_grid(walls));
}

std::vector<ParticleState> Feeder::insert(double time, const std::vector<Vec3d>& positions,
                                          const std::vector<double>& bounding_radii,
                                          const PlacementGrid& walls_grid) {
  std::vector<ParticleState> added;
  const long long wanted = due(time) - inserted_;
  if (wanted <= 0 || time < next_try_) return added;
  if (positions.size() != bounding_radii.size())
    throw std::invalid_argument(request_.source.where() + ": feed given " +
                                std::to_string(positions.size()) + " positions but " +
                                std::to_string(bounding_radii.size()) + " bounding radii");
  const CentreSampler sampler(request_.region, radius_);
  // The grid sized for what is wanted, but never for more spheres than the box has cells a reach
  // (two radii) wide: a feed that has fallen far behind (a backlog of thousands) would otherwise
  // allocate and clear millions of cells at every call. The size changes the cells, not which
  // places are free.
  const Vec3d extent = sampler.high() - sampler.low();
  double box_cells = 1;
  for (int k = 0; k < 3; ++k) box_cells *= std::floor(extent[k] / (2 * radius_)) + 1;
  const double expected = std::min(double(wanted), box_cells) + 64;
  PlacementGrid grid(sampler.low(), sampler.high(), radius_, std::size_t(expected));
  grid.take_triangles_of(walls_grid);
  for (std::size_t i = 0; i < positions.size(); ++i)
    grid.add_sphere(positions[i], bounding_radii[i]);
  for (long long n = 0; n < wanted; ++n) {
    ParticleState p;
    if (!place_one(sampler, grid, random_, kFeedAttemptsPerParticle, request_.template_index,
                   request_.random_orientation, request_.velocity, request_.source, p)) {
      break;  // the region is full now; the rest stay due
    }
    added.push_back(p);
  }
  inserted_ += (long long)added.size();
  // Placed none: wait 2, 4, ... up to kFeedMaxWaitSteps steps (half a step short of the next
  // try, so that the step's time, a sum of steps, is past it whatever its round-off); placed
  // some but not all: try again at the next step; all: no wait.
  if ((long long)added.size() == wanted) {
    wait_steps_ = 0;
  } else {
    wait_steps_ = added.empty() ? std::min(std::max(2, 2 * wait_steps_), kFeedMaxWaitSteps) : 1;
  }
  next_try_ = wait_steps_ > 0 ? time + (wait_steps_ - 0.5) * time_step_ : -HUGE_VAL;
  return added;
}

std::string Feeder::save() const {
  // The engine's text form is fixed by the standard ([rand.req.eng]): the same state reads back
  // on any standard library.
  // The next try's time as its bits: exact, and -inf as well as any other double.
  std::uint64_t next = 0;
  std::memcpy(&next, &next_try_, sizeof next);
  std::ostringstream text;
  text << kStateTag << ' ' << inserted_ << ' ' << wait_steps_ << ' ' << next << ' '
       << random_.engine();
  return text.str();
}

void Feeder::restore(const std::string& state) {
  std::istringstream text(state);
  std::string tag;
  long long inserted = -1;
  int wait = 0;
  std::uint64_t next = 0;
  const double no_wait = -HUGE_VAL;
  std::memcpy(&next, &no_wait, sizeof next);
  std::mt19937_64 engine;
  text >> tag >> inserted;
  if (tag == kStateTag) text >> wait >> next;
  text >> engine;
  double next_try = 0;
  std::memcpy(&next_try, &next, sizeof next_try);
  if ((tag != kStateTag && tag != kStateTagWithoutWait) || text.fail() || inserted < 0 ||
      inserted > total_ || wait < 0 || wait > kFeedMaxWaitSteps || std::isnan(next_try) ||
      !(text >> std::ws).eof())
    throw std::runtime_error(request_.source.where() + ": expected a saved feed state ('" +
                             kStateTag + " <inserted> <wait> <next try> <generator>'), got '" +
                             state.substr(0, 60) + (state.size() > 60 ? "...'" : "'"));
  inserted_ = inserted;
  wait_steps_ = wait;
  next_try_ = next_try;
  random_.engine() = engine;
}

}  // namespace talus
