// The scene's feeds as both backends run them (scene/feeder.hpp): one Feeder per feed, the walls'
// meshes at t = 0 and each template's bounding radius, asked in turn at the start of a step so
// that each feed keeps off the particles there and off what the feeds before it inserted. The
// backends only append what insert() returns; the checkpoint's feed states go through save() and
// restore().
#pragma once

#include <string>
#include <vector>

#include "solver/core/vec3.hpp"
#include "solver/domain/domain.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/scene.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus {

class Feeding {
 public:
  explicit Feeding(const Scene& scene);

  bool empty() const { return feeders_.empty(); }

  // Whether some feed has a particle due at `time` and is not waiting after a call that found no
  // room (Feeder::ready); when none has, insert() would return nothing and the caller need not
  // gather the positions.
  bool due(double time) const;

  // The particles the feeds insert at `time` (feed by feed, in order) among the particles now at
  // `positions` (world, m) with templates `template_ids`, those the local `domain` owns. Both
  // steps ask due() first, so that a step with nothing due gathers no positions.
  std::vector<ParticleState> insert(double time, std::vector<Vec3d> positions,
                                    const std::vector<int>& template_ids, const Domain& domain);
  // Every particle the feeds insert at `time` among the particles at `positions` (every rank's:
  // the decomposed step gathers them), whoever owns it.
  std::vector<ParticleState> insert_all(double time, std::vector<Vec3d> positions,
                                        const std::vector<int>& template_ids);

  // Each feed's progress at `time`, in the scene's order.
  std::vector<FeedCount> counts(double time) const;

  std::vector<std::string> save() const;
  // Throws CheckpointError naming `source` (the checkpoint file) and its section feeds.states
  // when the number of states is not the scene's number of feeds or a state cannot be read.
  void restore(const std::vector<std::string>& states, const std::string& source = "");

 private:
  // Where no wall moves: each feed's walls at `time` as its placement grid (Feeder::walls_grid),
  // kept until a wall's present triangles change (an outlet opening). A fed silo's feed is due
  // most steps; cutting its 65,000 triangles into the grid at each call was most of the call
  // (bench_setup's feed_attempt).
  const std::vector<PlacementGrid>& walls_grids(double time);

  const Scene& scene_;
  std::vector<Feeder> feeders_;
  std::vector<WallMesh> walls_;       // at t = 0, moved to the step's time by walls_at
  std::vector<double> radii_;         // per template: its bounding radius in double
  bool walls_move_ = false;           // some wall has a motion
  std::vector<PlacementGrid> grids_;  // per feed, of the walls' present triangles (static walls)
  std::vector<int> grids_present_;    // those present triangles, per wall
};

}  // namespace talus
