#include "solver/scene/initial_particles.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

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

void random_fill_particles(const Scene& scene, const RandomFillRequest& fill,
                           const std::vector<WallMesh>& walls,
                           std::vector<ParticleState>& particles) {
  const ParticleTemplate& shape = scene.templates.at(fill.template_index);
  const double radius = shape.bounding_radius;
  const CentreSampler sampler(fill.region, radius);
  PlacementGrid grid(sampler.low(), sampler.high(), radius,
                     particles.size() + std::size_t(fill.count));
  for (const ParticleState& p : particles)
    grid.add_sphere(p.position, scene.templates.at(p.template_index).bounding_radius);
  for (const WallMesh& wall : walls) grid.add_mesh(wall.mesh);
  PlacementRandom random(fill.seed);
  for (long long placed = 0; placed < fill.count; ++placed) {
    ParticleState p;
    const bool found =
        place_one(sampler, grid, random, kFillAttemptsPerParticle, fill.template_index,
                  fill.random_orientation, fill.velocity, fill.source, p);
    if (found) particles.push_back(p);
    if (!found)
      throw std::runtime_error(
          fill.source.where() + ": placed " + std::to_string(placed) + " of " +
          std::to_string(fill.count) + " particles of template '" + shape.name + "'; no free " +
          "place for the next one in " + std::to_string(kFillAttemptsPerParticle) +
          " random tries (the region is too full, or walls and earlier particles take its room)"
          ": ask for fewer particles or a larger region");
  }
}

std::vector<ParticleState> initial_particles(const Scene& scene) {
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
  return start;
}

}  // namespace talus
