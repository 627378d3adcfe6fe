#include "solver/shape/template_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "solver/shape/hull.hpp"

namespace talus {
namespace {

void add_outer(Matrix3d& m, const Vec3d& a, const Vec3d& b, double weight) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] += weight * a[i] * b[j];
}

Matrix3d multiply(const Matrix3d& a, const Matrix3d& b) {
  Matrix3d c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

Matrix3d transpose(const Matrix3d& a) {
  Matrix3d t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i][j] = a[j][i];
  return t;
}

}  // namespace

MassProperties mass_properties(const std::vector<Vec3d>& vertices,
                               const std::vector<std::array<int, 3>>& triangles) {
  // Tetrahedra (o, a, b, c) from a reference point o near the body, to limit cancellation. With
  // D = a.(b x c): volume D/6, first moment D/24 (a+b+c), second moment
  // D/120 (a a^T + b b^T + c c^T + s s^T), s = a+b+c (Tonon, J. Math. Stat. 1, 2004).
  Vec3d origin;
  for (const Vec3d& v : vertices) origin += v;
  origin = origin / double(vertices.size());
  double volume = 0;
  Vec3d first_moment;
  Matrix3d second_moment{};
  for (const auto& t : triangles) {
    const Vec3d a = vertices[t[0]] - origin, b = vertices[t[1]] - origin,
                c = vertices[t[2]] - origin;
    const double d = triple(a, b, c);
    const Vec3d s = a + b + c;
    volume += d / 6;
    first_moment += s * (d / 24);
    add_outer(second_moment, a, a, d / 120);
    add_outer(second_moment, b, b, d / 120);
    add_outer(second_moment, c, c, d / 120);
    add_outer(second_moment, s, s, d / 120);
  }
  MassProperties props;
  props.volume = volume;
  const Vec3d centroid = first_moment / volume;
  props.centroid = origin + centroid;
  add_outer(second_moment, centroid, centroid, -volume);  // parallel-axis shift to the centroid
  const double trace = second_moment[0][0] + second_moment[1][1] + second_moment[2][2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) props.inertia[i][j] = (i == j ? trace : 0) - second_moment[i][j];
  return props;
}

SymmetricEigen symmetric_eigen(const Matrix3d& matrix) {
  Matrix3d a = matrix;
  Matrix3d v{};
  for (int i = 0; i < 3; ++i) v[i][i] = 1;
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 64; ++sweep) {
    bool rotated = false;
    for (const auto& pair : kPairs) {
      const int p = pair[0], q = pair[1];
      const double apq = a[p][q];
      // An off-diagonal this small moves the eigenvalues by less than 1e-15 relative; leaving it
      // keeps degenerate axes (cube, cylinder cross-section) aligned with the input axes.
      if (std::abs(apq) <= 0.5e-15 * (std::abs(a[p][p]) + std::abs(a[q][q]))) continue;
      rotated = true;
      // Numerical Recipes §11.1: the rotation in the (p, q) plane that zeroes a[p][q].
      const double theta = (a[q][q] - a[p][p]) / (2 * apq);
      const double t =
          std::abs(theta) > 1e150
              ? 0.5 / theta
              : (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
      const double c = 1 / std::sqrt(t * t + 1), s = t * c;
      Matrix3d rot{};
      for (int i = 0; i < 3; ++i) rot[i][i] = 1;
      rot[p][p] = c, rot[q][q] = c, rot[p][q] = s, rot[q][p] = -s;
      a = multiply(transpose(rot), multiply(a, rot));
      a[p][q] = a[q][p] = 0;
      v = multiply(v, rot);
    }
    if (!rotated) break;
  }
  SymmetricEigen eigen;
  std::array<int, 3> order = {0, 1, 2};
  const double scale = std::abs(a[0][0]) + std::abs(a[1][1]) + std::abs(a[2][2]);
  // Ascending; values equal to round-off keep their order (stable axes for symmetric shapes).
  for (int i = 1; i < 3; ++i)
    for (int j = i; j > 0 && a[order[j]][order[j]] < a[order[j - 1]][order[j - 1]] - 1e-14 * scale;
         --j)
      std::swap(order[j], order[j - 1]);
  for (int k = 0; k < 3; ++k) {
    eigen.values[k] = a[order[k]][order[k]];
    eigen.vectors[k] = {v[0][order[k]], v[1][order[k]], v[2][order[k]]};
  }
  if (triple(eigen.vectors[0], eigen.vectors[1], eigen.vectors[2]) < 0)
    eigen.vectors[2] = -eigen.vectors[2];
  return eigen;
}

Quatd quaternion_from_columns(const std::array<Vec3d, 3>& columns) {
  // Shepperd's method: pivot on the largest of w, x, y, z for accuracy.
  const auto r = [&](int i, int j) { return columns[j][i]; };
  const double trace = r(0, 0) + r(1, 1) + r(2, 2);
  Quatd q;
  if (trace >= r(0, 0) && trace >= r(1, 1) && trace >= r(2, 2)) {
    const double s = 2 * std::sqrt(1 + trace);
    q = {s / 4, (r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s};
  } else if (r(0, 0) >= r(1, 1) && r(0, 0) >= r(2, 2)) {
    const double s = 2 * std::sqrt(1 + r(0, 0) - r(1, 1) - r(2, 2));
    q = {(r(2, 1) - r(1, 2)) / s, s / 4, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s};
  } else if (r(1, 1) >= r(2, 2)) {
    const double s = 2 * std::sqrt(1 + r(1, 1) - r(0, 0) - r(2, 2));
    q = {(r(0, 2) - r(2, 0)) / s, (r(0, 1) + r(1, 0)) / s, s / 4, (r(1, 2) + r(2, 1)) / s};
  } else {
    const double s = 2 * std::sqrt(1 + r(2, 2) - r(0, 0) - r(1, 1));
    q = {(r(1, 0) - r(0, 1)) / s, (r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, s / 4};
  }
  return q.normalized();
}

ShapeTemplate make_template(const std::string& name, const std::vector<Vec3d>& points,
                            double rel_tol) {
  if (points.size() > kMaxTemplatePoints)
    throw std::runtime_error(std::to_string(points.size()) +
                             " points; a template is built from at most " +
                             std::to_string(kMaxTemplatePoints));
  const Hull convex = convex_hull_with_tolerance(points, rel_tol);
  const std::vector<std::array<int, 3>>& hull = convex.triangles;
  const double eps = convex.tolerance;

  // Faces: coplanar hull triangles merged. A face's boundary loop holds corners, and, where
  // convex_hull stopped its rebuilds short, a vertex on the edge between two faces; a hull vertex
  // inside a face (on no loop) is not a template vertex.
  std::vector<std::vector<int>> loops;
  for (const std::vector<int>& group : coplanar_groups(points, hull, eps))
    loops.push_back(group_boundary_loop(hull, group));
  // Template vertices in input order, renumbered 0..n-1.
  ShapeTemplate shape;
  shape.name = name;
  std::vector<int> new_index(points.size(), -1);
  for (const std::vector<int>& loop : loops)
    for (int v : loop) new_index[v] = 0;
  std::vector<Vec3d> input_vertices;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (new_index[i] == 0) {
      new_index[i] = int(input_vertices.size());
      input_vertices.push_back(points[i]);
      shape.input_indices.push_back(int(i));
    }
  for (const std::vector<int>& loop : loops) {
    Face face;
    for (int v : loop) face.loop.push_back(new_index[v]);
    std::rotate(face.loop.begin(), std::min_element(face.loop.begin(), face.loop.end()),
                face.loop.end());
    shape.faces.push_back(std::move(face));
  }
  // Output triangulation: a fan over each (convex) face loop.
  for (const Face& face : shape.faces)
    for (std::size_t k = 1; k + 1 < face.loop.size(); ++k)
      shape.triangles.push_back({face.loop[0], face.loop[k], face.loop[k + 1]});
  for (const Face& face : shape.faces)
    for (std::size_t k = 0; k < face.loop.size(); ++k) {
      const int a = face.loop[k], b = face.loop[(k + 1) % face.loop.size()];
      if (a < b) shape.edges.push_back({a, b});  // each edge is seen once in each direction
    }
  std::sort(shape.edges.begin(), shape.edges.end());
  const int n_vertices = int(input_vertices.size()), n_faces = int(shape.faces.size());
  if (n_vertices - int(shape.edges.size()) + n_faces != 2)
    throw std::runtime_error("the merged faces of the hull break Euler's formula");

  // Mass properties in the input frame, then the principal-axes body frame.
  const MassProperties props = mass_properties(input_vertices, shape.triangles);
  if (!(props.volume > 0)) throw std::runtime_error("the hull has no positive volume");
  const SymmetricEigen eigen = symmetric_eigen(props.inertia);
  shape.volume = props.volume;
  shape.principal_moments = eigen.values;
  shape.input_centroid = props.centroid;
  shape.body_to_input = quaternion_from_columns(eigen.vectors);
  for (const Vec3d& x : input_vertices) {
    const Vec3d d = x - props.centroid;
    // body = R^T (x - c): coordinates along the principal axes.
    shape.vertices.push_back(
        {dot(eigen.vectors[0], d), dot(eigen.vectors[1], d), dot(eigen.vectors[2], d)});
  }
  for (const Vec3d& v : shape.vertices)
    shape.bounding_radius = std::max(shape.bounding_radius, norm(v));

  // Face planes in the body frame: Newell's area-weighted normal, offset through the farthest
  // loop vertex so that every vertex satisfies dot(normal, x) <= offset.
  for (Face& face : shape.faces) {
    const Vec3d& base = shape.vertices[face.loop[0]];
    Vec3d area;
    for (std::size_t k = 1; k + 1 < face.loop.size(); ++k)
      area += cross(shape.vertices[face.loop[k]] - base, shape.vertices[face.loop[k + 1]] - base);
    face.normal = area / norm(area);
    face.offset = -1e300;
    for (int v : face.loop)
      face.offset = std::max(face.offset, dot(face.normal, shape.vertices[v]));
    if (!(face.offset > 0))
      throw std::runtime_error("the centroid is not inside a face plane of the hull");
  }
  return shape;
}

std::string shape_size_problem(double metres) {
  const auto g = [](double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", x);
    return std::string(text);
  };
  if (metres > kMaxShapeSize)
    return g(metres) + " m is beyond the largest size talus supports, " + g(kMaxShapeSize) + " m";
  if (metres < kMinShapeSize)
    return g(metres) + " m is below the smallest size talus supports, " + g(kMinShapeSize) + " m";
  return "";
}

Vec3d body_to_input_point(const ShapeTemplate& shape, const Vec3d& body_point) {
  return shape.input_centroid + rotate(shape.body_to_input, body_point);
}

double smallest_edge_bend_degrees(const ShapeTemplate& shape) {
  double smallest = 180;
  for (const auto& edge : shape.edges) {
    const Face* sharing[2] = {nullptr, nullptr};
    int count = 0;
    for (const Face& face : shape.faces)
      for (std::size_t k = 0; k < face.loop.size(); ++k) {
        const int a = face.loop[k], b = face.loop[(k + 1) % face.loop.size()];
        if ((a == edge[0] && b == edge[1]) || (a == edge[1] && b == edge[0])) {
          if (count < 2) sharing[count] = &face;
          ++count;
        }
      }
    if (count != 2)
      throw std::logic_error(shape.name + ": an edge is shared by " + std::to_string(count) +
                             " faces, expected 2");
    const double cosine = std::min(1.0, dot(sharing[0]->normal, sharing[1]->normal));
    smallest = std::min(smallest, std::acos(cosine) * 180 / std::acos(-1.0));
  }
  return smallest;
}

}  // namespace talus
