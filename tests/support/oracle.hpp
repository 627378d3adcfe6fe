// Independent overlap oracle for the tests: the intersection of two posed convex polyhedra by
// primal half-space clipping in long double on the host. It shares no code with the production
// overlap (dual-space polar transform + Quickhull, paper §2.3) and favours plain over fast.
#pragma once

#include <vector>

#include "solver/core/quat.hpp"
#include "solver/shape/shape.hpp"

namespace talus {

using Vec3l = Vec3<long double>;

struct OracleResult {
  long double volume = 0;  // m^3
  Vec3l centroid;          // world frame; zero when the volume is zero
  // Sum over the intersection's boundary faces lying on A's surface of (area * A's outward unit
  // normal), m^2. Points from A into B; moving B along it shrinks the overlap:
  // dV/dx_B = -vector_area_a, dV/dx_A = +vector_area_a.
  Vec3l vector_area_a;
  // The same over the faces lying on B's surface (B's outward normals); for a closed surface
  // vector_area_a + vector_area_b = 0.
  Vec3l vector_area_b;
  int n_faces = 0;                // faces of the intersection polytope; 0 when it is empty or flat
  long double boundary_area = 0;  // total area of its boundary, m^2 (a scale for tolerances)
};

// Intersection of A and B posed in the world (world = position + rotate(orientation, body)).
// A is clipped, as a polyhedron of polygons, by every face plane of B. A face of the result that
// lies on a face of both A and B (coincident planes) is counted as A's.
OracleResult oracle_overlap(const ShapeTemplate& a, const Posed& pose_a, const ShapeTemplate& b,
                            const Posed& pose_b);

// The part of the posed body with dot(plane_normal, x) <= plane_offset (world frame; the normal
// need not be unit). vector_area_a collects the body's surface, vector_area_b the cut face
// (area * unit plane normal).
OracleResult oracle_clip_by_plane(const ShapeTemplate& body, const Posed& pose, Vec3l plane_normal,
                                  long double plane_offset);

// Volume of the posed body where dot(plane_normal, x) <= plane_offset, m^3.
long double oracle_volume_below_plane(const ShapeTemplate& body, const Posed& pose,
                                      Vec3l plane_normal, long double plane_offset);

// The section of the posed body by the plane dot(plane_normal, x) = plane_offset: its vertices in
// the world frame, counter-clockwise seen from the side plane_normal points to. Empty when the
// plane misses the body or only touches it at an edge or a vertex; a face lying on the plane is
// returned as the section.
std::vector<Vec3l> oracle_section_polygon(const ShapeTemplate& body, const Posed& pose,
                                          Vec3l plane_normal, long double plane_offset);

}  // namespace talus
