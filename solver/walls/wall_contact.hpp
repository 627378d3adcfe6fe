// One particle against one wall (paper §2.4), as TALUS_HD functions (one thread per particle and
// wall on the GPU): the wall's facets reached by the particle (those its bounding sphere meets,
// found through the wall's facet grid, facet_grid.hpp, or by testing each), each clipped by
// Sutherland-Hodgman
// (geometry/wall_clip.hpp, Algorithm VII), combined into ONE contact per particle and wall with
// the area weights w = overlap area / section area, so that a section spread over several
// coplanar facets (an edge, a vertex) counts once. The wall is rigid and infinitely large: its
// E/R term of Eqs. 13 and 19 vanishes and m_eff of Eq. 15 is the particle's mass.
//   volume laws: F^e = sum_i w_i p(dV_i) A_i n_i (K = E/R of the particle, A_i the facet plane's
//                section area, dV_i the volume below it, p the law's pressure, contact/laws/):
//                volume_paper p = K dV^(1/3) (Eq. 12) with k_n = sum_i w_i K A_i (Eq. 13);
//                volume p = K min(dV / A_ref, dV^(1/3)) with k_n = sum_i w_i p'(dV_i) A_i^2;
//                the stored energy sum_i w_i U(dV_i);
//   linear model: F^e = sum_i w_i K_N delta_i n_i, energy sum_i w_i K_N delta_i^2 / 2;
// n = -F^e / |F^e| (from the particle into the wall), the point = the overlap-area-weighted mean
// of the clipped sections' centroids (volume_paper: each moved to where the volume below its
// plane has its centroid, as between particles; the default law keeps the section's centroid,
// the exact torque of its potential, and takes its tilt stiffness from the rocking spring of
// force_law.hpp's patch_couple). Spheres
// (linear model) use the nearest-facet rule: the closest point q of the wall's surface to the
// centre, delta = r - |c - q|, exact across facet edges and vertices.
#pragma once

#include <cmath>

#include "solver/contact/laws/law_common.hpp"
#include "solver/geometry/simple_contact.hpp"
#include "solver/geometry/wall_clip.hpp"
#include "solver/walls/facet_grid.hpp"
#include "solver/walls/planar_patch.hpp"

namespace talus {

// A wall's prescribed rigid motion (scene/wall_motion.hpp places its triangles; this gives the
// velocity of its material point at x, for the relative velocity at the contact point).
template <class Real>
struct WallMotionData {
  int kind = 0;            // 0 none, 1 rotation, 2 translation
  Vec3<Real> axis;         // unit (rotation)
  Vec3<Real> point;        // on the axis (rotation)
  Real angular_speed = 0;  // rad/s
  Vec3<Real> velocity;     // m/s (translation)
  TALUS_HD Vec3<Real> angular_velocity() const {
    return kind == 1 ? axis * angular_speed : Vec3<Real>();
  }
  TALUS_HD Vec3<Real> velocity_at(const Vec3<Real>& x) const {
    if (kind == 1) return cross(axis, x - point) * angular_speed;
    if (kind == 2) return velocity;
    return Vec3<Real>();
  }
};

// The facets of one wall where they are now: triangle t has corners corners[3 t .. 3 t + 2],
// for t < count (the present facets: a closed outlet's plate, the mesh's last triangles, is gone
// once the outlet opens). With a grid (facet_grid.hpp, in the mesh's frame, which sits at
// world = rotate(rotation, mesh) + translation) a particle visits only the facets listed near
// it; without one, every facet (brute force). Both give the same bits.
template <class Real>
struct WallFacets {
  const Vec3<Real>* corners = nullptr;
  int count = 0;
  FacetGridView<Real> grid;
  Quat<Real> rotation;
  Vec3<Real> translation;
  // The wall's planar patches (planar_patch.hpp, mesh frame; at most kMaxPatchesPerWall), each
  // clipped as one plane where it holds a particle's circle.
  const PlanarPatch<Real>* patches = nullptr;
  int patch_count = 0;

  // The facets that the sphere (centre, radius) may reach, ascending.
  TALUS_HD FacetCursor<Real> near(const Vec3<Real>& centre, Real radius) const {
    if (!grid.present()) return FacetCursor<Real>(count);
    return FacetCursor<Real>(grid, count, rotation, translation, centre, radius);
  }
};

// The geometry of one particle-wall contact, before the force law.
template <class Real>
struct WallContactGeometry {
  bool in_contact = false;
  bool degenerate = false;        // a facet's clipping failed (capacity, non-finite input)
  Vec3<Real> normal;              // unit, from the particle into the wall
  Vec3<Real> point;               // m (world)
  Real elastic = 0;               // |F^e|, N
  Real normal_stiffness = 0;      // k_n (volume laws, above), N/m
  Real tangential_stiffness = 0;  // sum w_i G A_i (volume laws), N/m
  Real area = 0;                  // sum w_i A_i, m^2
  Real potential = 0;             // the stored normal elastic energy, J
  // The elastic forces' couple about `point`: sum over the facets of (c_i - point) x F_i, N m.
  // One force at one point turns the particle as the facets' forces at their own points do only
  // when the facets are coplanar; at an edge or a corner of a wall it does not, and the
  // difference is work from nothing (a spinning cube thrown into a box's corner, e = 1, gained
  // 25 % in 0.15 s with the sum at one point, 9.8 % with this couple; docs/contact.md).
  Vec3<Real> couple;
};

// The facets a polyhedron of bounding radius `radius` at `position` is clipped against, in order:
// each facet the search yields within the bounding sphere, or for a planar patch that holds the
// particle its stand-in (planar_patch.hpp; the patch's other facets skipped, and all of a patch
// whose plane the particle does not reach). `visit(a, b, c)` gets each triangle's corners and
// returns false to stop. The wall stage runs this and the clipping in one loop on the host
// (polyhedron_wall_geometry) and as separate kernels on the GPU, where a particle's facets are
// clipped by threads of their own (step/cuda/cuda_wall_stage.cu).
template <class Real, class Visit>
TALUS_HD inline void visit_wall_facets(const Vec3<Real>& position, Real radius,
                                       const WallFacets<Real>& facets, Visit&& visit) {
  // The patches that hold the particle's circle (bit k of `held`: patch k), clipped once each at
  // their first facet that the search yields, and those whose plane it does not reach (`clear`),
  // none of whose facets count.
  unsigned held = 0, clear = 0;
  for (int k = 0; k < facets.patch_count; ++k) {
    const PlanarPatch<Real>& patch = facets.patches[k];
    if (patch.end > facets.count) continue;
    const PatchHit<Real> hit =
        patch_hit(patch, facets.rotation, facets.translation, position, radius);
    if (hit.holds) held |= 1u << k;
    if (hit.clear) clear |= 1u << k;
  }
  FacetCursor<Real> near = facets.near(position, radius);
  for (int t = near.next(); t >= 0; t = near.next()) {
    Vec3<Real> a, b, c;
    int patch_state = 0;  // 1: the stand-in of a held patch; 2: a clear patch's facet
    for (int k = 0; (held | clear) != 0 && k < facets.patch_count; ++k) {
      const PlanarPatch<Real>& patch = facets.patches[k];
      if (((held | clear) & (1u << k)) == 0 || t < patch.first || t >= patch.end) continue;
      near.skip_below(patch.end);
      if (held & (1u << k)) {
        patch_stand_in(patch_hit(patch, facets.rotation, facets.translation, position, radius),
                       radius, a, b, c);
        patch_state = 1;
      } else {
        patch_state = 2;
      }
      break;
    }
    if (patch_state == 2) continue;
    if (patch_state == 0) {
      a = facets.corners[3 * t];
      b = facets.corners[3 * t + 1];
      c = facets.corners[3 * t + 2];
      // Facets beyond the bounding sphere cannot be reached. First, cheaply, a facet whose plane
      // is farther (a grid cell lists a curved wall's every segment near it, most of which face
      // the particle from beyond its reach): the plane is never farther than the triangle, so
      // this skips only facets the exact test below would skip; its margin (1e-3 of the squared
      // distance) is far above the round-off of either test, so they never disagree.
      const Vec3<Real> n = cross(b - a, c - a);
      const Real d = dot(n, position - a);
      if (d * d > Real(1.001) * radius * radius * dot(n, n)) continue;
      if (norm(closest_point_on_triangle(position, a, b, c) - position) > radius) continue;
    }
    if (!visit(a, b, c)) return;
  }
}

// The area-weighted sum of a polyhedron's clipped facets under the contact law Law (contact/laws/:
// each facet's elastic part, Law::facet_elastic), added facet by facet in visit_wall_facets'
// order, then finished into one contact. `stiffness` is K = E/R (volume laws) or K_N (linear),
// `shear` G = E / (2 (1 + nu) R) and `reference_area` A_ref = pi R^2 (volume laws only).
template <class Law, class Real>
struct WallGeometrySum {
  WallContactGeometry<Real> g;
  Vec3<Real> elastic, moment, force_moment;  // force_moment: sum c_i x F_i about the origin
  Real area_sum = 0;
  Real stiffness = 0, shear = 0, reference_area = 0;

  TALUS_HD WallGeometrySum(Real stiffness_, Real shear_, Real reference_area_)
      : stiffness(stiffness_), shear(shear_), reference_area(reference_area_) {}

  // One facet's clipping; false (and g.degenerate) when it failed: the sum stops there.
  TALUS_HD bool add(const WallContact<Real>& wc) {
    if (wc.status == WallContactStatus::degenerate) {
      g.degenerate = true;
      return false;
    }
    if (!(wc.overlap_area > Real(0)) || !(wc.section_area > Real(0))) return true;
    // The weight is not clamped to 1: the clipped area never exceeds the section's but for
    // round-off, and the weights must be the reference's definition to agree with it.
    const Real w = wc.overlap_area / wc.section_area;
    const Vec3<Real> elastic_before = elastic;
    // The paper's volume law's point is the overlap volume's centroid, as between particles: the
    // clipped section's centroid moved by the volume's offset from the section's (wall_clip.hpp).
    Vec3<Real> point = wc.overlap_centroid;
    if constexpr (Law::kVolumeGeometry) {
      if (!(wc.volume_below > Real(0))) return true;
      const NormalElastic<Real> e =
          Law::facet_elastic(w, stiffness, reference_area, wc.volume_below, wc.section_area);
      elastic += wc.normal * e.force;
      g.normal_stiffness += e.stiffness;
      g.potential += e.energy;
      g.tangential_stiffness += w * shear * wc.section_area;  // Eq. 19
      // The laws with the patch couple take the exact torque of U(V): for a plane, a rotation
      // changes the volume below it by the section's moment, so the force acts at the section's
      // centroid (the overlap's boundary on the particle and the section have opposite moments).
      if constexpr (!Law::kPatchCouple) point = wc.overlap_centroid + wc.volume_offset;
    } else {
      if (!(wc.depth > Real(0))) return true;
      const NormalElastic<Real> e = Law::facet_elastic(w, stiffness, wc.depth);
      elastic += wc.normal * e.force;
      g.potential += e.energy;
    }
    moment += point * wc.overlap_area;
    force_moment += cross(point, elastic - elastic_before);
    area_sum += wc.overlap_area;
    g.area += w * wc.section_area;
    return true;
  }

  TALUS_HD WallContactGeometry<Real> finish() {
    const Real magnitude = norm(elastic);
    if (g.degenerate || !(area_sum > Real(0)) || !(magnitude > Real(0))) return g;
    g.in_contact = true;
    g.normal = elastic / (-magnitude);
    g.point = moment / area_sum;
    g.elastic = magnitude;
    g.couple = force_moment - cross(g.point, elastic);
    return g;
  }
};

// A polyhedron against one wall under the contact law Law: its facets (visit_wall_facets), each
// clipped, summed (WallGeometrySum).
template <class Law, class Real>
TALUS_HD inline WallContactGeometry<Real> polyhedron_wall_geometry(const ConvexView<Real>& shape,
                                                                   const Pose<Real>& pose,
                                                                   const WallFacets<Real>& facets,
                                                                   Real stiffness, Real shear,
                                                                   Real reference_area) {
  WallGeometrySum<Law, Real> sum(stiffness, shear, reference_area);
  visit_wall_facets(pose.position, shape.bounding_radius, facets,
                    [&](const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
                      return sum.add(clip_against_triangle_sized(shape, pose, a, b, c));
                    });
  return sum.finish();
}

// A sphere against one wall, linear model: the nearest-facet rule. The point is midway between
// q and the sphere's deepest point c + r n.
template <class Real>
TALUS_HD inline WallContactGeometry<Real> sphere_wall_geometry(const Vec3<Real>& centre,
                                                               Real radius,
                                                               const WallFacets<Real>& facets,
                                                               Real stiffness) {
  WallContactGeometry<Real> g;
  Real best = Real(0);
  bool any = false;
  Vec3<Real> q = centre;
  // Only the facets within the radius can decide a contact: the grid's pruning keeps the
  // nearest one (and ties, in order) whenever it is.
  FacetCursor<Real> near = facets.near(centre, radius);
  for (int t = near.next(); t >= 0; t = near.next()) {
    const Vec3<Real> x = closest_point_on_triangle(
        centre, facets.corners[3 * t], facets.corners[3 * t + 1], facets.corners[3 * t + 2]);
    const Real d = norm(x - centre);
    if (!any || d < best) {
      best = d;
      q = x;
      any = true;
    }
  }
  if (!any || !(best < radius) || !(best > Real(0))) return g;  // apart, or centre on the wall
  g.in_contact = true;
  g.normal = (q - centre) / best;
  g.point = (q + (centre + g.normal * radius)) * Real(0.5);
  g.elastic = stiffness * (radius - best);
  g.potential = Real(0.5) * g.elastic * (radius - best);
  return g;
}

}  // namespace talus
