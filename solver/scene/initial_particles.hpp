// The particles a scene starts with: its explicit list, then its lattices, then its random
// fills, each group in scene order (docs/scenes.md, "What the scene produces").
#pragma once

#include <vector>

#include "solver/scene/scene.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus {

// How many random positions a fill tries for one particle before it gives up.
constexpr int kFillAttemptsPerParticle = 100000;

// All initial particles. A particle's global id is its index in the result. Random fills avoid
// the bounding spheres of every particle before them and the walls' triangles at t = 0 (closed
// outlet plates included). Throws std::runtime_error naming the request (source.where()) and
// how many it placed when a fill cannot be completed.
std::vector<ParticleState> initial_particles(const Scene& scene);

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

// The parts, for tests and tools. lattice_particles: the points min + spacing (i + 1/2) that
// fit in the box, x fastest, then y, then z. random_fill_particles: appends to `particles`
// (whose bounding radii it reads from the scene's templates).
std::vector<ParticleState> lattice_particles(const LatticeRequest& lattice);
void random_fill_particles(const Scene& scene, const RandomFillRequest& fill,
                           const std::vector<WallMesh>& walls,
                           std::vector<ParticleState>& particles);

}  // namespace talus
