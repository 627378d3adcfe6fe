#include "reference/contact/contact_geometry.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "reference/geometry/exact_overlap.hpp"

namespace talus::reference {

namespace {

Eigen::Vector3d to_eigen_v(const Vec3d& v) {
  return {v.x, v.y, v.z};
}

// Volume of a spherical cap of height h on a sphere of radius r, and the distance of its centroid
// from the sphere's centre (towards the cap).
double cap_volume(double r, double h) {
  return M_PI * h * h * (3 * r - h) / 3;
}
double cap_centroid_distance(double r, double h) {
  return 3 * (2 * r - h) * (2 * r - h) / (4 * (3 * r - h));
}

}  // namespace

PairGeometry volume_geometry(const ShapeTemplate& a, const RefPose& pose_a, const ShapeTemplate& b,
                             const RefPose& pose_b) {
  PairGeometry g;
  const RefOverlap overlap = exact_overlap(a, pose_a, b, pose_b);
  const double area = overlap.vector_area_a.norm();
  if (!overlap.overlapping || !(area > 0) || !(overlap.volume > 0)) return g;
  g.in_contact = true;
  g.volume = overlap.volume;
  g.area = area;
  g.normal = overlap.vector_area_a / area;  // dV/dx_A = +S: from A into B
  g.point = overlap.centroid;
  g.moment = overlap.surface_moment_a;
  return g;
}

PairGeometry sphere_lens_geometry(const Eigen::Vector3d& centre_a, double radius_a,
                                  const Eigen::Vector3d& centre_b, double radius_b) {
  PairGeometry g;
  const Eigen::Vector3d line = centre_b - centre_a;
  const double d = line.norm();
  if (d >= radius_a + radius_b) return g;
  if (d <= std::abs(radius_a - radius_b)) {
    throw std::invalid_argument(
        "reference sphere lens: one sphere lies inside the other (centre distance " +
        std::to_string(d) + " m): the volume model has no contact normal there");
  }
  const Eigen::Vector3d u = line / d;
  // The plane of the circle where the surfaces meet, at distance x from A's centre.
  const double x = (d * d + radius_a * radius_a - radius_b * radius_b) / (2 * d);
  const double h_a = radius_a - x, h_b = radius_b - (d - x);
  const double v_a = cap_volume(radius_a, h_a), v_b = cap_volume(radius_b, h_b);
  g.in_contact = true;
  g.volume = v_a + v_b;
  g.area = M_PI * (radius_a * radius_a - x * x);  // the circle's disc: dV/dd = -pi a^2
  g.normal = u;
  const Eigen::Vector3d c_a = centre_a + cap_centroid_distance(radius_a, h_a) * u;
  const Eigen::Vector3d c_b = centre_b - cap_centroid_distance(radius_b, h_b) * u;
  g.point = (v_a * c_a + v_b * c_b) / g.volume;
  return g;
}

PairGeometry linear_polyhedra_geometry(const ShapeTemplate& a, const RefPose& pose_a,
                                       const ShapeTemplate& b, const RefPose& pose_b) {
  const std::vector<Eigen::Vector3d> va = world_vertices(a, pose_a), vb = world_vertices(b, pose_b);
  const Eigen::Matrix3d ra = pose_a.orientation.normalized().toRotationMatrix();
  const Eigen::Matrix3d rb = pose_b.orientation.normalized().toRotationMatrix();
  std::vector<Eigen::Vector3d> axes;
  for (const Face& f : a.faces) axes.push_back(ra * to_eigen_v(f.normal));
  for (const Face& f : b.faces) axes.push_back(rb * to_eigen_v(f.normal));
  for (const auto& ea : a.edges) {
    const Eigen::Vector3d da = va[ea[1]] - va[ea[0]];
    for (const auto& eb : b.edges) {
      const Eigen::Vector3d db = vb[eb[1]] - vb[eb[0]];
      const Eigen::Vector3d axis = da.cross(db);
      // Parallel edges add no face to the Minkowski difference (their face normals are there).
      if (axis.norm() <= 1e-12 * da.norm() * db.norm()) continue;
      axes.push_back(axis.normalized());
    }
  }
  if (a.faces.empty() || b.faces.empty()) {
    throw std::invalid_argument("reference linear contact: templates '" + a.name + "' and '" +
                                b.name + "' need their merged faces");
  }
  PairGeometry g;
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& axis : axes) {
    double min_a = std::numeric_limits<double>::infinity(), max_a = -min_a;
    double min_b = min_a, max_b = -min_a;
    for (const Eigen::Vector3d& p : va) {
      const double s = axis.dot(p);
      min_a = std::min(min_a, s), max_a = std::max(max_a, s);
    }
    for (const Eigen::Vector3d& p : vb) {
      const double s = axis.dot(p);
      min_b = std::min(min_b, s), max_b = std::max(max_b, s);
    }
    const double forward = max_a - min_b, backward = max_b - min_a;  // B ahead of / behind A
    const double overlap = std::min(forward, backward);
    if (overlap <= 0) return PairGeometry{};  // a separating axis
    if (overlap < best) {
      best = overlap;
      g.normal = forward <= backward ? axis : Eigen::Vector3d(-axis);
    }
  }
  const RefOverlap overlap = exact_overlap(a, pose_a, b, pose_b);
  if (!overlap.overlapping) return PairGeometry{};  // the rounded axes saw a touching pair
  g.in_contact = true;
  g.depth = best;
  g.point = overlap.centroid;
  return g;
}

PairGeometry linear_sphere_geometry(const Eigen::Vector3d& centre_a, double radius_a,
                                    const Eigen::Vector3d& centre_b, double radius_b) {
  PairGeometry g;
  const Eigen::Vector3d line = centre_b - centre_a;
  const double d = line.norm();
  if (d >= radius_a + radius_b) return g;
  if (d == 0) {
    throw std::invalid_argument("reference linear contact: two spheres share a centre");
  }
  g.in_contact = true;
  g.normal = line / d;
  g.depth = radius_a + radius_b - d;
  g.point = 0.5 * ((centre_a + radius_a * g.normal) + (centre_b - radius_b * g.normal));
  return g;
}

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

PairGeometry linear_polyhedron_sphere_geometry(const ShapeTemplate& a, const RefPose& pose_a,
                                               const Eigen::Vector3d& centre_b, double radius_b) {
  if (a.faces.empty() || a.triangles.empty()) {
    throw std::invalid_argument("reference linear contact: template '" + a.name +
                                "' needs its faces and triangles");
  }
  const std::vector<Eigen::Vector3d> va = world_vertices(a, pose_a);
  const Eigen::Matrix3d ra = pose_a.orientation.normalized().toRotationMatrix();
  // Signed distance of the centre to each face plane (outward positive).
  double nearest = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d nearest_normal = Eigen::Vector3d::UnitZ();
  for (const Face& f : a.faces) {
    const Eigen::Vector3d n = ra * to_eigen_v(f.normal);
    const double s = n.dot(centre_b - pose_a.position) - f.offset;
    if (s > nearest) nearest = s, nearest_normal = n;
  }
  PairGeometry g;
  Eigen::Vector3d surface = Eigen::Vector3d::Zero();
  if (nearest <= 0) {  // centre inside (or on): leave through the nearest face
    g.normal = nearest_normal;
    g.depth = radius_b - nearest;
    surface = centre_b - nearest * nearest_normal;
  } else {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : a.triangles) {
      const Eigen::Vector3d q = closest_point_on_triangle(centre_b, va[t[0]], va[t[1]], va[t[2]]);
      const double d = (centre_b - q).norm();
      if (d < best) best = d, surface = q;
    }
    if (best >= radius_b) return g;
    g.normal = (centre_b - surface) / best;
    g.depth = radius_b - best;
  }
  g.in_contact = true;
  g.point = 0.5 * (surface + (centre_b - radius_b * g.normal));
  return g;
}

}  // namespace talus::reference
