#include "solver/shape/hull.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace talus {
namespace {

// Key of the directed edge a -> b.
std::uint64_t edge_key(int a, int b) {
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

struct HullFace {
  std::array<int, 3> v;
  Vec3d normal;  // unit, outward
  double offset = 0;
  std::vector<int> outside;  // conflict list: points strictly above this face's plane
  bool alive = true;
};

// Thrown when round-off at the current tolerance leaves the hull inconsistent (a face without a
// well-defined plane, a horizon that is not one loop); the caller retries with a larger tolerance.
struct DegenerateHull {};

// Incremental Quickhull: each step takes the point farthest above some face, removes the faces
// it sees (a connected region grown from that face), and fans new faces from the point to the
// region's boundary (the horizon). A point within `eps` of the current hull is never added,
// which keeps duplicates and near-coplanar points out.
class IncrementalHull {
 public:
  IncrementalHull(const std::vector<Vec3d>& points, double eps) : points_(points), eps_(eps) {}

  // The hull of all points, inserting `first` (which must span a volume) before the others:
  // the others enter only where they lie more than eps outside the hull of `first`.
  std::vector<std::array<int, 3>> run(const std::vector<int>& first) {
    build_simplex(first);
    std::vector<int> pending;
    for (int f = 0; f < int(faces_.size()); ++f) pending.push_back(f);
    // Rescanning every point against the final faces also catches points that were dropped as
    // inside while the hull was smaller but end up outside it after its faces turned.
    do {
      while (!pending.empty()) {
        const int f = pending.back();
        pending.pop_back();
        if (!faces_[f].alive || faces_[f].outside.empty()) continue;
        add_point(f, pending);
      }
    } while (rescan(pending));
    std::vector<std::array<int, 3>> triangles;
    for (const HullFace& face : faces_)
      if (face.alive) triangles.push_back(face.v);
    return triangles;
  }

 private:
  double distance(const HullFace& face, int p) const {
    return dot(face.normal, points_[p]) - face.offset;
  }

  // Puts every point lying more than eps above a face in that face's conflict list. A hull
  // vertex above a face means the surface folded (it is no longer convex).
  bool rescan(std::vector<int>& pending) {
    std::vector<bool> is_vertex(points_.size(), false);
    for (const HullFace& face : faces_)
      if (face.alive)
        for (int v : face.v) is_vertex[v] = true;
    bool found = false;
    for (int p = 0; p < int(points_.size()); ++p) {
      for (int f = 0; f < int(faces_.size()); ++f) {
        if (!faces_[f].alive || distance(faces_[f], p) <= eps_) continue;
        if (is_vertex[p]) throw DegenerateHull{};
        faces_[f].outside.push_back(p);
        pending.push_back(f);
        found = true;
        break;
      }
    }
    return found;
  }

  int add_face(int a, int b, int c) {
    HullFace face;
    face.v = {a, b, c};
    const Vec3d& pa = points_[a];
    const Vec3d n = cross(points_[b] - pa, points_[c] - pa);
    // A triangle lower than eps over its longest side has no reliable plane at this tolerance.
    const double longest =
        std::max({norm(points_[b] - pa), norm(points_[c] - pa), norm(points_[c] - points_[b])});
    if (!(norm(n) > 0.5 * eps_ * longest) || !std::isfinite(norm(n))) throw DegenerateHull{};
    face.normal = n / norm(n);
    face.offset = dot(face.normal, (pa + points_[b] + points_[c]) / 3.0);
    const int id = int(faces_.size());
    faces_.push_back(std::move(face));
    for (int k = 0; k < 3; ++k)
      edge_face_[edge_key(faces_[id].v[k], faces_[id].v[(k + 1) % 3])] = id;
    return id;
  }

  void remove_face(int f) {
    faces_[f].alive = false;
    for (int k = 0; k < 3; ++k)
      edge_face_.erase(edge_key(faces_[f].v[k], faces_[f].v[(k + 1) % 3]));
  }

  int neighbour(int a, int b) const { return edge_face_.at(edge_key(b, a)); }

  void build_simplex(const std::vector<int>& subset) {
    const auto dist2 = [&](int i, int j) { return norm2(points_[i] - points_[j]); };
    // Two far-apart points among the axis extremes.
    std::array<int, 6> extremes;
    extremes.fill(subset[0]);
    for (int i : subset)
      for (int axis = 0; axis < 3; ++axis) {
        if (points_[i][axis] < points_[extremes[2 * axis]][axis]) extremes[2 * axis] = i;
        if (points_[i][axis] > points_[extremes[2 * axis + 1]][axis]) extremes[2 * axis + 1] = i;
      }
    int i0 = extremes[0], i1 = extremes[1];
    for (int a = 0; a < 6; ++a)
      for (int b = a + 1; b < 6; ++b)
        if (dist2(extremes[a], extremes[b]) > dist2(i0, i1)) i0 = extremes[a], i1 = extremes[b];
    const std::string count = std::to_string(subset.size()) + " points ";
    if (std::sqrt(dist2(i0, i1)) <= eps_)
      throw std::runtime_error("convex_hull: the " + count +
                               "all coincide; a hull needs at least 4 non-coplanar points");
    // The point farthest from the line i0-i1, then the one farthest from that plane.
    const Vec3d axis = (points_[i1] - points_[i0]) / std::sqrt(dist2(i0, i1));
    int i2 = i0;
    double best = 0;
    for (int i : subset) {
      const double d = norm(cross(points_[i] - points_[i0], axis));
      if (d > best) best = d, i2 = i;
    }
    if (best <= eps_)
      throw std::runtime_error("convex_hull: the " + count +
                               "are collinear; a hull needs at least 4 non-coplanar points");
    Vec3d n = cross(points_[i1] - points_[i0], points_[i2] - points_[i0]);
    n = n / norm(n);
    int i3 = i0;
    best = 0;
    for (int i : subset) {
      const double d = std::abs(dot(n, points_[i] - points_[i0]));
      if (d > best) best = d, i3 = i;
    }
    if (best <= eps_)
      throw std::runtime_error("convex_hull: the " + count +
                               "are coplanar; a hull needs at least 4 non-coplanar points");
    if (dot(n, points_[i3] - points_[i0]) > 0) std::swap(i1, i2);  // (i0, i1, i2) faces away
    add_face(i0, i1, i2);
    add_face(i0, i3, i1);
    add_face(i1, i3, i2);
    add_face(i2, i3, i0);
    for (int i : subset) {
      if (i == i0 || i == i1 || i == i2 || i == i3) continue;
      assign(i, 0, 4);
    }
  }

  // Puts point p in the conflict list of the first face among [first, last) it lies above.
  void assign(int p, int first, int last) {
    for (int f = first; f < last; ++f) {
      if (distance(faces_[f], p) > eps_) {
        faces_[f].outside.push_back(p);
        return;
      }
    }
  }

  // Faces seen from p (distance above `threshold`), grown from `seed`, and the horizon: the
  // directed edges of seen faces whose neighbour is not seen. True when the horizon is one
  // simple loop, as it is for a point outside a convex polyhedron.
  bool find_visible(int seed, int p, double threshold, std::vector<int>& visible,
                    std::vector<std::array<int, 2>>& horizon) {
    visible.assign(1, seed);
    horizon.clear();
    ++stamp_;
    mark_.resize(faces_.size(), 0);
    seen_.resize(faces_.size(), false);
    mark_[seed] = stamp_;
    seen_[seed] = true;
    for (std::size_t q = 0; q < visible.size(); ++q) {
      const HullFace& face = faces_[visible[q]];
      for (int k = 0; k < 3; ++k) {
        const int a = face.v[k], b = face.v[(k + 1) % 3];
        const int g = neighbour(a, b);
        if (mark_[g] != stamp_) {
          mark_[g] = stamp_;
          seen_[g] = distance(faces_[g], p) > threshold;
          if (seen_[g]) visible.push_back(g);
        }
        if (!seen_[g]) horizon.push_back({a, b});
      }
    }
    std::unordered_map<int, int> next;
    for (const auto& e : horizon)
      if (!next.emplace(e[0], e[1]).second) return false;  // pinched at a vertex
    int v = horizon[0][0];
    for (std::size_t steps = 0; steps < horizon.size(); ++steps) {
      const auto it = next.find(v);
      if (it == next.end()) return false;
      v = it->second;
      if (v == horizon[0][0]) return steps + 1 == horizon.size();  // one loop covers all
    }
    return false;
  }

  void add_point(int f, std::vector<int>& pending) {
    std::vector<int>& outside = faces_[f].outside;
    int p = outside[0];
    for (int q : outside)
      if (distance(faces_[f], q) > distance(faces_[f], p)) p = q;
    std::vector<int> visible;
    std::vector<std::array<int, 2>> horizon;
    // Round-off can leave a nearly coplanar face unseen inside the seen region; counting faces
    // within eps as seen repairs that (their vertices are then within eps of the new hull).
    if (!find_visible(f, p, eps_, visible, horizon) && !find_visible(f, p, -eps_, visible, horizon))
      throw DegenerateHull{};
    std::vector<int> orphans;
    for (int g : visible) {
      for (int q : faces_[g].outside)
        if (q != p) orphans.push_back(q);
      faces_[g].outside.clear();
      faces_[g].outside.shrink_to_fit();
      remove_face(g);
    }
    const int first_new = int(faces_.size());
    for (const auto& e : horizon) pending.push_back(add_face(e[0], e[1], p));
    for (int q : orphans) assign(q, first_new, int(faces_.size()));
  }

  const std::vector<Vec3d>& points_;
  const double eps_;
  std::vector<HullFace> faces_;
  std::unordered_map<std::uint64_t, int> edge_face_;  // directed edge -> face holding it
  std::vector<int> mark_;
  std::vector<bool> seen_;
  int stamp_ = 0;
};

}  // namespace

double hull_tolerance(const std::vector<Vec3d>& points, double rel_tol) {
  if (points.empty()) return 0;
  Vec3d low = points[0], high = points[0];
  for (const Vec3d& p : points)
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = std::min(low[axis], p[axis]);
      high[axis] = std::max(high[axis], p[axis]);
    }
  return rel_tol * std::max({high.x - low.x, high.y - low.y, high.z - low.z});
}

namespace {

// One attempt at a fixed absolute tolerance: the hull, then the hull again with the corners
// inserted first. A point added early (when it was outside) may end up inside a facet or an edge
// of the final hull, where it lies on fewer than 3 facets; inserted after the corners it is
// within eps of their hull and stays out.
std::vector<std::array<int, 3>> hull_at_tolerance(const std::vector<Vec3d>& points, double eps) {
  std::vector<int> first(points.size());
  std::iota(first.begin(), first.end(), 0);
  for (int pass = 0; pass < 4; ++pass) {
    std::vector<std::array<int, 3>> triangles = IncrementalHull(points, eps).run(first);
    const std::vector<std::vector<int>> groups = coplanar_groups(points, triangles, eps);
    std::unordered_map<int, std::vector<int>> groups_of_vertex;
    for (int g = 0; g < int(groups.size()); ++g)
      for (int t : groups[g])
        for (int v : triangles[t]) {
          std::vector<int>& list = groups_of_vertex[v];
          if (std::find(list.begin(), list.end(), g) == list.end()) list.push_back(g);
        }
    std::vector<int> corners;
    for (const auto& entry : groups_of_vertex)
      if (entry.second.size() >= 3) corners.push_back(entry.first);
    if (corners.size() == groups_of_vertex.size()) return triangles;
    std::sort(corners.begin(), corners.end());
    first = corners;
  }
  throw DegenerateHull{};
}

}  // namespace

Hull convex_hull_with_tolerance(const std::vector<Vec3d>& points, double rel_tol) {
  if (points.size() < 4)
    throw std::runtime_error("convex_hull: got " + std::to_string(points.size()) +
                             " points; a hull needs at least 4 non-coplanar points");
  for (const Vec3d& p : points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw std::runtime_error("convex_hull: a point has a non-finite coordinate");
  if (!(rel_tol > 0)) throw std::invalid_argument("convex_hull: rel_tol must be positive");
  double eps = hull_tolerance(points, rel_tol);
  const double largest = std::max(eps, hull_tolerance(points, kLargestRaisedRelTol)) * 1.000001;
  // Points clustered a few tolerances apart make planes that round-off cannot resolve at this
  // tolerance; features that small are then merged by retrying at ten times the tolerance.
  for (int attempt = 0; attempt <= kToleranceRaises && eps <= largest; ++attempt, eps *= 10) {
    try {
      return {hull_at_tolerance(points, eps), eps};
    } catch (const DegenerateHull&) {
    }
  }
  throw std::runtime_error("convex_hull: round-off left the hull inconsistent even at " +
                           std::to_string(eps / 10) + " m tolerance");
}

std::vector<std::array<int, 3>> convex_hull(const std::vector<Vec3d>& points, double rel_tol) {
  return convex_hull_with_tolerance(points, rel_tol).triangles;
}

std::vector<std::vector<int>> coplanar_groups(const std::vector<Vec3d>& points,
                                              const std::vector<std::array<int, 3>>& triangles,
                                              double abs_tol) {
  const int n = int(triangles.size());
  std::vector<Vec3d> normals(n);
  std::vector<double> areas(n);
  std::unordered_map<std::uint64_t, int> edge_triangle;
  for (int t = 0; t < n; ++t) {
    const auto& v = triangles[t];
    const Vec3d c = cross(points[v[1]] - points[v[0]], points[v[2]] - points[v[0]]);
    areas[t] = norm(c);
    normals[t] = areas[t] > 0 ? c / areas[t] : Vec3d{};
    for (int k = 0; k < 3; ++k) edge_triangle[edge_key(v[k], v[(k + 1) % 3])] = t;
  }
  // Largest triangles first: their planes are the best determined.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return areas[a] > areas[b]; });
  std::vector<int> group_of(n, -1);
  std::vector<std::vector<int>> groups;
  for (int seed : order) {
    if (group_of[seed] >= 0) continue;
    const int id = int(groups.size());
    const Vec3d normal = normals[seed];
    const auto& sv = triangles[seed];
    const double offset = dot(normal, (points[sv[0]] + points[sv[1]] + points[sv[2]]) / 3.0);
    std::vector<int> group{seed};
    group_of[seed] = id;
    for (std::size_t q = 0; q < group.size(); ++q) {
      const auto& v = triangles[group[q]];
      for (int k = 0; k < 3; ++k) {
        const auto it = edge_triangle.find(edge_key(v[(k + 1) % 3], v[k]));
        if (it == edge_triangle.end() || group_of[it->second] >= 0) continue;
        const int u = it->second;
        bool in_plane = dot(normals[u], normal) > 0;
        for (int w : triangles[u])
          in_plane = in_plane && std::abs(dot(normal, points[w]) - offset) <= abs_tol;
        if (!in_plane) continue;
        group_of[u] = id;
        group.push_back(u);
      }
    }
    groups.push_back(std::move(group));
  }
  return groups;
}

std::vector<int> group_boundary_loop(const std::vector<std::array<int, 3>>& triangles,
                                     const std::vector<int>& group) {
  std::unordered_map<std::uint64_t, bool> inside;
  for (int t : group)
    for (int k = 0; k < 3; ++k) inside[edge_key(triangles[t][k], triangles[t][(k + 1) % 3])] = true;
  std::unordered_map<int, int> next;
  std::size_t n_boundary = 0;
  for (int t : group)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      if (inside.count(edge_key(b, a))) continue;
      ++n_boundary;
      if (!next.emplace(a, b).second)
        throw std::runtime_error("group_boundary_loop: facet boundary is pinched at a vertex");
    }
  if (n_boundary < 3) throw std::runtime_error("group_boundary_loop: facet has no boundary");
  std::vector<int> loop{next.begin()->first};
  for (;;) {
    const auto it = next.find(loop.back());
    if (it == next.end()) throw std::runtime_error("group_boundary_loop: facet boundary is open");
    if (it->second == loop[0]) break;
    loop.push_back(it->second);
    if (loop.size() > n_boundary) break;
  }
  if (loop.size() != n_boundary)
    throw std::runtime_error("group_boundary_loop: facet boundary is not a single loop");
  // Start at the smallest index so the loop does not depend on hash order.
  std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
  return loop;
}

}  // namespace talus
