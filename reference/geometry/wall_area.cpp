#include "reference/geometry/wall_area.hpp"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>

#include <cmath>
#include <list>
#include <stdexcept>
#include <vector>

namespace talus::reference {

namespace {

using FT = ExactKernel::FT;
using Vector3 = ExactKernel::Vector_3;
using Point2 = ExactKernel::Point_2;
using Polygon2 = CGAL::Polygon_2<ExactKernel>;
using PolygonWithHoles2 = CGAL::Polygon_with_holes_2<ExactKernel>;

// Drop coordinate `k` of a point of the plane.
Point2 project(const ExactPoint& p, int k) {
  if (k == 0) return {p.y(), p.z()};
  if (k == 1) return {p.z(), p.x()};
  return {p.x(), p.y()};
}

// The point of `plane` whose projection (dropping coordinate k) is q.
ExactPoint lift(const ExactPlane& plane, const Point2& q, int k) {
  if (k == 0)
    return {-(plane.d() + plane.b() * q.x() + plane.c() * q.y()) / plane.a(), q.x(), q.y()};
  if (k == 1)
    return {q.y(), -(plane.d() + plane.a() * q.y() + plane.c() * q.x()) / plane.b(), q.x()};
  return {q.x(), q.y(), -(plane.d() + plane.a() * q.x() + plane.b() * q.y()) / plane.c()};
}

// Area and area centroid of a simple polygon (shoelace, exact).
FT polygon_area_centroid(const Polygon2& polygon, Point2& centroid) {
  FT twice_area(0), sx(0), sy(0);
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const Point2& p = polygon[i];
    const Point2& q = polygon[(i + 1) % n];
    const FT w = p.x() * q.y() - q.x() * p.y();
    twice_area += w;
    sx += (p.x() + q.x()) * w;
    sy += (p.y() + q.y()) * w;
  }
  if (twice_area != 0) centroid = Point2(sx / (3 * twice_area), sy / (3 * twice_area));
  return twice_area / 2;
}

// The centroid of the solid bounded by a closed, outward-oriented mesh, exact: the sum over its
// facets (fanned into triangles) of the signed cones from the first vertex o, each of volume
// u . (v x w) / 6 and centroid o + (u + v + w) / 4. False when the volume is not positive.
bool solid_centroid(const ExactMesh& mesh, ExactPoint& centroid) {
  if (mesh.number_of_vertices() == 0) return false;
  const ExactPoint& o = mesh.point(*mesh.vertices().begin());
  FT six_volume(0);
  Vector3 moment24(0, 0, 0);  // 24 times the first moment about o
  for (auto f : mesh.faces()) {
    std::vector<Vector3> corners;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      corners.push_back(mesh.point(v) - o);
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k) {
      const Vector3 &u = corners[0], &v = corners[k], &w = corners[k + 1];
      const FT cone = CGAL::scalar_product(u, CGAL::cross_product(v, w));
      six_volume += cone;
      moment24 = moment24 + cone * (u + v + w);
    }
  }
  if (!(six_volume > 0)) return false;
  centroid = o + moment24 / (4 * six_volume);
  return true;
}

Eigen::Vector3d to_eigen_vector(const Vector3& v) {
  return {to_double_tight(v.x()), to_double_tight(v.y()), to_double_tight(v.z())};
}

}  // namespace

RefWallContact wall_contact(const ShapeTemplate& shape, const RefPose& pose,
                            const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  RefWallContact result;
  const ExactPoint pa(a.x(), a.y(), a.z()), pb(b.x(), b.y(), b.z()), pc(c.x(), c.y(), c.z());
  if (CGAL::collinear(pa, pb, pc)) throw std::invalid_argument("reference: degenerate triangle");
  // Positive side = the side (b - a) x (c - a) points to, "above" where particles live.
  const ExactPlane plane(pa, pb, pc);
  const Eigen::Vector3d normal_d(to_double_tight(plane.a()), to_double_tight(plane.b()),
                                 to_double_tight(plane.c()));
  result.normal = normal_d.normalized();

  const ExactConvex convex = make_exact_convex(shape, pose);
  FT min_distance = plane.a() * convex.vertices[0].x() + plane.b() * convex.vertices[0].y() +
                    plane.c() * convex.vertices[0].z() + plane.d();
  for (const ExactPoint& p : convex.vertices) {
    const FT s = plane.a() * p.x() + plane.b() * p.y() + plane.c() * p.z() + plane.d();
    if (s < min_distance) min_distance = s;
  }
  if (min_distance > 0) return result;  // the particle does not reach the plane
  result.reaches_plane = true;
  result.depth = -to_double_tight(min_distance) / normal_d.norm();

  // The part below: vertices below or on, and the edges' crossings (the clipped edge ends).
  const std::vector<ExactPlane> below{plane};
  std::vector<ExactPoint> below_points, section;
  for (const auto& e : convex.edges) {
    clip_segment(convex.vertices[e[0]], convex.vertices[e[1]], below, below_points);
  }
  ExactPoint below_centroid;
  bool has_below_centroid = false;
  if (is_full_dimensional(below_points)) {
    ExactMesh hull;
    CGAL::convex_hull_3(below_points.begin(), below_points.end(), hull);
    result.volume_below = measure_mesh(hull).volume;
    has_below_centroid = solid_centroid(hull, below_centroid);
    if (has_below_centroid) result.volume_below_centroid = to_eigen(below_centroid);
  }
  for (const ExactPoint& p : below_points) {
    if (plane.has_on(p)) section.push_back(p);
  }

  // Project, dropping the normal's largest component (nonzero: the plane has a normal).
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(normal_d[i]) > std::abs(normal_d[k])) k = i;
  }
  const double area_scale = normal_d.norm() / std::abs(normal_d[k]);  // plane area / projected
  std::vector<Point2> projected;
  for (const ExactPoint& p : section) projected.push_back(project(p, k));
  std::vector<Point2> hull2;
  CGAL::convex_hull_2(projected.begin(), projected.end(), std::back_inserter(hull2));
  result.section_points = static_cast<int>(hull2.size());
  if (hull2.size() < 3) return result;                         // a point or a segment: no area
  const Polygon2 section_polygon(hull2.begin(), hull2.end());  // counter-clockwise
  Point2 section_centroid_2;
  result.section_area =
      to_double_tight(polygon_area_centroid(section_polygon, section_centroid_2)) * area_scale;
  // The projection is an affine bijection of the plane: it maps centroids to centroids.
  const ExactPoint section_centroid = lift(plane, section_centroid_2, k);
  result.section_centroid = to_eigen(section_centroid);
  if (has_below_centroid) {
    // The in-plane part of (below centroid - section centroid): less its component along the
    // plane's normal N = (a, b, c).
    const Vector3 d = below_centroid - section_centroid;
    const Vector3 normal = plane.orthogonal_vector();
    result.volume_offset =
        to_eigen_vector(d - normal * (CGAL::scalar_product(d, normal) / normal.squared_length()));
  }

  Polygon2 triangle;
  triangle.push_back(project(pa, k));
  triangle.push_back(project(pb, k));
  triangle.push_back(project(pc, k));
  if (triangle.is_clockwise_oriented()) triangle.reverse_orientation();
  std::list<PolygonWithHoles2> common;
  CGAL::intersection(section_polygon, triangle, std::back_inserter(common));
  // Two convex polygons meet in at most one convex polygon (no holes).
  FT area(0), moment_x(0), moment_y(0);
  for (const PolygonWithHoles2& piece : common) {
    Point2 centroid;
    const FT piece_area = polygon_area_centroid(piece.outer_boundary(), centroid);
    if (piece_area == 0) continue;
    area += piece_area;
    moment_x += piece_area * centroid.x();
    moment_y += piece_area * centroid.y();
  }
  if (area > 0) {
    result.overlap_area = to_double_tight(area) * area_scale;
    result.overlap_centroid = to_eigen(lift(plane, Point2(moment_x / area, moment_y / area), k));
  }
  return result;
}

}  // namespace talus::reference
