// Flat convex parts of a wall made of many facets (a cylinder's or a drum's cap, an outlet's
// plate: fans of `segments` thin triangles about the centre), and the test that lets the wall
// contact treat such a part as one plane (wall_contact.hpp).
//
// Why: a particle lying on a fan meets every thin triangle under it, up to all of them near the
// centre, and each costs a full clipping (wall_clip.hpp) of the same section in the same plane;
// a 1,024-segment drum's caps made the GPU wall stage cost more than three steps of a 1e6 bed.
// When the circle in which the particle's bounding sphere meets the plane lies inside the
// patch's polygon, the particle's section lies inside it too, so the area weights of the patch's
// facets (overlap area / section area) add up to one and every facet has the same section, volume
// below and normal: the facets' weighted sum is exactly one contact with the whole plane. The
// wall contact then clips the particle once against a stand-in triangle of that plane large
// enough to hold the circle, and skips the patch's facets. Outside that circle test (a particle
// at the patch's rim) it clips the facets as before. The two agree up to round-off (the stand-in
// plane is the patch's, the facets' planes are their corners'); tests/walls/test_planar_patch.cpp
// compares them.
//
// The patches are found on the host from the mesh itself (planar_patch_build.hpp), in the mesh's
// frame, as the facet grid is: a moving wall maps the particle's centre back by its transform.
#pragma once

#include "solver/core/hd.hpp"
#include "solver/core/math.hpp"
#include "solver/core/quat.hpp"
#include "solver/core/vec3.hpp"
#include "solver/walls/facet_grid.hpp"

namespace talus {

// One patch: facets [first, end) of the wall's mesh lie in one plane and tile a convex polygon
// that holds the disc of `inradius` about `centre`.
template <class Real>
struct PlanarPatch {
  Vec3<Real> centre;  // mesh frame, m
  Vec3<Real> normal;  // unit, mesh frame: the facets' normal (towards the particles)
  Real inradius = 0;  // m, already less a margin for the facets' own round-off
  int first = 0, end = 0;
};

// The plane of a patch where the wall is now and where the particle meets it.
template <class Real>
struct PatchHit {
  bool holds = false;  // the sphere's circle in the plane lies inside the patch
  bool clear = false;  // the sphere does not reach the plane: no facet of the patch counts
  Vec3<Real> foot;     // the sphere's centre projected onto the plane (world), m
  Vec3<Real> normal;   // the patch's normal (world)
};

// Whether the sphere (centre, radius; world) meets patch `p`'s plane only inside the patch, or
// not at all, the
// wall's mesh being at world = rotate(rotation, mesh) + translation. The test keeps a margin for
// the round-off of mapping the centre back, as the facet grid's query does (facet_grid_margin of
// the magnitudes involved; 2.3e-13 of them in double, 1.2e-4 in float).
template <class Real>
TALUS_HD inline PatchHit<Real> patch_hit(const PlanarPatch<Real>& p, const Quat<Real>& rotation,
                                         const Vec3<Real>& translation, const Vec3<Real>& centre,
                                         Real radius) {
  PatchHit<Real> hit;
  const Real margin =
      facet_grid_margin(norm(centre) + norm(translation) + norm(p.centre) + p.inradius + radius);
  const Vec3<Real> local = rotate_inverse(rotation, centre - translation);
  const Vec3<Real> offset = local - p.centre;
  const Real height = dot(offset, p.normal);
  const Vec3<Real> in_plane = offset - p.normal * height;
  if (!is_finite(local)) return hit;
  // A sphere clear of the plane (by more than the round-off of the height) is farther than its
  // radius from each of the patch's facets, which the wall contact would each test and skip.
  if (abs_of(height) > radius + margin) {
    hit.clear = true;
    return hit;
  }
  // Only a sphere that reaches the plane: then the facet under the foot is within the sphere's
  // box, so the facet grid yields one of the patch's facets as brute force does.
  if (!(abs_of(height) <= radius) || !(norm(in_plane) + radius + margin <= p.inradius)) {
    return hit;
  }
  hit.holds = true;
  hit.foot = rotate(rotation, p.centre + in_plane) + translation;
  hit.normal = rotate(rotation, p.normal);
  return hit;
}

// The stand-in facet for a patch hit: the equilateral triangle about the foot whose inscribed
// circle has radius 2 `radius` (so it holds every section of a particle within that bounding
// radius, with room for round-off), wound so that its normal (b - a) x (c - a) is hit.normal.
template <class Real>
TALUS_HD inline void patch_stand_in(const PatchHit<Real>& hit, Real radius, Vec3<Real>& a,
                                    Vec3<Real>& b, Vec3<Real>& c) {
  const Vec3<Real>& n = hit.normal;
  // u: any unit vector across n (the coordinate axis least aligned with it, crossed), v = n x u.
  const Real ax = abs_of(n.x), ay = abs_of(n.y), az = abs_of(n.z);
  const Vec3<Real> pick = (ax <= ay && ax <= az) ? Vec3<Real>(1, 0, 0)
                          : (ay <= az)           ? Vec3<Real>(0, 1, 0)
                                                 : Vec3<Real>(0, 0, 1);
  Vec3<Real> u = cross(pick, n);
  u = u / norm(u);
  const Vec3<Real> v = cross(n, u);
  // Circumradius 4 r (inradius 2 r); corners at 90, 210 and 330 degrees, counter-clockwise
  // about n since (u, v, n) is right-handed.
  const Real s = Real(4) * radius;
  const Real half = s * Real(0.5), across = s * Real(0.86602540378443864676);
  a = hit.foot + v * s;
  b = hit.foot - u * across - v * half;
  c = hit.foot + u * across - v * half;
}

}  // namespace talus
