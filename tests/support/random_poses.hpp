// Deterministic random poses and point clouds for the geometry tests (std::mt19937_64, seeded by
// the caller, so a failing case can be replayed from its seed).
#pragma once

#include <random>
#include <vector>

#include "solver/core/quat.hpp"

namespace talus {

// Uniform on the unit sphere: a normalised isotropic Gaussian vector.
Vec3d random_direction(std::mt19937_64& rng);

// Uniform on SO(3) (Shoemake, "Uniform random rotations", Graphics Gems III, 1992).
Quatd random_rotation(std::mt19937_64& rng);

// n_points (>= 4) points on or just inside an ellipsoid whose largest diameter is about `size`
// (semi-axes drawn in [0.25, 0.5] * size, randomly rotated), about its centre: in general position
// with probability one; most points lie near the surface so that the hull has many vertices.
std::vector<Vec3d> random_convex_cloud(std::mt19937_64& rng, int n_points, double size);

// Position uniform in the cube [-extent, extent]^3, orientation uniform on SO(3).
Posed random_pose(std::mt19937_64& rng, double extent);

struct PosePair {
  Posed a, b;
};

// A within a few diameters of the origin, B along a uniform random direction from A at the
// centre distance (radius_a + radius_b) * (1 - f), f uniform in [depth_fraction_min,
// depth_fraction_max]; both orientations uniform. "Shallow" is f in [0, 0.1]. With bounding radii
// the bounding spheres overlap; the polyhedra themselves may still be separate.
PosePair random_overlapping_pair(std::mt19937_64& rng, double radius_a, double radius_b,
                                 double depth_fraction_min, double depth_fraction_max);

}  // namespace talus
