// Reference particle-triangle contact (the oracle for solver/geometry/wall_clip.hpp, paper §2.4):
// the posed polyhedron's cross-section with the triangle's plane, intersected with the triangle by
// CGAL's 2-D Boolean operations, and the part of the polyhedron below the plane with its centroid,
// all exact.
#pragma once

#include <Eigen/Core>

#include "reference/geometry/exact_convex.hpp"
#include "solver/shape/shape.hpp"

namespace talus::reference {

struct RefWallContact {
  bool reaches_plane = false;                        // some vertex on or below the plane
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit((b - a) x (c - a)): "above" side
  double section_area = 0;                           // m^2: the whole cross-section
  int section_points = 0;                            // corners of the cross-section polygon
  double overlap_area = 0;                           // m^2: the cross-section within the triangle
  Eigen::Vector3d overlap_centroid = Eigen::Vector3d::Zero();  // m, world; zero when no area
  double depth = 0;         // m: max over vertices of -normal . (x - a), at least 0
  double volume_below = 0;  // m^3: the part with normal . (x - a) <= 0
  // m, world: the area centroid of the whole cross-section (on the plane) and the centroid of
  // the part below (zero where there is no area, resp. no volume).
  Eigen::Vector3d section_centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d volume_below_centroid = Eigen::Vector3d::Zero();
  // m, world, in the plane: volume_below_centroid - section_centroid projected onto the plane
  // (computed exactly, rounded once); zero unless both the section's area and the volume below
  // are positive. volume_paper's wall contact point of this facet is overlap_centroid +
  // volume_offset (the default law's is overlap_centroid; world/world.cpp says why).
  Eigen::Vector3d volume_offset = Eigen::Vector3d::Zero();
};

// The cross-section's corners are the polyhedron's vertices on the plane and its edges' crossings
// of it (exact). They are projected onto the coordinate plane that drops the normal's largest
// component (an affine bijection of the wall plane, so areas scale by |n| / |n_k| and centroids
// map back exactly), intersected with the triangle there (CGAL::intersection of two Polygon_2),
// and lifted back. The volume below is the hull of the vertices below and the crossings; its
// centroid is summed exactly over the cones from one hull vertex to the hull's facets.
RefWallContact wall_contact(const ShapeTemplate& shape, const RefPose& pose,
                            const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c);

}  // namespace talus::reference
