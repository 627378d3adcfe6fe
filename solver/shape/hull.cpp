#include "solver/shape/hull.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <queue>
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
  int farthest = -1;         // the point of `outside` farthest above the plane
  double farthest_distance = 0;
  bool alive = true;
};

// Thrown when round-off at the current tolerance leaves the hull inconsistent (a face without a
// well-defined plane, a horizon that is not one loop, an edge folding inward); the caller retries
// with a larger tolerance.
struct DegenerateHull {};

// Incremental Quickhull: each step takes the point farthest above some face, removes the faces
// it sees (a connected region grown from that face), and fans new faces from the point to the
// region's boundary (the horizon). A point within `eps` of the current hull is never added,
// which keeps duplicates and near-coplanar points out.
class IncrementalHull {
 public:
  IncrementalHull(const std::vector<Vec3d>& points, double eps) : points_(points), eps_(eps) {}

  // The hull of the points `subset` (which must span a volume). Each point is tested only against
  // the faces that replace the ones whose conflict list held it, so the expected cost is
  // O(n log n) for n points.
  std::vector<std::array<int, 3>> run(const std::vector<int>& subset) {
    build_simplex(subset);
    // Faces with a conflict list, farthest point first. Taking the farthest point of the whole
    // cloud (not of the face last made) refines all parts of the surface evenly: on a cylinder,
    // refining one rim far ahead of the other leaves fans of O(n) slivers that every later point
    // on the other rim sees, which made the hull O(n^2).
    Pending pending;
    for (int f = 0; f < int(faces_.size()); ++f) push(pending, f);
    while (!pending.empty()) {
      const int f = pending.top().second;
      pending.pop();
      if (faces_[f].alive) add_point(f, pending);
    }
    check_locally_convex();
    std::vector<std::array<int, 3>> triangles;
    for (const HullFace& face : faces_)
      if (face.alive) triangles.push_back(face.v);
    return triangles;
  }

 private:
  double distance(const HullFace& face, int p) const {
    return dot(face.normal, points_[p]) - face.offset;
  }

  // A closed surface whose every edge bends outward is convex, so checking each edge against its
  // two faces (O(n)) finds any fold that round-off left, without testing every point against
  // every face (O(n^2)).
  void check_locally_convex() const {
    for (const HullFace& face : faces_) {
      if (!face.alive) continue;
      for (int k = 0; k < 3; ++k) {
        const HullFace& other = faces_[neighbour(face.v[k], face.v[(k + 1) % 3])];
        for (int w : other.v)
          if (distance(face, w) > eps_) throw DegenerateHull{};
      }
    }
  }

  using Pending = std::priority_queue<std::pair<double, int>>;  // (farthest distance, face)

  void push(Pending& pending, int f) const {
    if (!faces_[f].outside.empty()) pending.push({faces_[f].farthest_distance, f});
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
      throw std::runtime_error("the " + count +
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
      throw std::runtime_error("the " + count +
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
      throw std::runtime_error("the " + count +
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
        HullFace& face = faces_[f];
        face.outside.push_back(p);
        const double d = distance(face, p);
        if (face.farthest < 0 || d > face.farthest_distance)
          face.farthest = p, face.farthest_distance = d;
        return;
      }
    }
  }

  // Faces seen from p (distance above `threshold`), grown from `seed`, then made to leave a
  // convex cone (see close_horizon). True when the horizon is one simple loop, as it is for a
  // point outside a convex polyhedron.
  bool find_visible(int seed, int p, double threshold, std::vector<int>& visible,
                    std::vector<std::array<int, 2>>& horizon) {
    visible.assign(1, seed);
    ++stamp_;
    mark_.resize(faces_.size(), 0);
    seen_.resize(faces_.size(), false);
    mark_[seed] = stamp_;
    seen_[seed] = true;
    for (std::size_t q = 0; q < visible.size(); ++q) {
      const HullFace& face = faces_[visible[q]];
      for (int k = 0; k < 3; ++k) {
        const int g = neighbour(face.v[k], face.v[(k + 1) % 3]);
        if (mark_[g] == stamp_) continue;
        mark_[g] = stamp_;
        seen_[g] = distance(faces_[g], p) > threshold;
        if (seen_[g]) visible.push_back(g);
      }
    }
    return close_horizon(p, visible, horizon);
  }

  bool is_visible(int g) const { return mark_[g] == stamp_ && seen_[g]; }

  // The horizon (directed edges of visible faces whose neighbour is not visible), after growing
  // the visible region over every kept face that would fold against its new neighbour. A point
  // just outside the hull and close to a horizon edge makes a new face (a, b, p) that is thin or
  // steep: a kept face g beyond (a, b), which p sees within the tolerance only, then has its far
  // vertex well above the new face, a fold far larger than the tolerance. Taking g into the
  // visible region moves the horizon past it; p lies within the tolerance of g's plane, so the
  // surface moves by no more than that.
  bool close_horizon(int p, std::vector<int>& visible, std::vector<std::array<int, 2>>& horizon) {
    for (;;) {  // each round adds a face, so this ends
      horizon.clear();
      for (int f : visible)
        for (int k = 0; k < 3; ++k) {
          const int a = faces_[f].v[k], b = faces_[f].v[(k + 1) % 3];
          if (!is_visible(neighbour(a, b))) horizon.push_back({a, b});
        }
      if (!is_simple_loop(horizon)) return false;
      int fold = -1;
      for (const auto& e : horizon)
        if (folds(e[0], e[1], p)) {
          fold = neighbour(e[0], e[1]);
          break;
        }
      if (fold < 0) return true;
      if (distance(faces_[fold], p) < -eps_) return false;  // p is well inside: not a fold to mend
      mark_[fold] = stamp_;
      seen_[fold] = true;
      visible.push_back(fold);
    }
  }

  // True when the new face (a, b, p) has no reliable plane, or the kept face beyond edge (a, b)
  // has its third vertex more than eps above that plane.
  bool folds(int a, int b, int p) const {
    const Vec3d& pa = points_[a];
    const Vec3d n = cross(points_[b] - pa, points_[p] - pa);
    const double longest =
        std::max({norm(points_[b] - pa), norm(points_[p] - pa), norm(points_[p] - points_[b])});
    if (!(norm(n) > 0.5 * eps_ * longest)) return true;
    const HullFace& kept = faces_[neighbour(a, b)];
    for (int w : kept.v)
      if (w != a && w != b && dot(n, points_[w] - pa) > eps_ * norm(n)) return true;
    return false;
  }

  static bool is_simple_loop(const std::vector<std::array<int, 2>>& horizon) {
    if (horizon.empty()) return false;
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

  void add_point(int f, Pending& pending) {
    const int p = faces_[f].farthest;
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
    for (const auto& e : horizon) add_face(e[0], e[1], p);
    for (int q : orphans) assign(q, first_new, int(faces_.size()));
    for (int g = first_new; g < int(faces_.size()); ++g) push(pending, g);
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

// One attempt at fixed absolute tolerances: the hull with visibility decided at `hull_eps` (near
// round-off, so that dense points on a curved surface give a consistent, convex triangulation),
// then its triangles grouped into facets at `merge_eps`. A vertex on fewer than 3 facets lies
// inside a facet or on an edge, within merge_eps of it: the hull is built again from the corners
// alone, until every vertex is a corner. Each rebuild can let more triangles merge (on a dense,
// nearly flat patch the corners left are again within the tolerance of a wider plane), so this
// stops after kCornerPasses rebuilds: a vertex still on two facets then lies on their common edge
// within the tolerance, and one on a single facet inside it (make_template keeps neither).
std::vector<std::array<int, 3>> hull_at_tolerance(const std::vector<Vec3d>& points, double hull_eps,
                                                  double merge_eps) {
  std::vector<int> subset(points.size());
  std::iota(subset.begin(), subset.end(), 0);
  std::vector<int> groups_of_vertex(points.size());
  std::vector<int> last_group(points.size());
  for (int pass = 0;; ++pass) {
    std::vector<std::array<int, 3>> triangles = IncrementalHull(points, hull_eps).run(subset);
    const std::vector<std::vector<int>> groups = coplanar_groups(points, triangles, merge_eps);
    // Distinct facets around each vertex; a group's triangles around one vertex are counted once.
    std::fill(groups_of_vertex.begin(), groups_of_vertex.end(), 0);
    std::fill(last_group.begin(), last_group.end(), -1);
    for (int g = 0; g < int(groups.size()); ++g)
      for (int t : groups[g])
        for (int v : triangles[t])
          if (last_group[v] != g) last_group[v] = g, ++groups_of_vertex[v];
    std::vector<int> corners;
    bool all_corners = true;
    for (int v = 0; v < int(points.size()); ++v) {
      if (groups_of_vertex[v] >= 3) corners.push_back(v);
      if (groups_of_vertex[v] > 0 && groups_of_vertex[v] < 3) all_corners = false;
    }
    if (all_corners || pass == kCornerPasses) return triangles;
    subset = corners;
    if (subset.size() < 4) throw DegenerateHull{};
  }
}

}  // namespace

Hull convex_hull_with_tolerance(const std::vector<Vec3d>& points, double rel_tol) {
  if (points.size() < 4)
    throw std::runtime_error("only " + std::to_string(points.size()) +
                             " points; a hull needs at least 4 non-coplanar points");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3d& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw std::runtime_error("point " + std::to_string(i + 1) + " has a non-finite coordinate");
  }
  if (!(rel_tol > 0)) throw std::invalid_argument("convex_hull: rel_tol must be positive");
  double merge_eps = hull_tolerance(points, rel_tol);
  double hull_eps = std::min(merge_eps, hull_tolerance(points, kHullRelTol));
  const double largest =
      std::max(merge_eps, hull_tolerance(points, kLargestRaisedRelTol)) * 1.000001;
  // Points clustered a few tolerances apart make planes that round-off cannot resolve at this
  // tolerance; features that small are then merged by retrying at ten times the tolerance.
  for (int attempt = 0; attempt <= kToleranceRaises && hull_eps <= largest; ++attempt) {
    try {
      return {hull_at_tolerance(points, hull_eps, merge_eps), merge_eps};
    } catch (const DegenerateHull&) {
    }
    hull_eps *= 10;
    merge_eps = std::max(merge_eps, hull_eps);
  }
  char text[64];
  std::snprintf(text, sizeof text, "%.3g m", hull_eps / 10);
  throw std::runtime_error("round-off left the hull of " + std::to_string(points.size()) +
                           " points inconsistent even at " + text + " tolerance");
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
