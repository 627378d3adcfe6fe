// The overlap oracle (tests/support/oracle.hpp) against closed forms, and its invariances; the
// random pose generators it is driven by.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tests/support/oracle.hpp"
#include "tests/support/random_poses.hpp"

namespace talus {
namespace {

using Real = long double;
using Quatl = Quat<long double>;

// A template from vertices and face loops given in any orientation: each loop is turned
// counter-clockwise seen from outside (the vertices are about an interior origin).
ShapeTemplate template_from_loops(std::vector<Vec3d> vertices,
                                  std::vector<std::vector<int>> loops) {
  ShapeTemplate shape;
  shape.vertices = std::move(vertices);
  for (std::vector<int>& loop : loops) {
    Vec3d area;
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
      const Vec3d& p0 = shape.vertices[loop[0]];
      area += cross(shape.vertices[loop[i]] - p0, shape.vertices[loop[i + 1]] - p0);
    }
    Face face;
    face.normal = area / norm(area);
    face.offset = dot(face.normal, shape.vertices[loop[0]]);
    if (face.offset < 0) {
      std::reverse(loop.begin(), loop.end());
      face.normal = -face.normal;
      face.offset = -face.offset;
    }
    face.loop = loop;
    shape.faces.push_back(face);
  }
  for (const Vec3d& v : shape.vertices)
    shape.bounding_radius = std::max(shape.bounding_radius, norm(v));
  return shape;
}

ShapeTemplate make_box(double hx, double hy, double hz) {
  std::vector<Vec3d> vertices;
  for (int i = 0; i < 8; ++i)  // bit 0: x, bit 1: y, bit 2: z; set bit = positive side
    vertices.push_back({(i & 1) ? hx : -hx, (i & 2) ? hy : -hy, (i & 4) ? hz : -hz});
  ShapeTemplate box = template_from_loops(
      vertices,
      {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}});
  box.volume = 8 * hx * hy * hz;
  return box;
}

// Volume of a template by tetrahedra from the origin, in long double.
Real template_volume(const ShapeTemplate& shape) {
  Real volume = 0;
  for (const Face& f : shape.faces)
    for (size_t i = 1; i + 1 < f.loop.size(); ++i)
      volume += triple(Vec3l(shape.vertices[f.loop[0]]), Vec3l(shape.vertices[f.loop[i]]),
                       Vec3l(shape.vertices[f.loop[i + 1]])) /
                6;
  return volume;
}

// Convex hull of a cloud in general position by brute force (every triple whose plane has all
// points on one side is a facet), moved so that its centroid is the origin.
ShapeTemplate brute_force_hull(std::vector<Vec3d> points) {
  const size_t n = points.size();
  std::vector<std::vector<int>> loops;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t k = j + 1; k < n; ++k) {
        const Vec3d normal = cross(points[j] - points[i], points[k] - points[i]);
        if (norm(normal) == 0) continue;
        int above = 0, below = 0;
        for (size_t l = 0; l < n; ++l) {
          if (l == i || l == j || l == k) continue;  // their distances are round-off only
          const double s = dot(normal, points[l] - points[i]);
          above += s > 0;
          below += s < 0;
        }
        if (above == 0 || below == 0) loops.push_back({int(i), int(j), int(k)});
      }
  // Shift to the centroid (tetrahedra from the cloud's mean, an interior point).
  Vec3d mean;
  for (const Vec3d& p : points) mean += p / double(n);
  Vec3l moment;
  Real volume = 0;
  for (const auto& t : loops) {
    const Vec3l a(points[t[0]] - mean), b(points[t[1]] - mean), c(points[t[2]] - mean);
    const Real tet = std::fabs(triple(a, b, c)) / 6;
    volume += tet;
    moment += (a + b + c) * (tet / 4);
  }
  const Vec3d centroid = mean + Vec3d(moment / volume);
  for (Vec3d& p : points) p -= centroid;
  ShapeTemplate hull = template_from_loops(points, loops);
  hull.volume = double(template_volume(hull));
  return hull;
}

Real relative_difference(const Vec3l& value, const Vec3l& expected, Real scale) {
  return norm(value - expected) / scale;
}

Posed pose_at(Vec3d position, Quatd orientation = Quatd()) {
  return Posed{position, orientation};
}

// ---- axis-aligned boxes: the intersection is a box -------------------------------------------

struct AlignedBox {
  Vec3d centre, half;
};

TEST(Oracle, AxisAlignedBoxesGiveTheBoxOfTheirIntersection) {
  const AlignedBox cases[][2] = {
      {{{0.1, -0.2, 0.3}, {0.5, 0.4, 0.3}}, {{0.6, 0.1, 0.05}, {0.35, 0.45, 0.2}}},
      {{{0, 0, 0}, {1, 1, 1}}, {{1.5, 1.25, -1.75}, {0.75, 0.5, 1}}},
      {{{3e-3, 1e-3, -2e-3}, {5e-3, 2e-3, 4e-3}}, {{-1e-3, 2.5e-3, 1e-3}, {3e-3, 1.5e-3, 4.5e-3}}},
  };
  for (const auto& pair : cases) {
    const AlignedBox& a = pair[0];
    const AlignedBox& b = pair[1];
    Vec3l low, high, expected_area_a;
    for (int k = 0; k < 3; ++k) {
      low[k] = std::max(Real(a.centre[k]) - a.half[k], Real(b.centre[k]) - b.half[k]);
      high[k] = std::min(Real(a.centre[k]) + a.half[k], Real(b.centre[k]) + b.half[k]);
    }
    const Vec3l size = high - low;
    const Real volume = size.x * size.y * size.z;
    for (int k = 0; k < 3; ++k) {
      // The intersection's +k face lies on A when A's +k face is the inner one (no ties here).
      const Real face_area = volume / size[k];
      if (Real(a.centre[k]) + a.half[k] < Real(b.centre[k]) + b.half[k])
        expected_area_a[k] += face_area;
      if (Real(a.centre[k]) - a.half[k] > Real(b.centre[k]) - b.half[k])
        expected_area_a[k] -= face_area;
    }
    const OracleResult r =
        oracle_overlap(make_box(a.half.x, a.half.y, a.half.z), pose_at(a.centre),
                       make_box(b.half.x, b.half.y, b.half.z), pose_at(b.centre));
    // Every step is a few long double roundings (relative 5e-20) of double data: 1e-15 is loose.
    const Real length = std::cbrt(volume);
    EXPECT_NEAR(double(r.volume / volume), 1.0, 1e-15);
    EXPECT_LT(relative_difference(r.centroid, (low + high) * 0.5L, length), 1e-15);
    EXPECT_LT(relative_difference(r.vector_area_a, expected_area_a, length * length), 1e-15);
    EXPECT_LT(relative_difference(r.vector_area_b, -expected_area_a, length * length), 1e-15);
    EXPECT_EQ(r.n_faces, 6);
  }
}

// ---- degenerate placements ----------------------------------------------------------------

TEST(Oracle, ShapeAgainstItsOwnCopyIsTheShape) {
  std::mt19937_64 rng(11);
  const ShapeTemplate shapes[] = {make_box(0.3, 0.2, 0.1),
                                  brute_force_hull(random_convex_cloud(rng, 20, 0.01))};
  for (const ShapeTemplate& shape : shapes) {
    const Posed pose = random_pose(rng, 0.05);
    const OracleResult r = oracle_overlap(shape, pose, shape, pose);
    // Every B plane passes through A's face to double round-off; the tolerance band keeps A whole.
    const Real volume = template_volume(shape);
    EXPECT_NEAR(double(r.volume / volume), 1.0, 1e-14);
    EXPECT_LT(relative_difference(r.centroid, Vec3l(pose.position), shape.bounding_radius), 1e-14);
    EXPECT_EQ(r.n_faces, int(shape.faces.size()));
  }
}

TEST(Oracle, NestedShapeIsTheInnerShape) {
  const ShapeTemplate big = make_box(1.0, 0.8, 0.9);
  const ShapeTemplate small = make_box(0.2, 0.1, 0.15);  // bounding radius 0.27 < 0.8
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 10; ++trial) {
    const Posed big_pose = random_pose(rng, 1.0);
    Posed small_pose{big_pose.position + Vec3d{0.3, -0.2, 0.1}, random_rotation(rng)};
    for (const bool small_first : {true, false}) {
      const OracleResult r = small_first ? oracle_overlap(small, small_pose, big, big_pose)
                                         : oracle_overlap(big, big_pose, small, small_pose);
      EXPECT_NEAR(double(r.volume / small.volume), 1.0, 1e-14);
      EXPECT_LT(relative_difference(r.centroid, Vec3l(small_pose.position), 0.27L), 1e-14);
      EXPECT_EQ(r.n_faces, 6);
      // Every face of the result is the inner box's: none may be attributed to the outer one.
      EXPECT_EQ(norm(small_first ? r.vector_area_b : r.vector_area_a), 0.0L);
    }
  }
}

TEST(Oracle, TouchingAndSeparateShapesHaveNoOverlap) {
  const ShapeTemplate box = make_box(0.5, 0.5, 0.5);
  const Quatd tilt = Quatd::from_axis_angle(Vec3d{0, 0, 1}, 0.7853981633974483);  // 45 degrees
  const std::pair<Posed, Posed> placements[] = {
      {pose_at({0, 0, 0}), pose_at({1, 0.3, -0.2})},                      // face on face
      {pose_at({0, 0, 0}), pose_at({1, 1, 0})},                           // edge on edge
      {pose_at({0, 0, 0}), pose_at({1, 1, 1})},                           // vertex on vertex
      {pose_at({0, 0, 0}), pose_at({0.5 + std::sqrt(0.5), 0, 0}, tilt)},  // edge on face
      {pose_at({0, 0, 0}), pose_at({1.01, 0, 0})},                        // separate
      {pose_at({0, 0, 0}), pose_at({3, -2, 1}, tilt)},                    // far apart
  };
  for (const auto& [pose_a, pose_b] : placements) {
    for (const OracleResult& r :
         {oracle_overlap(box, pose_a, box, pose_b), oracle_overlap(box, pose_b, box, pose_a)}) {
      // Touching leaves at most a flat contact: no volume beyond the on-plane tolerance band.
      EXPECT_LE(r.volume, 1e-14L);
      EXPECT_EQ(r.n_faces, 0);
    }
  }
}

// ---- random pairs: closure, symmetry, invariance, gradient -----------------------------------

struct RandomCase {
  ShapeTemplate a, b;
  PosePair poses;
};

std::vector<RandomCase> random_cases(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::vector<RandomCase> cases;
  for (int i = 0; i < count; ++i) {
    RandomCase c;
    if (i % 2 == 0) {
      std::uniform_real_distribution<double> half(0.002, 0.01);
      c.a = make_box(half(rng), half(rng), half(rng));
      c.b = make_box(half(rng), half(rng), half(rng));
    } else {
      c.a = brute_force_hull(random_convex_cloud(rng, 8 + i % 33, 0.02));
      c.b = brute_force_hull(random_convex_cloud(rng, 40 - i % 33, 0.015));
    }
    c.poses = random_overlapping_pair(rng, c.a.bounding_radius, c.b.bounding_radius, 0.0, 0.7);
    cases.push_back(std::move(c));
  }
  return cases;
}

// Round-off of the double data (a template's vertices vs its planes, poses re-rounded after a
// rigid motion) moves each surface by some displacement delta ~ 1e-16 R. The volume then changes
// by at most delta * boundary area, V * centroid (about the centroid) by that times the size R,
// and the vector areas by delta times the faces' perimeters (~ boundary area / depth). So these
// errors are measured in units of the surfaces' displacement, not relative to V, which a shallow
// contact makes small.
struct SurfaceShiftErrors {
  Real volume, centroid, vector_area;
};
SurfaceShiftErrors shift_errors(const OracleResult& r, const Vec3l& centroid, Real volume,
                                const Vec3l& vector_area_a, Real radius) {
  const Real area = r.boundary_area, depth = r.volume / r.boundary_area;
  return {std::fabs(r.volume - volume) / (area * radius),
          norm(r.centroid - centroid) * r.volume / (area * radius * radius),
          norm(r.vector_area_a - vector_area_a) * depth / (area * radius)};
}

TEST(Oracle, BoundaryOfTheIntersectionIsClosed) {
  int overlapping = 0;
  const std::vector<RandomCase> cases = random_cases(21, 60);
  for (size_t i = 0; i < cases.size(); ++i) {
    const RandomCase& c = cases[i];
    const OracleResult r = oracle_overlap(c.a, c.poses.a, c.b, c.poses.b);
    if (r.volume == 0) continue;
    ++overlapping;
    EXPECT_GE(r.n_faces, 4);
    // Sum of area * normal over a closed surface is 0.
    const Real residual = norm(r.vector_area_a + r.vector_area_b);
    if (i % 2 == 0) {
      // Boxes: exact planes, three per vertex; the faces agree with their normals to long double
      // round-off, so 1e-15 of the boundary's area is loose. (Relative to |S| it would not be: S
      // may be a small difference of large opposite faces.)
      EXPECT_LT(residual / r.boundary_area, 1e-15);
    } else {
      // Hulls: where more than three of B's planes (double data) meet at a vertex they miss a
      // common point by ~1e-16 R, and the on-plane snap moves vertices by up to that: a surface
      // displacement error, measured as in shift_errors.
      EXPECT_LT(residual * (r.volume / r.boundary_area) / (r.boundary_area * c.a.bounding_radius),
                1e-14);
    }
  }
  EXPECT_GE(overlapping, 30);  // the generator must produce overlapping pairs
}

TEST(Oracle, SymmetricAndInvariantUnderACommonRigidMotion) {
  std::mt19937_64 rng(33);
  int overlapping = 0;
  for (const RandomCase& c : random_cases(22, 60)) {
    const OracleResult ab = oracle_overlap(c.a, c.poses.a, c.b, c.poses.b);
    const OracleResult ba = oracle_overlap(c.b, c.poses.b, c.a, c.poses.a);
    const Posed motion = random_pose(rng, 0.1);
    auto moved = [&](const Posed& p) {
      return Posed{motion.position + rotate(motion.orientation, p.position),
                   motion.orientation * p.orientation};
    };
    const OracleResult moved_ab = oracle_overlap(c.a, moved(c.poses.a), c.b, moved(c.poses.b));
    if (ab.volume == 0 || ba.volume == 0 || moved_ab.volume == 0) {
      // Either all are empty or the contact is within the on-plane tolerance band of touching.
      EXPECT_LE(std::max({ab.volume, ba.volume, moved_ab.volume}), 1e-14L * c.a.volume);
      continue;
    }
    ++overlapping;
    const Real radius = std::max(c.a.bounding_radius, c.b.bounding_radius);
    // B-then-A: A's faces are B's in this order, and vice versa.
    const SurfaceShiftErrors swapped =
        shift_errors(ba, ab.centroid, ab.volume, ab.vector_area_b, radius);
    const Quatl q(motion.orientation);
    const SurfaceShiftErrors moved_errors =
        shift_errors(moved_ab, Vec3l(motion.position) + rotate(q, ab.centroid), ab.volume,
                     rotate(q, ab.vector_area_a), radius);
    for (const SurfaceShiftErrors& e : {swapped, moved_errors}) {
      EXPECT_LT(e.volume, 1e-14);
      EXPECT_LT(e.centroid, 1e-14);
      EXPECT_LT(e.vector_area, 1e-14);
    }
  }
  EXPECT_GE(overlapping, 30);
}

TEST(Oracle, VectorAreaOnAIsMinusTheVolumeGradientInBsPosition) {
  int checked = 0;
  for (const RandomCase& c : random_cases(23, 40)) {
    const OracleResult r = oracle_overlap(c.a, c.poses.a, c.b, c.poses.b);
    if (r.volume == 0) continue;
    ++checked;
    // Step relative to the overlap's size, so that a shallow overlap is still resolved.
    const double step = 1e-5 * double(std::cbrt(r.volume));
    for (int k = 0; k < 3; ++k) {
      Posed plus = c.poses.b, minus = c.poses.b;
      plus.position[k] += step;
      minus.position[k] -= step;
      const Real dv = oracle_overlap(c.a, c.poses.a, c.b, plus).volume -
                      oracle_overlap(c.a, c.poses.a, c.b, minus).volume;
      // Moving B along S (from A into B) shrinks the overlap: dV/dx_B = -S. Central difference
      // of a piecewise cubic: truncation ~(step / size)^2 = 1e-10 of |S|; 1e-8 leaves room for a
      // change of the intersection's combinatorics within the step.
      const double derivative = double(dv / (Real(plus.position[k]) - Real(minus.position[k])));
      EXPECT_NEAR(derivative, -double(r.vector_area_a[k]), 1e-8 * double(norm(r.vector_area_a)));
    }
  }
  EXPECT_GE(checked, 20);
}

// ---- plane clipping and sections ------------------------------------------------------------

// Volume of the box [-h, h] (body frame) with dot(m, y) <= e, by inclusion-exclusion over the
// corners of simplices {z >= 0, dot(m, z) <= t}, of volume t^3 / (6 m_x m_y m_z).
Real box_volume_below_plane(const Vec3d& h, Vec3l m, Real e) {
  Real t = e + dot(m, Vec3l(h));  // y = z - h, z in [0, 2h]
  for (int k = 0; k < 3; ++k)
    if (m[k] < 0) {  // reflect z_k -> 2 h_k - z_k so that every m_k > 0
      t -= 2 * h[k] * m[k];
      m[k] = -m[k];
    }
  Real volume = 0;
  for (int corner = 0; corner < 8; ++corner) {
    Real shifted = t;
    int sign = 1;
    for (int k = 0; k < 3; ++k)
      if (corner & (1 << k)) {
        shifted -= 2 * h[k] * m[k];
        sign = -sign;
      }
    if (shifted > 0) volume += sign * shifted * shifted * shifted;
  }
  return volume / (6 * m.x * m.y * m.z);
}

Vec3l polygon_vector_area(const std::vector<Vec3l>& p) {
  Vec3l sum;
  for (size_t i = 1; i + 1 < p.size(); ++i) sum += cross(p[i] - p[0], p[i + 1] - p[0]) * 0.5L;
  return sum;
}

TEST(Oracle, VolumeBelowATiltedPlaneMatchesTheClosedForm) {
  const Vec3d half{0.3, 0.2, 0.1};
  const ShapeTemplate box = make_box(half.x, half.y, half.z);
  std::mt19937_64 rng(44);
  for (int trial = 0; trial < 20; ++trial) {
    const Posed pose = random_pose(rng, 1.0);
    const Vec3l n = Vec3l(rotate(random_rotation(rng), Vec3d{0, 0, 1})) * 2.5L;  // not unit
    const Real reach = norm(n) * norm(Vec3l(half));
    const Real offset =
        dot(n, Vec3l(pose.position)) + reach * std::uniform_real_distribution<Real>(-1, 1)(rng);
    const Quatl q(pose.orientation);
    const Real expected =
        box_volume_below_plane(half, rotate_inverse(q, n), offset - dot(n, Vec3l(pose.position)));
    const OracleResult below = oracle_clip_by_plane(box, pose, n, offset);
    const OracleResult above = oracle_clip_by_plane(box, pose, -n, -offset);
    // Closed form and clipping both in long double from the same double data; the closed form's
    // inclusion-exclusion cancels terms of size (reach)^3, so allow 1e-14 of the box volume.
    EXPECT_NEAR(double(below.volume), double(expected), 1e-14 * box.volume);
    EXPECT_EQ(oracle_volume_below_plane(box, pose, n, offset), below.volume);
    EXPECT_NEAR(double(below.volume + above.volume), box.volume, 1e-14 * box.volume);
    // The two parts balance about the box centre; the cut face is the section polygon.
    const Vec3l moment = below.centroid * below.volume + above.centroid * above.volume;
    EXPECT_LT(relative_difference(moment / Real(box.volume), Vec3l(pose.position), 0.4L), 1e-14);
    const std::vector<Vec3l> section = oracle_section_polygon(box, pose, n, offset);
    if (below.volume > 0 && above.volume > 0) {
      const Vec3l cap = polygon_vector_area(section);
      EXPECT_LT(relative_difference(below.vector_area_b, cap, norm(cap)), 1e-15);
      EXPECT_LT(relative_difference(above.vector_area_b, -cap, norm(cap)), 1e-15);
    }
  }
}

TEST(Oracle, OverlapWithAHugeTiltedBoxIsTheVolumeBelowItsFace) {
  const Vec3d half{0.3, 0.2, 0.1};
  const ShapeTemplate box = make_box(half.x, half.y, half.z);
  const ShapeTemplate wall = make_box(50, 50, 50);
  std::mt19937_64 rng(45);
  for (int trial = 0; trial < 10; ++trial) {
    const Posed pose = random_pose(rng, 0.5);
    const Quatd wall_orientation = random_rotation(rng);
    const Vec3d up = rotate(wall_orientation, Vec3d{0, 0, 1});
    // The wall's +z face passes at signed distance `gap` from the box centre, cutting the box.
    const double gap = std::uniform_real_distribution<double>(-0.3, 0.3)(rng);
    const Posed wall_pose{pose.position + up * (gap - 50), wall_orientation};
    const Real offset = dot(Vec3l(up), Vec3l(wall_pose.position)) + 50;
    const Real expected = oracle_volume_below_plane(box, pose, Vec3l(up), offset);
    const Real closed_form =
        box_volume_below_plane(half, rotate_inverse(Quatl(pose.orientation), Vec3l(up)),
                               offset - dot(Vec3l(up), Vec3l(pose.position)));
    // The wall's other faces are 50 m away: only its +z face cuts. Offsets of 50 m carry a
    // double round-off of 1e-14 m into the plane, i.e. 1e-13 of the box volume.
    EXPECT_NEAR(double(oracle_overlap(box, pose, wall, wall_pose).volume), double(closed_form),
                1e-12 * box.volume);
    EXPECT_NEAR(double(expected), double(closed_form), 1e-14 * box.volume);
  }
}

TEST(Oracle, SectionsOfACube) {
  const double a = 0.02, h = a / 2;  // edge and half edge
  const ShapeTemplate cube = make_box(h, h, h);
  const Posed pose{Vec3d{0.1, -0.3, 0.2}, Quatd()};
  const Vec3l centre(pose.position);
  const Vec3l n = Vec3l(1, 1, 1) / std::sqrt(3.0L);
  // Through the centre perpendicular to a body diagonal: a regular hexagon through the edge
  // midpoints, side a / sqrt(2), area (3 sqrt(3) / 2) (a^2 / 2) = 3 sqrt(3) a^2 / 4.
  const std::vector<Vec3l> hexagon = oracle_section_polygon(cube, pose, n, dot(n, centre));
  ASSERT_EQ(hexagon.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(double(norm(hexagon[i] - centre)), a / std::sqrt(2.0), 1e-17);
    EXPECT_NEAR(double(dot(n, hexagon[i] - centre)), 0.0, 1e-18);
    // Counter-clockwise about n: each turn is positive.
    const Vec3l turn = cross(hexagon[(i + 1) % 6] - hexagon[i], hexagon[(i + 2) % 6] - hexagon[i]);
    EXPECT_GT(dot(turn, n), 0);
  }
  EXPECT_NEAR(double(dot(polygon_vector_area(hexagon), n)), 3 * std::sqrt(3.0) / 4 * a * a, 1e-18);
  // Cutting off the corner (h, h, h) at depth t along each edge: equilateral triangle of side
  // t sqrt(2), area sqrt(3) t^2 / 2.
  const Real t = 0.3L * a;
  const std::vector<Vec3l> triangle =
      oracle_section_polygon(cube, pose, n, dot(n, centre + Vec3l(h, h, h)) - t / std::sqrt(3.0L));
  ASSERT_EQ(triangle.size(), 3u);
  EXPECT_NEAR(double(dot(polygon_vector_area(triangle), n)), double(std::sqrt(3.0L) / 2 * t * t),
              1e-19);
  // A face lying on the plane is the section, oriented about the given normal.
  const std::vector<Vec3l> face =
      oracle_section_polygon(cube, pose, Vec3l(-1, 0, 0), -(centre.x - h));
  ASSERT_EQ(face.size(), 4u);
  EXPECT_NEAR(double(polygon_vector_area(face).x), -a * a, 1e-18);
  // A plane past the cube, and one touching only an edge.
  EXPECT_TRUE(oracle_section_polygon(cube, pose, n, dot(n, centre) + a).empty());
  EXPECT_TRUE(
      oracle_section_polygon(cube, pose, Vec3l(1, 1, 0), centre.x + centre.y + 2 * h).empty());
}

// ---- random pose generators ----------------------------------------------------------------

TEST(RandomPoses, DeterministicForASeed) {
  std::mt19937_64 first(7), second(7);
  for (int i = 0; i < 5; ++i) {
    const PosePair p = random_overlapping_pair(first, 0.01, 0.02, 0.0, 0.1);
    const PosePair q = random_overlapping_pair(second, 0.01, 0.02, 0.0, 0.1);
    EXPECT_EQ(p.b.position.x, q.b.position.x);
    EXPECT_EQ(p.b.orientation.w, q.b.orientation.w);
  }
  EXPECT_EQ(random_convex_cloud(first, 9, 1.0)[8].z, random_convex_cloud(second, 9, 1.0)[8].z);
}

TEST(RandomPoses, RotationsAreUniformOnSO3) {
  std::mt19937_64 rng(8);
  const int samples = 20000;
  double mean[3][3] = {}, mean_square[3][3] = {};
  for (int s = 0; s < samples; ++s) {
    const Quatd q = random_rotation(rng);
    ASSERT_NEAR(q.norm(), 1.0, 1e-15);
    const Mat3<double> r = rotation_matrix(q);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        mean[i][j] += r.m[i][j] / samples;
        mean_square[i][j] += r.m[i][j] * r.m[i][j] / samples;
      }
  }
  // Haar measure: E[R_ij] = 0 and E[R_ij^2] = 1/3; standard errors 0.0041 and 0.0020, so 5 sigma
  // bounds are 0.02 and 0.01. A non-uniform map (e.g. uniform Euler angles) breaks them.
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(mean[i][j], 0.0, 0.02);
      EXPECT_NEAR(mean_square[i][j], 1.0 / 3, 0.01);
    }
}

TEST(RandomPoses, PairsSitAtTheAskedDepthAndCloudsInTheirEllipsoid) {
  std::mt19937_64 rng(9);
  for (int i = 0; i < 100; ++i) {
    const PosePair p = random_overlapping_pair(rng, 0.01, 0.03, 0.02, 0.1);
    const double fraction = 1 - norm(p.b.position - p.a.position) / 0.04;
    EXPECT_GE(fraction, 0.02 - 1e-12);
    EXPECT_LE(fraction, 0.1 + 1e-12);
    EXPECT_LE(std::fabs(p.a.position.x), 0.04);
  }
  const std::vector<Vec3d> cloud = random_convex_cloud(rng, 40, 0.5);
  ASSERT_EQ(cloud.size(), 40u);
  double largest = 0;
  for (const Vec3d& v : cloud) largest = std::max(largest, norm(v));
  EXPECT_LE(largest, 0.25);          // semi-axes at most size / 2
  EXPECT_GE(largest, 0.85 * 0.125);  // and at least size / 4, radial factor >= 0.85
  EXPECT_GE(brute_force_hull(cloud).faces.size(), 20u);  // most points on the hull
}

}  // namespace
}  // namespace talus
