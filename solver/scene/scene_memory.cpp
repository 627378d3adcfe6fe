#include "solver/scene/scene_memory.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_loader.hpp"

namespace talus {

MemoryEstimate estimate_scene_memory(const Scene& scene) {
  MemoryEstimate e;
  e.particles = scene_particle_count(scene);
  e.bytes = e.particles * kBytesPerParticle;
  const auto consider = [&](double count, const SourceRef& source) {
    if (count > e.largest_particles) e.largest_particles = count, e.largest = source;
  };
  // The explicit list counts as one entry, named by its first particle.
  if (!scene.particles.empty()) consider(double(scene.particles.size()), scene.particles[0].source);
  for (const LatticeRequest& l : scene.lattices)
    consider(lattice_point_count(l.region, l.spacing), l.source);
  for (const RandomFillRequest& f : scene.random_fills) consider(double(f.count), f.source);
  for (const FeedRequest& f : scene.feeds)
    consider(feed_particle_count(f.rate, f.start, f.stop), f.source);
  return e;
}

std::uint64_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return std::uint64_t(pages) * std::uint64_t(page_size);
}

void check_scene_memory(const Scene& scene, std::uint64_t available_bytes) {
  const MemoryEstimate e = estimate_scene_memory(scene);
  if (available_bytes == 0 || e.bytes <= double(available_bytes)) return;
  const SourceRef& at = e.largest;
  throw SceneError(
      at.file.empty() ? scene.file : at.file, at.line, at.column, at.key,
      fmt::format("the scene would create {:.0f} particles ({:.0f} of them from this entry), an "
                  "estimated {:.0f} bytes ({:.0f} a particle), more than the {} bytes of memory "
                  "this machine has; ask for fewer particles",
                  e.particles, e.largest_particles, e.bytes, kBytesPerParticle, available_bytes));
}

}  // namespace talus
