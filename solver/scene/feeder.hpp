// Particles inserted during a run by a `feed` entry (FeedRequest): at `rate` per second from
// `start` to `stop`, at random places in the region where their bounding spheres overlap no
// particle and no wall triangle.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "solver/scene/placement.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

// How many random positions a feed tries for one particle in one step before it leaves the
// particle for a later step.
constexpr int kFeedAttemptsPerParticle = 1000;

// A feed whose call placed none of its due particles (its region full) waits before it tries
// again: 2 steps after the first such call, then twice as long after each one that follows, up
// to this many steps; a call that places some tries again at the next step, one that places all
// waits for nothing. A blocked call costs the step a download of every position and 1000 random
// tries on the host (0.5 ms for a silo's feed, bench_setup's feed_attempt, against a step of 1 to
// 2 ms on the GPU); waiting, a blocked feed costs almost nothing, and a region that frees is seen
// within this many steps (0.4 to 0.6 ms at the fixed bed's and the silo's steps).
constexpr int kFeedMaxWaitSteps = 32;

// A feed's progress at a time: the particles it has inserted, those due by then
// (Feeder::due) and its whole count (due at its stop). inserted < due: it has fallen behind (its
// region had no room for the rest).
struct FeedCount {
  long long inserted = 0, due = 0, total = 0;
};

class Feeder {
 public:
  // The request, its template's bounding radius (m) and the run's time step (s), in which a
  // blocked feed's waits are counted (kFeedMaxWaitSteps; 0: it never waits).
  Feeder(const FeedRequest& request, double bounding_radius, double time_step = 0);
  // For scene.feeds[feed_index], with the scene's time step.
  Feeder(const Scene& scene, int feed_index);

  // How many particles should have been inserted by time t (s): floor(rate (min(t, stop) -
  // start)), 0 before start. Computed from t, never accumulated, so it does not drift.
  long long due(double time) const;
  // Whether a call at `time` would try to place particles: some are due and the feed is not
  // waiting after a call that placed none (kFeedMaxWaitSteps).
  bool ready(double time) const;

  // The particles to insert at the step at time t: due(t) - inserted(), each placed with its
  // bounding sphere inside the region, off the given particles (centres and bounding radii,
  // world) and off the walls' triangles (world coordinates at t), and off each other. A particle
  // without a free place after kFeedAttemptsPerParticle tries stays due for the next call, and
  // so do the ones after it; a call that places none makes the feed wait (kFeedMaxWaitSteps),
  // and a call while it waits returns nothing. Deterministic: the same feeder state and inputs
  // give the same bits.
  std::vector<ParticleState> insert(double time, const std::vector<Vec3d>& positions,
                                    const std::vector<double>& bounding_radii,
                                    const std::vector<TriangleMesh>& walls);
  // The same with the walls given as walls_grid(walls): a copy of it takes the particles. A
  // caller whose walls do not change keeps the grid instead of cutting every wall's triangles
  // into it at each call. The grid only finds the free places; their tests are exact, so the
  // particles placed are the same bits whichever way the walls come.
  std::vector<ParticleState> insert(double time, const std::vector<Vec3d>& positions,
                                    const std::vector<double>& bounding_radii,
                                    const PlacementGrid& walls_grid);
  // insert()'s placement grid over the feed region's box of centres with the walls' triangles in
  // it (those within reach of the box) and no particle.
  PlacementGrid walls_grid(const std::vector<TriangleMesh>& walls) const;

  long long inserted() const { return inserted_; }
  FeedCount count(double time) const { return {inserted_, due(time), total_}; }
  bool finished() const;  // every particle of the feed has been inserted

  // The state that changes during a run (the count inserted, the wait and the generator), as one
  // line of text; restore() on a feeder made from the same request continues exactly as this one
  // would. It also reads the state of a talus before the waits (talus-feeder-v1: no wait).
  // Throws std::runtime_error naming the request when the text is not a saved state.
  std::string save() const;
  void restore(const std::string& state);

 private:
  FeedRequest request_;
  double radius_;
  long long total_;  // due(stop)
  long long inserted_ = 0;
  double time_step_;
  int wait_steps_ = 0;           // the last wait, steps (0: the last call placed all it owed)
  double next_try_ = -HUGE_VAL;  // while time < next_try_ the feed waits
  PlacementRandom random_;
};

}  // namespace talus
