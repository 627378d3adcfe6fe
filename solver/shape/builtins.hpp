// Built-in particle shapes, named by a spec "name:size" (sizes in metres).
#pragma once

#include <string>
#include <vector>

#include "solver/shape/mesh_io.hpp"
#include "solver/shape/shape.hpp"

namespace talus {

// Specs:
//   tetrahedron:D, cube:D, octahedron:D, dodecahedron:D, icosahedron:D   (regular solids)
//   corn:D      corn-kernel-like wedge (BLAZE-DEM §5.3 hopper flow), 20 vertices
//   mineral:D   irregular mineral-like particle (paper §4.1): 18 vertices, 32 triangular faces
//     D: circumscribed-sphere diameter = twice the largest vertex distance from the centroid
//   cuboid:a,b,c       side lengths
//   cylinder:D,L[,N]   N-sided prism (default 20) whose rim vertices lie on the circle of
//                      diameter D (paper §3.1, Table 1: D = 8 mm, L = 5.3 mm)
// Throws std::invalid_argument naming the spec and what was expected.
ShapeTemplate make_builtin(const std::string& spec);

// The shape names make_builtin accepts.
std::vector<std::string> builtin_names();

// The paper's cylinder mesh (§3.1, Fig. 9a): 2N rim vertices plus the 2 cap centres, N-triangle
// fans on each cap and 2N side triangles (N = 20: 42 vertices, 80 triangles), axis along z,
// centred at the origin, outward oriented.
TriangleMesh cylinder_mesh(double diameter, double length, int sides = 20);

}  // namespace talus
