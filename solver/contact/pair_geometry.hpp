// The geometry of one particle-particle contact for the force laws (TALUS_HD, per pair):
// the volume model's overlap volume, vector area and point (polyhedra: GJK, Algorithm I, then the
// dual-space overlap, §2.3; spheres: the closed-form lens), and the linear model's penetration
// depth, normal and point (BLAZE-DEM's simple contact, geometry/simple_contact.hpp).
#pragma once

#include "solver/geometry/gjk.hpp"
#include "solver/geometry/overlap_polyhedra.hpp"
#include "solver/geometry/simple_contact.hpp"

namespace talus {

template <class Real>
struct PairGeometryData {
  bool in_contact = false;  // overlap with interior (volume) or delta > 0 (linear)
  bool degenerate = false;  // the geometry could not be computed (the step reports it)
  Vec3<Real> normal;        // unit, from A into B
  Vec3<Real> point;         // m (world)
  Real volume = 0;          // dV, m^3 (volume model)
  Real area = 0;            // A_n = |S|, m^2 (volume model)
  Real depth = 0;           // delta, m (linear model)
  // The overlap's surface moment on A's part of its boundary about `point`, m^3 (polyhedra in
  // the volume model: OverlapResult::surface_moment; zero for the spheres' lens, by symmetry).
  Vec3<Real> moment;
};

// Two spheres in the volume model: the lens of two caps. With x the distance of the plane where
// the surfaces meet from A's centre, the caps have heights h_a = r_a - x and h_b = r_b - (d - x),
// volumes pi h^2 (3 r - h) / 3 and centroids 3 (2 r - h)^2 / (4 (3 r - h)) from their sphere's
// centre; dV/dd = -pi a^2 with a^2 = r_a^2 - x^2, so A_n is the disc of the circle and n the
// centre line. One sphere inside the other has no such circle: degenerate.
template <class Real>
TALUS_HD inline PairGeometryData<Real> sphere_lens_geometry(const Vec3<Real>& centre_a,
                                                            Real radius_a,
                                                            const Vec3<Real>& centre_b,
                                                            Real radius_b) {
  PairGeometryData<Real> g;
  const Vec3<Real> line = centre_b - centre_a;
  const Real d = norm(line);
  if (!(d < radius_a + radius_b)) return g;
  if (d <= abs_of(radius_a - radius_b)) {
    g.degenerate = true;
    return g;
  }
  const Real pi = Real(3.14159265358979323846);
  const Vec3<Real> u = line / d;
  const Real x = (d * d + radius_a * radius_a - radius_b * radius_b) / (Real(2) * d);
  const Real h_a = radius_a - x, h_b = radius_b - (d - x);
  const Real v_a = pi * h_a * h_a * (Real(3) * radius_a - h_a) / Real(3);
  const Real v_b = pi * h_b * h_b * (Real(3) * radius_b - h_b) / Real(3);
  const Real k_a = Real(3) * (Real(2) * radius_a - h_a) * (Real(2) * radius_a - h_a) /
                   (Real(4) * (Real(3) * radius_a - h_a));
  const Real k_b = Real(3) * (Real(2) * radius_b - h_b) * (Real(2) * radius_b - h_b) /
                   (Real(4) * (Real(3) * radius_b - h_b));
  g.in_contact = true;
  g.volume = v_a + v_b;
  g.area = pi * (radius_a * radius_a - x * x);
  g.normal = u;
  g.point = ((centre_a + u * k_a) * v_a + (centre_b - u * k_b) * v_b) / g.volume;
  return g;
}

// The contact geometry of an overlap result (polyhedra_volume_geometry's last part; the GPU's
// phased pair stage computes the overlap in two kernels and finishes with this).
template <class Real>
TALUS_HD inline PairGeometryData<Real> volume_geometry_from(const OverlapResult<Real>& overlap) {
  PairGeometryData<Real> g;
  if (overlap.status == OverlapStatus::degenerate) {
    g.degenerate = true;
    return g;
  }
  const Real area = norm(overlap.vector_area);
  if (overlap.status != OverlapStatus::overlapping || !(area > 0) || !(overlap.volume > 0)) {
    return g;
  }
  g.in_contact = true;
  g.volume = overlap.volume;
  g.area = area;
  g.normal = overlap.vector_area / area;
  g.point = overlap.centroid;
  g.moment = overlap.surface_moment;
  return g;
}

// Two polyhedra in the volume model: GJK decides touching (never calls an overlapping pair
// separate), then the overlap in the caller's workspace (capacity from overlap_capacity_for).
// n = S / |S|, A_n = |S|, point = the overlap's centroid (docs/design.md, "Contact laws").
template <class Real, class Workspace>
TALUS_HD inline PairGeometryData<Real> polyhedra_volume_geometry(const ConvexView<Real>& a,
                                                                 const Pose<Real>& pose_a,
                                                                 const ConvexView<Real>& b,
                                                                 const Pose<Real>& pose_b,
                                                                 Workspace& workspace) {
  if (!gjk_intersect(a, pose_a, b, pose_b).intersecting) return PairGeometryData<Real>();
  return volume_geometry_from(overlap_polyhedra(a, pose_a, b, pose_b, workspace));
}

// The linear model's contact from a simple contact: only a positive depth pushes.
template <class Real>
TALUS_HD inline PairGeometryData<Real> from_simple_contact(const SimpleContact<Real>& s) {
  PairGeometryData<Real> g;
  if (!s.touching || !(s.depth > Real(0))) return g;
  g.in_contact = true;
  g.normal = s.normal;
  g.point = s.point;
  g.depth = s.depth;
  return g;
}

}  // namespace talus
