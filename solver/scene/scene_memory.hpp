// What a scene will allocate, estimated from its particle count before any particle is made, so
// that a scene too large for the machine is refused with its numbers (which entry, how many
// particles, how many bytes) instead of a std::bad_alloc after the machine's memory is gone.
#pragma once

#include <cstdint>

#include "solver/scene/scene.hpp"

namespace talus {

// Host bytes a particle costs at the peak of a production run in double precision, measured
// (docs/scenes.md, "Limits"): 216,000 spheres on a cubic lattice touching their 6 neighbours
// (2.95 pair contacts a particle, as in a packed bed) peak at 1842 bytes a particle above a run of
// 1,000, the step's arrays (particle_array_bytes) 1841 -- three quarters of it the contacts'
// records (2 x 200 bytes each), keys, histories (72) and candidate pairs; without contacts
// (216,000 dodecahedra apart) 475 and 440. Rounded up to 2048: about 11 % above a packed bed,
// so that what is refused cannot fit.
constexpr double kBytesPerParticle = 2048;

struct MemoryEstimate {
  double particles = 0;  // as scene_particle_count (scene_limits.hpp)
  double bytes = 0;      // particles x kBytesPerParticle
  // The entry that creates the most particles (the one a message names), and how many.
  SourceRef largest;
  double largest_particles = 0;
};

MemoryEstimate estimate_scene_memory(const Scene& scene);

// The machine's physical memory, sysconf(_SC_PHYS_PAGES) x sysconf(_SC_PAGESIZE); 0 when the
// system does not say.
std::uint64_t physical_memory_bytes();

// Throws SceneError at the entry that creates the most particles when the estimate exceeds
// `available_bytes` (0: unknown, never refused), naming the count, the estimated bytes and the
// memory available.
void check_scene_memory(const Scene& scene, std::uint64_t available_bytes);

}  // namespace talus
