// The largest counts a scene may ask for, and the counts it derives from real numbers (steps from
// time.end / time.step, lattice points from box / spacing, feed particles from rate x time),
// computed in doubles and compared with the limits before any integer conversion, so that no
// conversion overflows (a step count above 2^63 once ran 0 steps; a feed above 2^63 inserted
// nothing). docs/scenes.md, "Limits", lists them.
#pragma once

#include <array>
#include <string>

#include "solver/scene/scene.hpp"

namespace talus {

// Steps of a run: at most 2^53, so that the step index and the time step x index stay exact in a
// double (every integer up to 2^53 is one), and the count fits a long long with room to spare.
constexpr long long kMaxSteps = 1LL << 53;
// Particles a scene may create (initial ones and all that its feeds insert): the solvers index
// particles and their candidate pairs with int (neighbor/contact_pairs.hpp), so 2^31 - 1.
constexpr long long kMaxParticles = 2147483647LL;
// Seeds: non-negative and below 2^63, so that the scene's seed plus an entry's place still fits
// the 64-bit generator's seed without wrapping.
constexpr long long kMaxSeed = 9223372036854775807LL;

// "2^53 = 9007199254740992", "2^31 - 1 = 2147483647", "2^63 - 1 = 9223372036854775807".
std::string describe_limit(long long limit);

// What is wrong with a run from 0 to end_time in steps of time_step: "" when its step count,
// round(end_time / time_step) computed in doubles, is at most kMaxSteps, else a message giving
// the count and the limit.
std::string step_count_problem(double end_time, double time_step);
// The run's steps, round(end_time / time_step). Throws std::overflow_error naming `what` (the
// key that set the end time) when the count is above kMaxSteps.
long long checked_step_count(double end_time, double time_step, const std::string& what);
// The steps of the scene's run, time.end / time.step (checked: the loader refused larger).
long long scene_step_count(const Scene& scene);

// Lattice points per axis (floor(size / spacing), at least 1, as doubles: a huge box over a fine
// spacing gives a count that no integer type holds) and their product.
std::array<double, 3> lattice_dimensions(const Region& box, const Vec3d& spacing);
double lattice_point_count(const Region& box, const Vec3d& spacing);

// The most particles a feed inserts: floor(rate (stop - start)), as a double.
double feed_particle_count(double rate, double start, double stop);

// Every particle the scene creates: its explicit list, its lattices' points, its random fills'
// counts and all that its feeds insert by their stop times, as a double (no overflow).
double scene_particle_count(const Scene& scene);

}  // namespace talus
