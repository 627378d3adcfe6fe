#include "solver/step/feeding.hpp"

#include "solver/io/checkpoint.hpp"

namespace talus {

Feeding::Feeding(const Scene& scene) : scene_(scene) {
  for (std::size_t f = 0; f < scene.feeds.size(); ++f)
    feeders_.emplace_back(scene, static_cast<int>(f));
  if (feeders_.empty()) return;
  walls_ = make_wall_meshes(scene);
  for (const ParticleTemplate& t : scene.templates) radii_.push_back(t.bounding_radius);
  for (const WallSpec& wall : scene.walls)
    walls_move_ = walls_move_ || wall.motion.kind != WallMotion::Kind::none;
}

const std::vector<PlacementGrid>& Feeding::walls_grids(double time) {
  std::vector<int> present(walls_.size());
  for (std::size_t w = 0; w < walls_.size(); ++w)
    present[w] = present_triangle_count(scene_.walls[w], walls_[w], time);
  if (grids_.empty() || present != grids_present_) {
    const std::vector<TriangleMesh> now = walls_at(scene_, walls_, time);
    grids_.clear();
    for (const Feeder& feeder : feeders_) grids_.push_back(feeder.walls_grid(now));
    grids_present_ = present;
  }
  return grids_;
}

bool Feeding::due(double time) const {
  for (const Feeder& feeder : feeders_)
    if (feeder.ready(time)) return true;
  return false;
}

std::vector<ParticleState> Feeding::insert(double time, std::vector<Vec3d> positions,
                                           const std::vector<int>& template_ids,
                                           const Domain& domain) {
  // This rank's share: every rank runs the same feeders, and each appends what it owns.
  std::vector<ParticleState> owned;
  for (const ParticleState& p : insert_all(time, std::move(positions), template_ids))
    if (domain.owns(p.position)) owned.push_back(p);
  return owned;
}

std::vector<ParticleState> Feeding::insert_all(double time, std::vector<Vec3d> positions,
                                               const std::vector<int>& template_ids) {
  std::vector<ParticleState> added;
  std::vector<double> radii;
  radii.reserve(positions.size());
  for (const int t : template_ids) radii.push_back(radii_[t]);
  const std::vector<TriangleMesh> moved =
      walls_move_ ? walls_at(scene_, walls_, time) : std::vector<TriangleMesh>();
  const std::vector<PlacementGrid>* grids = walls_move_ ? nullptr : &walls_grids(time);
  for (std::size_t f = 0; f < feeders_.size(); ++f) {
    Feeder& feeder = feeders_[f];
    const std::vector<ParticleState> more = grids
                                                ? feeder.insert(time, positions, radii, (*grids)[f])
                                                : feeder.insert(time, positions, radii, moved);
    for (const ParticleState& p : more) {  // the next feed keeps off these too
      positions.push_back(p.position);
      radii.push_back(radii_[p.template_index]);
    }
    added.insert(added.end(), more.begin(), more.end());
  }
  return added;
}

std::vector<FeedCount> Feeding::counts(double time) const {
  std::vector<FeedCount> counts;
  for (const Feeder& feeder : feeders_) counts.push_back(feeder.count(time));
  return counts;
}

std::vector<std::string> Feeding::save() const {
  std::vector<std::string> states;
  for (const Feeder& feeder : feeders_) states.push_back(feeder.save());
  return states;
}

void Feeding::restore(const std::vector<std::string>& states, const std::string& source) {
  if (states.size() != feeders_.size())
    throw_checkpoint_error(
        source, "feeds.states",
        "the checkpoint does not fit the scene: " + std::to_string(states.size()) +
            " feed states, the scene has " + std::to_string(feeders_.size()) + " feeds");
  for (std::size_t f = 0; f < feeders_.size(); ++f) {
    try {
      feeders_[f].restore(states[f]);
    } catch (const std::runtime_error& e) {  // Feeder's message names the feed in the scene
      throw_checkpoint_error(source, "feeds.states", "feed " + std::to_string(f) + ": " + e.what());
    }
  }
}

}  // namespace talus
