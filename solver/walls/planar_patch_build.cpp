#include "solver/walls/planar_patch_build.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace talus {

namespace {

Vec3d area_vector(const std::vector<Vec3d>& v, const std::array<int, 3>& t) {
  return cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]);  // twice the area, along the normal
}

// The patch of facets [first, end), all in one plane: false when they do not tile one convex
// polygon (see the header).
bool make_patch(const std::vector<Vec3d>& vertices,
                const std::vector<std::array<int, 3>>& triangles, int first, int end, double size,
                PlanarPatch<double>& patch) {
  Vec3d sum;
  double facet_area = 0;
  std::map<std::pair<int, int>, int> directed;  // edge -> how many facets run along it
  for (int t = first; t < end; ++t) {
    const Vec3d a = area_vector(vertices, triangles[t]);
    sum += a;
    facet_area += 0.5 * norm(a);
    for (int k = 0; k < 3; ++k) ++directed[{triangles[t][k], triangles[t][(k + 1) % 3]}];
  }
  const double twice_area = norm(sum);
  if (!(twice_area > 0)) return false;
  const Vec3d n = sum / twice_area;
  // The boundary: edges whose reverse no facet of the run has; each start vertex once.
  std::map<int, int> next;
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;  // two facets along one edge the same way: overlapping
    if (directed.count({edge.second, edge.first})) continue;
    if (!next.emplace(edge.first, edge.second).second) return false;
  }
  if (next.size() < 3) return false;
  std::vector<Vec3d> loop;
  int at = next.begin()->first;
  for (std::size_t k = 0; k < next.size(); ++k) {
    loop.push_back(vertices[at]);
    const auto it = next.find(at);
    if (it == next.end()) return false;
    at = it->second;
  }
  if (at != next.begin()->first) return false;  // more than one loop
  const std::size_t m = loop.size();
  // Convex and counter-clockwise about n: every turn to the left (or straight); the polygon's
  // area (the loop's) equal to the facets' (no hole, no fold).
  Vec3d loop_sum, centroid;
  for (std::size_t k = 0; k < m; ++k) {
    const Vec3d& p = loop[k];
    const Vec3d& q = loop[(k + 1) % m];
    const Vec3d& r = loop[(k + 2) % m];
    const Vec3d e0 = q - p, e1 = r - q;
    if (dot(cross(e0, e1), n) < -1e-12 * norm(e0) * norm(e1)) return false;
    const Vec3d fan = cross(p - loop[0], q - loop[0]);
    loop_sum += fan;
    centroid += (loop[0] + p + q) * (dot(fan, n) / 3);
  }
  const double loop_twice_area = dot(loop_sum, n);
  if (!(loop_twice_area > 0)) return false;
  if (std::fabs(0.5 * loop_twice_area - facet_area) > 1e-9 * facet_area) return false;
  centroid = centroid / loop_twice_area;
  double inradius = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < m; ++k) {
    const Vec3d e = loop[(k + 1) % m] - loop[k];
    const double length = norm(e);
    if (!(length > 0)) continue;
    inradius = std::min(inradius, dot(cross(e, centroid - loop[k]), n) / length);
  }
  inradius -= 1e-9 * size;
  if (!(inradius > 0) || !std::isfinite(inradius)) return false;
  patch.centre = centroid;
  patch.normal = n;
  patch.inradius = inradius;
  patch.first = first;
  patch.end = end;
  return true;
}

}  // namespace

template <class Real>
std::vector<PlanarPatch<Real>> find_planar_patches(
    const std::vector<Vec3d>& vertices, const std::vector<std::array<int, 3>>& triangles) {
  std::vector<PlanarPatch<Real>> patches;
  double size = 0;
  for (const Vec3d& v : vertices) size = std::max(size, norm(v));
  const int facets = static_cast<int>(triangles.size());
  for (const auto& t : triangles) {
    for (const int k : t) {
      if (k < 0 || k >= static_cast<int>(vertices.size()) || !is_finite(vertices[k])) {
        return patches;  // the facet grid's build names such a mesh's error
      }
    }
  }
  int first = 0;
  while (first < facets && static_cast<int>(patches.size()) < kMaxPatchesPerWall) {
    const Vec3d a = area_vector(vertices, triangles[first]);
    const double twice = norm(a);
    int end = first + 1;
    if (twice > 0) {
      const Vec3d n = a / twice;
      const double offset = dot(n, vertices[triangles[first][0]]);
      const auto in_plane = [&](int t) {
        const Vec3d b = area_vector(vertices, triangles[t]);
        const double l = norm(b);
        if (!(l > 0) || !(dot(b, n) > 0) || norm(cross(b / l, n)) > 1e-9) return false;
        for (const int k : triangles[t]) {
          if (std::fabs(dot(n, vertices[k]) - offset) > 1e-9 * size) return false;
        }
        return true;
      };
      while (end < facets && in_plane(end)) ++end;
    }
    PlanarPatch<double> p;
    if (end - first >= kMinPatchFacets && make_patch(vertices, triangles, first, end, size, p)) {
      PlanarPatch<Real> r;
      r.centre = Vec3<Real>(p.centre);
      r.normal = Vec3<Real>(p.normal);
      r.inradius = Real(p.inradius);
      r.first = p.first;
      r.end = p.end;
      patches.push_back(r);
    }
    first = end;
  }
  return patches;
}

template std::vector<PlanarPatch<float>> find_planar_patches<float>(
    const std::vector<Vec3d>&, const std::vector<std::array<int, 3>>&);
template std::vector<PlanarPatch<double>> find_planar_patches<double>(
    const std::vector<Vec3d>&, const std::vector<std::array<int, 3>>&);

}  // namespace talus
