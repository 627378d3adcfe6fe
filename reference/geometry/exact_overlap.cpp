#include "reference/geometry/exact_overlap.hpp"

#include <CGAL/convex_hull_3.h>

namespace talus::reference {

namespace {

// True when the three points lie on one of the planes (exact).
bool on_any_plane(const std::vector<ExactPlane>& planes, const ExactPoint& p, const ExactPoint& q,
                  const ExactPoint& r) {
  for (const ExactPlane& h : planes) {
    if (h.has_on(p) && h.has_on(q) && h.has_on(r)) return true;
  }
  return false;
}

}  // namespace

RefOverlap exact_overlap(const ShapeTemplate& a, const RefPose& pose_a, const ShapeTemplate& b,
                         const RefPose& pose_b) {
  return exact_overlap(make_exact_convex(a, pose_a), make_exact_convex(b, pose_b));
}

RefOverlap exact_overlap(const ExactConvex& a, const ExactConvex& b) {
  RefOverlap result;
  std::vector<ExactPoint> points;
  for (const auto& e : a.edges) clip_segment(a.vertices[e[0]], a.vertices[e[1]], b.planes, points);
  for (const auto& e : b.edges) clip_segment(b.vertices[e[0]], b.vertices[e[1]], a.planes, points);
  if (points.empty()) return result;
  if (!is_full_dimensional(points)) {
    result.touching = true;
    return result;
  }
  ExactMesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  result.overlapping = true;
  const MeshMeasures measures = measure_mesh(hull);
  result.volume = measures.volume;
  result.centroid = measures.centroid;

  for (auto f : hull.faces()) {
    const auto h = hull.halfedge(f);
    const ExactPoint& p = hull.point(hull.source(h));
    const ExactPoint& q = hull.point(hull.target(h));
    const ExactPoint& r = hull.point(hull.target(hull.next(h)));
    // Outward area vector in double, from differences of the (exact, rounded) corners.
    const Eigen::Vector3d p_d = to_eigen(p), q_d = to_eigen(q), r_d = to_eigen(r);
    const Eigen::Vector3d area = 0.5 * (q_d - p_d).cross(r_d - p_d);
    result.boundary_area += area.norm();
    ++result.facets;
    // A facet of P on a plane of A has A's outward normal there (P lies inside A).
    if (!on_any_plane(a.planes, p, q, r)) continue;
    const double weight = on_any_plane(b.planes, p, q, r) ? 0.5 : 1.0;
    result.vector_area_a += weight * area;
    // n is constant on the flat triangle: its moment about the centroid is the lever of its own
    // centroid times its area vector.
    const Eigen::Vector3d lever = (p_d + q_d + r_d) / 3 - result.centroid;
    result.surface_moment_a += weight * lever.cross(area);
  }
  return result;
}

}  // namespace talus::reference
