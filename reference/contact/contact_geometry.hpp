// The geometry of one particle-particle contact, computed by the reference's own code: the exact
// overlap (volume model) and the penetration depth, normal and point (linear model). Shares no
// code with solver/geometry; the normal always points from A into B.
#pragma once

#include <Eigen/Core>

#include "reference/geometry/exact_convex.hpp"
#include "solver/shape/shape.hpp"

namespace talus::reference {

struct PairGeometry {
  bool in_contact = false;  // overlapping with interior (volume) or delta > 0 (linear)
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, from A into B
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // contact point, m (world)
  double volume = 0;                                 // dV, m^3 (volume model)
  double area = 0;                                   // A_n = |S|, m^2 (volume model)
  double depth = 0;                                  // delta, m (linear model)
  // m^3 (volume model): the surface moment of the overlap's boundary on A about `point`
  // (RefOverlap::surface_moment_a); the default law's couple of U(V) on A is -p(V) times it.
  // Zero for the spheres' lens: A's normals all pass through A's centre, so M = (x_A - point) x S,
  // and the point and S lie on the line of centres.
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

// Volume model, two polyhedra: exact_overlap; n = S / |S|, A_n = |S|, point = overlap centroid,
// moment = its surface moment on A.
PairGeometry volume_geometry(const ShapeTemplate& a, const RefPose& pose_a, const ShapeTemplate& b,
                             const RefPose& pose_b);

// Volume model, two spheres (closed-form lens): dV = pi h^2 ... of the two caps, S = pi a^2 u with
// a the radius of the circle where the spheres' surfaces meet and u the unit centre line from A
// to B; point = the lens's volume centroid. Throws std::invalid_argument when one sphere holds
// the other's centre line degenerate (coincident centres) or lies inside the other (no circle).
PairGeometry sphere_lens_geometry(const Eigen::Vector3d& centre_a, double radius_a,
                                  const Eigen::Vector3d& centre_b, double radius_b);

// Linear model, two polyhedra: brute-force separating-axis test over all face normals of both
// bodies and all cross products of an edge of A with an edge of B (the minimum translation
// distance of convex polyhedra is attained on one of them). delta = the smallest overlap of the
// projections, n = that axis oriented from A to B. The point is the exact overlap's centroid,
// deliberately not production's feature rule (docs/geometry.md, "The simple contact": the mean of
// the supporting-feature vertices inside the other body, else edge closest points, else feature
// centroids, put on the mid-plane). That rule depends on a tolerance (kFeatureTolerance) and
// jumps when a vertex enters or leaves the other body or the tolerance band (a face sliding over
// a face: the point, so the torque, steps), and for overlapping faces the mean of the inside
// corners is not the patch's centre. The centroid is continuous in the poses, tolerance-free,
// the point of the volume model too, and for face-face contact its projection onto the
// mid-plane is the common patch's centroid. What production should change: for face-face and
// edge-face contacts, clip the two supporting faces' polygons in the mid-plane (the Sutherland-
// Hodgman of wall_clip.hpp) and take the patch's area centroid; keep the vertex rule for
// vertex-face only (one vertex: the same point). Until then, comparisons of the two solvers
// (issue 4) should compare forces exactly and torques only up to |F| times the patch's size.
PairGeometry linear_polyhedra_geometry(const ShapeTemplate& a, const RefPose& pose_a,
                                       const ShapeTemplate& b, const RefPose& pose_b);

// Linear model, two spheres: along the centre line, point midway between the deepest points.
PairGeometry linear_sphere_geometry(const Eigen::Vector3d& centre_a, double radius_a,
                                    const Eigen::Vector3d& centre_b, double radius_b);

// Linear model, polyhedron A and sphere B. Centre outside: the closest point p on A's surface,
// delta = r - |c - p|, n = (c - p) / |c - p|. Centre inside: the nearest face plane, delta = r +
// its distance, n = that face's outward normal. Point: midway between p and the sphere's deepest
// point c - r n.
PairGeometry linear_polyhedron_sphere_geometry(const ShapeTemplate& a, const RefPose& pose_a,
                                               const Eigen::Vector3d& centre_b, double radius_b);

// The point of triangle (a, b, c) closest to p (by its Voronoi regions: vertices, edges, face).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace talus::reference
