// Triangle meshes from Wavefront OBJ and STL (ASCII or binary) files, and shape templates built
// from them or from a built-in spec.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "solver/shape/shape.hpp"

namespace talus {

struct TriangleMesh {
  std::vector<Vec3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // indices into vertices
};

// OBJ: 'v x y z [w]' vertices and 'f a b c ...' faces (indices 1-based or negative-relative,
// 'a/t/n' forms accepted; polygons fanned into triangles); vt, vn, vp, g, o, s, l, p, usemtl,
// mtllib are ignored. A file with vertices but no faces is read as a point cloud.
TriangleMesh read_obj(const std::string& path);
// STL: binary when the size matches the header's triangle count, else ASCII ('solid ...').
// Vertices with identical coordinates are merged; facets that collapse to a line are dropped.
TriangleMesh read_stl(const std::string& path);
// By extension (.obj or .stl, any case).
TriangleMesh read_mesh(const std::string& path);
// All readers throw std::runtime_error naming the file, the line (text formats) and what was
// expected.

void write_obj(const std::string& path, const TriangleMesh& mesh);
void write_stl(const std::string& path, const TriangleMesh& mesh, bool binary);

// The template of the convex hull of a mesh file's vertices, scaled by `scale` (file units to
// metres), named after the path. A non-convex mesh gets one warning on stderr
// ("<file>: mesh is not convex; using its convex hull") and its hull is used.
ShapeTemplate load_shape_file(const std::string& path, double scale = 1);

// Ends in .obj or .stl (any case): a mesh file rather than a built-in spec.
bool is_mesh_path(const std::string& path);

// A built-in spec (see builtins.hpp) or a mesh file, optionally "path:scale".
ShapeTemplate make_shape(const std::string& spec);

// Relative tolerance for shapes from files: coordinates printed with ~7 digits or stored as
// 32-bit floats are coplanar only to ~1e-7 of the particle size.
constexpr double kMeshFileRelTol = 1e-6;

}  // namespace talus
