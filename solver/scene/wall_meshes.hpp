// The triangles of each wall a scene asks for, in world coordinates at t = 0.
//
// Convention: every triangle (a, b, c) has its normal unit((b - a) x (c - a)) pointing to the
// side where particles live: into a container (box, cylinder, drum, hopper, silo), to the side
// the plane's `normal` names. The wall contact treats that side as "above" the triangle. A mesh
// file keeps the winding it was written with, so it must follow the same rule.
//
// Circles are polygons of `segments` sides whose corners lie on the circle (inscribed), the first
// corner at angle 0 of axis_basis(axis). Parts that meet (the cone and the bin of a silo, a
// cylinder and its caps) share their vertices, so a closed wall is watertight: every edge is
// shared by exactly two triangles, traversed once each way.
#pragma once

#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

struct WallMesh {
  TriangleMesh mesh;  // world coordinates at t = 0
  // A closed outlet's plate (hopper, silo): the last `plate_triangles` triangles of the mesh,
  // which the solver drops when the outlet opens. 0 for every other wall.
  int plate_triangles = 0;
};

// How far from the origin a wall's corner may lie, in m (checked when the scene is read): far
// beyond any container, and well within what the wall contact's clipping resolves.
constexpr double kMaxWallReach = 1e6;

// Two unit vectors u, v with u x v = axis (axis: unit). The same axis always gives the same
// pair, so that meshes and random cylinder regions are reproducible.
void axis_basis(const Vec3d& axis, Vec3d& u, Vec3d& v);

// The mesh of one wall. Generated walls: as described above. Mesh walls: world = translation +
// R(rotation) (scale * file), triangles as in the file. Plane: a square of side `size` centred
// at `point` (two triangles). Box: 12 triangles (10 with open_top), all facing inward.
// Cylinder: the side (2 triangles per segment) and the caps asked for (a fan about the centre).
// Drum: a cylinder of `length` centred at `center`, both caps. Hopper: the frustum from the
// outlet circle to the top circle, open at the top; a plate over a closed outlet. Silo: the bin,
// above the cone (or a flat annulus from the outlet to the wall when cone_height is 0); a plate
// over a closed outlet; open at the top.
WallMesh make_wall_mesh(const WallSpec& wall);

// Every wall of the scene, in the order of Scene::walls.
std::vector<WallMesh> make_wall_meshes(const Scene& scene);

// Whether the outlet plate of a hopper or silo is still in place at `time` (s): a closed outlet
// with no opening time, or one whose opening time has not come. False for other walls.
bool outlet_closed_at(const WallSpec& wall, double time);

// The triangles of a wall present at `time`: all of its mesh but an opened outlet's plate.
int present_triangle_count(const WallSpec& wall, const WallMesh& mesh, double time);

// The walls as they stand at `time` (s): each mesh of make_wall_meshes moved by its wall's rigid
// motion (wall_motion.hpp), with only its present triangles. ParaView's walls and the pictures
// of `talus render` are drawn from these.
std::vector<TriangleMesh> walls_at(const Scene& scene, const std::vector<WallMesh>& meshes,
                                   double time);

// Sum of the triangles' areas, m^2.
double mesh_area(const TriangleMesh& mesh);

}  // namespace talus
