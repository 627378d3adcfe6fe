// Finding a wall mesh's planar patches (planar_patch.hpp) on the host, once per wall. Host code:
// std::vector.
#pragma once

#include <array>
#include <vector>

#include "solver/walls/planar_patch.hpp"

namespace talus {

// A patch needs at least this many facets to be worth its test (a box's face has two).
constexpr int kMinPatchFacets = 6;
// The wall contact looks at no more than this many patches of a wall (the first ones).
constexpr int kMaxPatchesPerWall = 8;

// The runs of consecutive facets, at least kMinPatchFacets long, that lie in one plane (normals
// within 1e-9 rad, corners within 1e-9 of the mesh's size of it) and tile one convex polygon: their
// edges used once form a single closed loop, counter-clockwise about the normal, turning one way
// only, and the facets' areas add up to the loop's. The centre is the polygon's centroid, the
// inradius its distance to the nearest edge less 1e-9 of the mesh's size. At most
// kMaxPatchesPerWall, the first in facet order. Vertices must be shared by index (the generated
// walls, STL after its merging, OBJ); a mesh that repeats them gets no patches, which is only
// slower.
template <class Real>
std::vector<PlanarPatch<Real>> find_planar_patches(
    const std::vector<Vec3d>& vertices, const std::vector<std::array<int, 3>>& triangles);

extern template std::vector<PlanarPatch<float>> find_planar_patches<float>(
    const std::vector<Vec3d>&, const std::vector<std::array<int, 3>>&);
extern template std::vector<PlanarPatch<double>> find_planar_patches<double>(
    const std::vector<Vec3d>&, const std::vector<std::array<int, 3>>&);

}  // namespace talus
