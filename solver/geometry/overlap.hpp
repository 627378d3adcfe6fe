// Overlap of two convex polyhedra (paper §2.3): the intersection polytope by the polar (dual-space)
// transform about an interior point and an incremental Quickhull in a fixed workspace
// (Algorithms II-VI), its volume (Eq. 9), the vector area S of its boundary on particle A, and its
// centroid.
#pragma once

#include <stdexcept>
#include <string>

#include "solver/geometry/convex.hpp"

namespace talus {

enum class OverlapStatus : int {
  separate = 0,     // no common point
  touching = 1,     // common points but no interior (volume 0 up to round-off)
  overlapping = 2,  // a proper intersection polytope was built
  degenerate = 3,   // the computation could not be completed (workspace too small, non-finite
                    // input); the result is zero and finite
};

TALUS_HD inline const char* to_string(OverlapStatus s) {
  switch (s) {
    case OverlapStatus::separate:
      return "separate";
    case OverlapStatus::touching:
      return "touching";
    case OverlapStatus::overlapping:
      return "overlapping";
    default:
      return "degenerate";
  }
}

template <class Real>
struct OverlapResult {
  OverlapStatus status = OverlapStatus::separate;
  Real volume = 0;  // m^3 (Eq. 9)
  // Vector area of the part of the intersection boundary lying on A's surface, with A's outward
  // normals. It points from A into B: moving A along S grows the overlap, so dV/dx_A = +S and
  // dV/dx_B = -S (Feng's energy-conserving normal); the contact normal is n = S/|S| and the
  // projected area A_n = |S|. The normal force on A is along -S.
  Vec3<Real> vector_area;
  Vec3<Real> centroid;  // world frame; meaningful when status == overlapping
  // The moment about the centroid of the same part of the boundary, integral of (r - c) x n dA,
  // m^3: a pressure p on that part gives A the force -p S and, besides (c - x_A) x (-p S), the
  // couple -p M. That is dU/dtheta_A of a potential U(V) exactly (the rigid rotation's change of V
  // is the integral of (w x (r - x_A)) . n over the part), so an overlap-volume law applying it
  // conserves energy where the centroid alone as the point does not (docs/contact.md).
  Vec3<Real> surface_moment;
  Real depth_hint = 0;  // inradius of the intersection (Chebyshev-centre LP value), m
  int hull_points = 0;  // dual points that entered the hull (planes that bound the intersection)
  bool workspace_overrun = false;  // asserted false by the tests
  // Decided by the vertex enumeration (vertex_enumeration.hpp) rather than the LP and the dual
  // hull; depth_hint is then a lower bound of the inradius, not the LP's value.
  bool enumerated = false;
  // The dual hull failed on a slab thinner than its resolution and the pair is reported as
  // touching (overlap_polyhedra.hpp, below_dual_resolution).
  bool thin_slab = false;
};

// Which planes enter the dual hull. Both filters are exact (docs/geometry.md); they are switches
// so that the benchmarks can show what each one gains against the naive hull of every plane.
struct OverlapOptions {
  // Drop a face plane whose half-space holds the other body strictly inside (bounding sphere,
  // then vertices); also gives the separating-plane exit.
  bool cull_planes = true;
  // Also drop a plane whose face polygon lies outside the other body (needs the templates' face
  // loops; only with cull_planes).
  bool cull_faces = true;
  // Try the vertex enumeration first when at most kEnumerationPlanes planes are kept
  // (vertex_enumeration.hpp); it declines whatever it cannot certify, which then goes to the LP
  // and the dual hull as without it.
  bool enumerate = true;
};

// The benchmarks' named variants: "naive" (every plane), "planes" (cull_planes only), "faces"
// (both) — these three always build the dual hull — and "vertices" (both culls and the vertex
// enumeration: the default options). Host only.
inline OverlapOptions overlap_options_named(const std::string& name) {
  OverlapOptions options;
  if (name == "vertices") return options;
  options.enumerate = false;
  if (name == "naive") {
    options.cull_planes = options.cull_faces = false;
  } else if (name == "planes") {
    options.cull_faces = false;
  } else if (name != "faces") {
    throw std::invalid_argument("overlap variant '" + name +
                                "': expected one of naive, planes, faces, vertices");
  }
  return options;
}

}  // namespace talus
