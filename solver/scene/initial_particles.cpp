#include "solver/scene/initial_particles.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include "solver/core/host_parallel.hpp"
#include "solver/scene/placement.hpp"
#include "solver/scene/scene_limits.hpp"

namespace talus {

std::vector<ParticleState> lattice_particles(const LatticeRequest& lattice) {
  // The loader refused lattices of more than kMaxParticles points, so the counts fit an int.
  const std::array<double, 3> dimensions = lattice_dimensions(lattice.region, lattice.spacing);
  int count[3];
  for (int k = 0; k < 3; ++k) count[k] = static_cast<int>(dimensions[k]);
  PlacementRandom random(lattice.seed);
  std::vector<ParticleState> particles;
  particles.reserve(std::size_t(count[0]) * count[1] * count[2]);
  for (int z = 0; z < count[2]; ++z)
    for (int y = 0; y < count[1]; ++y)
      for (int x = 0; x < count[0]; ++x) {
        ParticleState p;
        p.template_index = lattice.template_index;
        const Vec3d index(x + 0.5, y + 0.5, z + 0.5);
        for (int k = 0; k < 3; ++k)
          p.position[k] = lattice.region.box_min[k] + lattice.spacing[k] * index[k];
        if (lattice.random_orientation) p.orientation = random.orientation();
        p.velocity = lattice.velocity;
        p.source = lattice.source;
        particles.push_back(p);
      }
  return particles;
}

std::uint64_t fill_orientation_seed(std::uint64_t seed) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ull;  // splitmix64 (Steele, Lea, Flood 2014)
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

void random_fill_particles(const Scene& scene, const RandomFillRequest& fill,
                           const std::vector<WallMesh>& walls,
                           std::vector<ParticleState>& particles, const FillWork& work) {
  const ParticleTemplate& shape = scene.templates.at(fill.template_index);
  const double radius = shape.bounding_radius;
  const CentreSampler sampler(fill.region, radius);
  PlacementGrid grid(sampler.low(), sampler.high(), radius,
                     particles.size() + std::size_t(fill.count));
  for (const ParticleState& p : particles)
    grid.add_sphere(p.position, scene.templates.at(p.template_index).bounding_radius);
  for (const WallMesh& wall : walls) grid.add_mesh(wall.mesh);
  PlacementRandom centres(fill.seed), turns(fill_orientation_seed(fill.seed));
  const int threads = host_thread_count(work.threads);
  // 16 candidates a thread: enough work between two joins (tens of microseconds), while the
  // serial pass's test against the batch's kept candidates (up to a batch of them) stays short.
  const int batch = work.batch > 0 ? work.batch : std::max(64, 16 * threads);
  // As PlacementGrid::add_sphere and is_free compare two spheres of the grid's radius, so that a
  // candidate is kept here exactly when is_free would say so with the batch's earlier ones added.
  const double reach = radius + radius, reach2 = reach * reach;
  std::vector<Vec3d> candidate(batch), kept;
  std::vector<char> clear(batch);
  kept.reserve(batch);
  particles.reserve(particles.size() + std::size_t(fill.count));
  long long placed = 0;
  int misses = 0;  // candidates refused since the last one kept
  while (placed < fill.count) {
    for (Vec3d& c : candidate) c = sampler.sample(centres);
    // is_free only reads the grid; each index writes its own slot.
    parallel_for_dynamic(threads, batch, 16,
                         [&](long long i) { clear[i] = grid.is_free(candidate[i]) ? 1 : 0; });
    kept.clear();
    for (int i = 0; i < batch && placed < fill.count; ++i) {
      bool ok = clear[i] != 0;
      for (std::size_t k = 0; ok && k < kept.size(); ++k)
        ok = !(norm2(candidate[i] - kept[k]) < reach2);
      if (!ok) {
        if (++misses < kFillAttemptsPerParticle) continue;
        throw std::runtime_error(
            fill.source.where() + ": placed " + std::to_string(placed) + " of " +
            std::to_string(fill.count) + " particles of template '" + shape.name +
            "'; no free place for the next one in " + std::to_string(kFillAttemptsPerParticle) +
            " random tries (the region is too full, or walls and earlier particles take its "
            "room): ask for fewer particles or a larger region");
      }
      misses = 0;
      kept.push_back(candidate[i]);
      grid.add_sphere(candidate[i], radius);
      ParticleState p;
      p.template_index = fill.template_index;
      p.position = candidate[i];
      if (fill.random_orientation) p.orientation = turns.orientation();
      p.velocity = fill.velocity;
      p.source = fill.source;
      particles.push_back(p);
      ++placed;
    }
  }
}

void keep_initial_particles(const Scene& scene, std::vector<ParticleState> particles) {
  if (!scene.made_particles) return;  // a moved-from scene: nothing to hand on through
  MadeParticles& made = *scene.made_particles;
  made.list = std::move(particles);
  made.full = true;
}

std::vector<ParticleState> initial_particles(const Scene& scene) {
  MadeParticles* made = scene.made_particles.get();
  if (made && made->full && made->list.size() == initial_particle_count(scene)) {
    made->full = false;  // taken once: the list moves out, the scene's copies see none either
    return std::move(made->list);
  }
  std::vector<ParticleState> particles = scene.particles;
  for (const LatticeRequest& lattice : scene.lattices) {
    const std::vector<ParticleState> points = lattice_particles(lattice);
    particles.insert(particles.end(), points.begin(), points.end());
  }
  if (!scene.random_fills.empty()) {
    const std::vector<WallMesh> walls = make_wall_meshes(scene);
    for (const RandomFillRequest& fill : scene.random_fills)
      random_fill_particles(scene, fill, walls, particles);
  }
  return particles;
}

std::size_t initial_particle_count(const Scene& scene) {
  std::size_t count = scene.particles.size();
  for (const LatticeRequest& lattice : scene.lattices)  // whole numbers below 2^53: exact
    count += static_cast<std::size_t>(lattice_point_count(lattice.region, lattice.spacing));
  for (const RandomFillRequest& fill : scene.random_fills)
    count += static_cast<std::size_t>(fill.count);
  return count;
}

Scene without_initial_particles(const Scene& scene) {
  Scene start = scene;
  start.particles.clear();
  start.lattices.clear();
  start.random_fills.clear();
  start.left_out_particles = scene.left_out_particles + initial_particle_count(scene);
  start.made_particles = std::make_shared<MadeParticles>();  // none: they were left out
  return start;
}

}  // namespace talus
