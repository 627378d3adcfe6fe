// The particles a scene starts with: its explicit list, then its lattices, then its random
// fills, each group in scene order (docs/scenes.md, "What the scene produces").
#pragma once

#include <cstdint>
#include <vector>

#include "solver/scene/scene.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus {

// How many random positions a fill tries for one particle before it gives up.
constexpr int kFillAttemptsPerParticle = 100000;

// All initial particles. A particle's global id is its index in the result. Random fills avoid
// the bounding spheres of every particle before them and the walls' triangles at t = 0 (closed
// outlet plates included). Throws std::runtime_error naming the request (source.where()) and
// how many it placed when a fill cannot be completed. Where the scene holds a list handed on by
// keep_initial_particles, the first call takes it (the scene's slot is then empty) instead of
// making the particles again.
std::vector<ParticleState> initial_particles(const Scene& scene);

// Hands `particles` (initial_particles(scene)'s result) on to the next initial_particles call on
// this scene or a copy of it: `talus run` checks the initial particles, then builds the solver,
// which would otherwise place a random fill of millions a second time (minutes on one core).
void keep_initial_particles(const Scene& scene, std::vector<ParticleState> particles);

// How many particles initial_particles(scene) makes, without placing them: the explicit list,
// every lattice's points and every random fill's count (a fill that cannot place them all
// throws, so a scene that ran has them all).
std::size_t initial_particle_count(const Scene& scene);

// The scene without its initial particles (no list, lattices or random fills), the rest as it
// is: what a resumed run builds its step from, since the checkpoint's state replaces them.
// Placing a million-particle random fill again took most of such a run's start. Its
// left_out_particles says how many it lacks (the steps check a checkpoint's count against the
// scene's: step_state.hpp, checkpoint_count_fits).
Scene without_initial_particles(const Scene& scene);

// How a random fill runs; the particles it places do not depend on either. `threads`: host
// threads that test candidates (<= 0: all, host_parallel.hpp); `batch`: candidates drawn and
// tested together (<= 0: 16 a thread, at least 64).
struct FillWork {
  int threads = 0;
  int batch = 0;
};

// The parts, for tests and tools. lattice_particles: the points min + spacing (i + 1/2) that
// fit in the box, x fastest, then y, then z. random_fill_particles: appends to `particles`
// (whose bounding radii it reads from the scene's templates). Candidate centres come from one
// generator seeded with the fill's seed, orientations from a second one (seeded from it by
// fill_orientation_seed), so the k-th candidate does not depend on which earlier ones were kept:
// a batch of candidates is tested on several threads against the spheres placed before it, then
// kept in order, each also tested against those kept earlier in its batch. The result is that of
// trying the candidates one at a time.
std::vector<ParticleState> lattice_particles(const LatticeRequest& lattice);
void random_fill_particles(const Scene& scene, const RandomFillRequest& fill,
                           const std::vector<WallMesh>& walls,
                           std::vector<ParticleState>& particles, const FillWork& work = {});
// The seed of a fill's orientation generator: splitmix64 of its seed (a fixed bijection whose
// outputs differ from the seed in about half their bits).
std::uint64_t fill_orientation_seed(std::uint64_t seed);

}  // namespace talus
