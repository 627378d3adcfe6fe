#include "reference/geometry/exact_convex.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/convex_hull_3.h>

#include <stdexcept>

namespace talus::reference {

namespace {
using DoubleKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using DoubleMesh = CGAL::Surface_mesh<DoubleKernel::Point_3>;
}  // namespace

std::vector<Eigen::Vector3d> world_vertices(const ShapeTemplate& shape, const RefPose& pose) {
  const Eigen::Matrix3d rotation = pose.orientation.normalized().toRotationMatrix();
  std::vector<Eigen::Vector3d> out;
  out.reserve(shape.vertices.size());
  for (const Vec3d& v : shape.vertices) {
    out.push_back(pose.position + rotation * Eigen::Vector3d(v.x, v.y, v.z));
  }
  return out;
}

ExactConvex make_exact_convex(const ShapeTemplate& shape, const RefPose& pose) {
  std::vector<ExactPoint> points;
  for (const Eigen::Vector3d& w : world_vertices(shape, pose))
    points.emplace_back(w.x(), w.y(), w.z());
  if (!is_full_dimensional(points)) {
    throw std::invalid_argument("reference: template '" + shape.name + "' is not a solid");
  }
  ExactMesh mesh;
  CGAL::convex_hull_3(points.begin(), points.end(), mesh);
  ExactConvex convex;
  convex.vertices.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) convex.vertices.push_back(mesh.point(v));
  for (auto e : mesh.edges()) {
    convex.edges.push_back(
        {static_cast<int>(mesh.vertex(e, 0).idx()), static_cast<int>(mesh.vertex(e, 1).idx())});
  }
  for (auto f : mesh.faces()) {
    // Faces of convex_hull_3 are counter-clockwise seen from outside: the plane through the
    // corners in that order has the outside on its positive side.
    auto h = mesh.halfedge(f);
    const ExactPoint& p = mesh.point(mesh.source(h));
    const ExactPoint& q = mesh.point(mesh.target(h));
    const ExactPoint& r = mesh.point(mesh.target(mesh.next(h)));
    convex.planes.emplace_back(p, q, r);
  }
  return convex;
}

bool clip_segment(const ExactPoint& p0, const ExactPoint& p1, const std::vector<ExactPlane>& planes,
                  std::vector<ExactPoint>& out) {
  using FT = ExactKernel::FT;
  // Parametric clipping (Cyrus–Beck) in exact arithmetic: x(t) = p0 + t (p1 - p0), t in [0, 1].
  FT t_in(0), t_out(1);
  bool moved_in = false, moved_out = false;
  for (const ExactPlane& h : planes) {
    const CGAL::Oriented_side side0 = h.oriented_side(p0), side1 = h.oriented_side(p1);
    if (side0 != CGAL::ON_POSITIVE_SIDE && side1 != CGAL::ON_POSITIVE_SIDE) continue;
    if (side0 == CGAL::ON_POSITIVE_SIDE && side1 == CGAL::ON_POSITIVE_SIDE) return false;
    const FT s0 = h.a() * p0.x() + h.b() * p0.y() + h.c() * p0.z() + h.d();
    const FT s1 = h.a() * p1.x() + h.b() * p1.y() + h.c() * p1.z() + h.d();
    const FT t = s0 / (s0 - s1);  // one strictly outside, the other not: s0 != s1
    if (side0 == CGAL::ON_POSITIVE_SIDE) {
      if (!moved_in || t > t_in) t_in = t;
      moved_in = true;
    } else {
      if (!moved_out || t < t_out) t_out = t;
      moved_out = true;
    }
    if (t_in > t_out) return false;
  }
  const ExactKernel::Vector_3 d = p1 - p0;
  out.push_back(moved_in ? p0 + t_in * d : p0);
  out.push_back(moved_out ? p0 + t_out * d : p1);
  return true;
}

bool is_full_dimensional(const std::vector<ExactPoint>& points) {
  const size_t n = points.size();
  size_t i1 = 1;
  while (i1 < n && points[i1] == points[0]) ++i1;
  if (i1 >= n) return false;
  size_t i2 = i1 + 1;
  while (i2 < n && CGAL::collinear(points[0], points[i1], points[i2])) ++i2;
  if (i2 >= n) return false;
  for (size_t i3 = i2 + 1; i3 < n; ++i3) {
    if (CGAL::orientation(points[0], points[i1], points[i2], points[i3]) != CGAL::COPLANAR) {
      return true;
    }
  }
  return false;
}

MeshMeasures measure_mesh(const ExactMesh& mesh) {
  MeshMeasures m;
  if (mesh.number_of_vertices() == 0) return m;
  // About the first vertex, so that a polytope far from the origin keeps its digits.
  const Eigen::Vector3d origin = to_eigen(mesh.point(*mesh.vertices().begin()));
  DoubleMesh local;
  std::vector<DoubleMesh::Vertex_index> map(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = to_eigen(mesh.point(v)) - origin;
    map[v.idx()] = local.add_vertex(DoubleKernel::Point_3(p.x(), p.y(), p.z()));
  }
  for (auto f : mesh.faces()) {
    std::vector<DoubleMesh::Vertex_index> loop;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) loop.push_back(map[v.idx()]);
    local.add_face(loop);
  }
  m.volume = CGAL::Polygon_mesh_processing::volume(local);
  if (m.volume > 0) {
    const auto c = CGAL::Polygon_mesh_processing::centroid(local);
    m.centroid = origin + Eigen::Vector3d(c.x(), c.y(), c.z());
  } else {
    m.centroid = origin;
  }
  return m;
}

}  // namespace talus::reference
