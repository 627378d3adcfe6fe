#include "solver/scene/initial_state_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

#include "solver/core/host_parallel.hpp"
#include "solver/neighbor/contact_pairs.hpp"
#include "solver/scene/placement.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus {
namespace {

// A warning lists this many ids, then says how many more.
constexpr std::size_t kListedIds = 5;

// What the checks need of a template: its inscribed and bounding radii about the centroid, and
// for a polyhedron its faces and vertices (body frame).
struct Body {
  bool sphere = false;
  double inscribed = 0, bounding = 0;
  const ShapeTemplate* shape = nullptr;
};

std::vector<Body> template_bodies(const Scene& scene) {
  std::vector<Body> bodies;
  for (const ParticleTemplate& t : scene.templates) {
    Body b;
    b.sphere = t.kind == ParticleShapeKind::sphere;
    b.bounding = t.bounding_radius;
    b.shape = &t.shape;
    b.inscribed = b.sphere ? t.sphere_radius : t.bounding_radius;
    if (!b.sphere)
      for (const Face& f : t.shape.faces) b.inscribed = std::min(b.inscribed, f.offset);
    bodies.push_back(b);
  }
  return bodies;
}

// Depths below this fraction of a particle's bounding radius count as touching: positions carry
// round-off (a lattice point is min + spacing (i + 1/2), so neighbours at a spacing of one
// diameter come out up to ~1e-16 relative closer), and the loader lets a lattice's spacing be
// 1e-9 below the bounding diameter (scene_particles.cpp).
constexpr double kTouching = 1e-8;

// Whether world point x lies inside particle p (of body b), deeper than kTouching.
bool contains(const Body& b, const ParticleState& p, const Vec3d& x) {
  const Vec3d local = rotate_inverse(p.orientation, x - p.position);
  const double margin = kTouching * b.bounding;
  if (b.sphere) return norm(local) < b.bounding - margin;
  for (const Face& f : b.shape->faces)
    if (!(dot(f.normal, local) < f.offset - margin)) return false;
  return true;
}

// Whether a vertex of polyhedron p lies strictly inside q (spheres have no vertices).
bool vertex_inside(const Body& bp, const ParticleState& p, const Body& bq, const ParticleState& q) {
  if (bp.sphere) return false;
  for (const Vec3d& v : bp.shape->vertices)
    if (contains(bq, q, p.position + rotate(p.orientation, v))) return true;
  return false;
}

std::string metres(double value) {
  return fmt::format("{:.3g} m", value);
}

// Findings of one kind for one scene entry (and the other entry or wall involved), reported as
// one warning line: "<count> <what>", in the singular for one.
struct Group {
  SourceRef entry;
  std::string one, many;  // "particle crosses ...", "particles cross ..."
  long long count = 0;
  std::vector<std::string> ids;
};

class Groups {
 public:
  explicit Groups(std::string ids_label) : ids_label_(std::move(ids_label)) {}
  void add(const SourceRef& entry, const std::string& one, const std::string& many,
           const std::string& id) {
    const std::string key = entry.where() + "\n" + many;
    auto [it, fresh] = index_.emplace(key, groups_.size());
    if (fresh) groups_.push_back({entry, one, many, 0, {}});
    Group& g = groups_[it->second];
    ++g.count;
    if (g.ids.size() < kListedIds) g.ids.push_back(id);
  }
  void append_lines(std::vector<std::string>& lines) const {
    for (const Group& g : groups_) {
      std::string ids;
      for (const std::string& id : g.ids) ids += (ids.empty() ? "" : ", ") + id;
      const long long listed = static_cast<long long>(g.ids.size());
      if (g.count > listed) ids += fmt::format(" and {} more", g.count - listed);
      lines.push_back(fmt::format("{}: warning: {} {} ({}: {})", g.entry.where(), g.count,
                                  g.count == 1 ? g.one : g.many, ids_label_, ids));
    }
  }

 private:
  std::string ids_label_;
  std::vector<Group> groups_;
  std::map<std::string, std::size_t> index_;
};

std::string other_entry(const SourceRef& entry, const SourceRef& other) {
  return entry.where() == other.where() ? "within this entry"
                                        : "with particles of " + other.where();
}

// Pairs of particles: the candidate pairs of their bounding spheres, then an error for a
// centroid inside the other particle, a warning for a certain overlap.
void check_pairs(const Scene& scene, const std::vector<Body>& bodies,
                 const std::vector<ParticleState>& particles, std::vector<std::string>& warnings) {
  const std::size_t n = particles.size();
  std::vector<double> x(n), y(n), z(n), radius(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = particles[i].position.x, y[i] = particles[i].position.y;
    z[i] = particles[i].position.z;
    radius[i] = bodies[particles[i].template_index].bounding;
  }
  NeighborInput<double> in;
  in.x = x.data(), in.y = y.data(), in.z = z.data(), in.radius = radius.data();
  in.count = static_cast<int>(n);  // at most kMaxParticles (scene_limits.hpp)
  // On all cores: for 1e6 particles the pass costs about what a step's broad phase does (a few
  // seconds on one core); the list is the same for any thread count.
  const std::vector<ContactPair> pairs =
      build_candidate_pairs(in, nullptr, 0.0, host_thread_count());
  long long deep = 0;
  ContactPair first_deep{-1, -1};
  Groups overlaps("id pairs");
  for (const ContactPair& pair : pairs) {
    const ParticleState &a = particles[pair.a], &b = particles[pair.b];
    const Body &ba = bodies[a.template_index], &bb = bodies[b.template_index];
    const double d = norm(a.position - b.position);
    const double touching = kTouching * std::max(ba.bounding, bb.bounding);
    if (!(d < ba.bounding + bb.bounding - touching)) continue;  // touching at most
    // The error's threshold: a centroid inside the other body. The overlap is then of the order
    // of the smaller particle's volume (for equal spheres, more than a radius deep), where the
    // laws' force direction -- from the overlap's geometry -- no longer parts the pair reliably
    // and identical poses get none; the laws and the time-step advisor are made for overlaps of
    // a few percent of a particle. Shallower overlaps are resolved by the law: a warning.
    if (contains(bb, b, a.position) || contains(ba, a, b.position)) {
      if (deep++ == 0) first_deep = pair;
      continue;
    }
    // Certain overlaps: the inscribed spheres meet, or a vertex of one is inside the other. (An
    // edge through an edge with no vertex inside is not seen: a shallow overlap either way.)
    if (d < ba.inscribed + bb.inscribed - touching || vertex_inside(ba, a, bb, b) ||
        vertex_inside(bb, b, ba, a)) {
      const std::string rest = " at the start " + other_entry(a.source, b.source) +
                               "; the contact law pushes them apart at the first step, turning "
                               "the overlap's elastic energy into speed";
      overlaps.add(a.source, "pair of particles overlaps" + rest,
                   "pairs of particles overlap" + rest, fmt::format("{}-{}", pair.a, pair.b));
    }
  }
  if (deep > 0) {
    const ParticleState &a = particles[first_deep.a], &b = particles[first_deep.b];
    const Body &ba = bodies[a.template_index], &bb = bodies[b.template_index];
    const double d = norm(a.position - b.position);
    const SourceRef& at = a.source;
    throw SceneError(
        at.file.empty() ? scene.file : at.file, at.line, at.column, at.key,
        fmt::format("particles {} and {} ({}) start with the centroid of one inside the other: "
                    "centres {} apart{}, inscribed radii {} and {}; the contact law cannot "
                    "separate such a pair (identical poses feel no force at all, slightly "
                    "shifted ones are thrown apart at hundreds of m/s); move them apart ({} "
                    "such pair{} in all)",
                    first_deep.a, first_deep.b,
                    b.source.where() == at.where() ? "both of this entry"
                                                   : "the second of " + b.source.where(),
                    metres(d), d == 0 ? " (identical positions)" : "", metres(ba.inscribed),
                    metres(bb.inscribed), deep, deep == 1 ? "" : "s"));
  }
  overlaps.append_lines(warnings);
}

// Whether the segment from the centroid c (signed distance sc to the triangle's plane) to the
// vertex v (sv, of the other sign) crosses the plane inside triangle (a, b, t).
bool segment_crosses(const Vec3d& c, double sc, const Vec3d& v, double sv, const Vec3d& a,
                     const Vec3d& b, const Vec3d& t, double size) {
  const Vec3d x = c + (v - c) * (sc / (sc - sv));
  const double tolerance = 1e-12 * size;
  return point_triangle_distance2(x, a, b, t) <= tolerance * tolerance;
}

// Whether particle p (body bp) crosses triangle (a, b, c), whose unit normal n points to the
// particles' side; `signed_centre`: the centroid's signed distance to its plane.
bool crosses(const Body& bp, const ParticleState& p, const Vec3d& a, const Vec3d& b, const Vec3d& c,
             const Vec3d& n, double signed_centre, double distance) {
  const double margin = kTouching * bp.bounding;      // resting on the wall is not crossing it
  if (distance < bp.inscribed - margin) return true;  // spheres: inscribed = bounding
  if (bp.sphere) return false;
  for (const Vec3d& local : bp.shape->vertices) {
    const Vec3d v = p.position + rotate(p.orientation, local);
    const double sv = dot(n, v - a);
    const bool other_side = signed_centre < 0 ? sv > margin : sv < -margin;
    if (other_side && segment_crosses(p.position, signed_centre, v, sv, a, b, c, bp.bounding))
      return true;
  }
  return false;
}

// Where a centroid lies with respect to the space a wall holds its particles in.
enum class Side : unsigned char {
  inside,   // where the particles belong
  outside,  // behind the wall: it can reach the particles' side only around the wall
  unknown,  // beyond an open end or an edge, or not decided (docs/scenes.md)
};

// A closed container (no opening): a box without open_top, a drum, a capped cylinder.
bool closed_container(const WallSpec& wall) {
  if (const auto* box = std::get_if<BoxWall>(&wall.shape)) return !box->open_top;
  if (const auto* cylinder = std::get_if<CylinderWall>(&wall.shape))
    return cylinder->bottom_cap && cylinder->top_cap;
  return wall.kind == WallKind::drum;
}

// An axial wall in its own coordinates: `along` the axis from `base` and `radial` from it. The
// side spans along in [0, height] with radius side_radius(along); a flat bottom at along = 0
// covers radial in [bottom_inner, bottom_outer] (none when empty); a top cap of `top_radius` at
// along = height, when there is one. Circles: the polygons' corners (the faces lie up to
// r (1 - cos(pi / segments)) inside, counted as inside).
struct Axial {
  Vec3d base, axis;
  double height = 0;
  double bottom_inner = 0, bottom_outer = -1;
  double top_radius = -1;  // negative: open top
};

template <class SideRadius>
Side axial_side(const Axial& wall, const Vec3d& x, SideRadius side_radius) {
  const double along = dot(x - wall.base, wall.axis);
  const double radial = norm(x - wall.base - wall.axis * along);
  if (along >= 0 && along <= wall.height)  // beside the side wall: it can never get in there
    return radial <= side_radius(along) ? Side::inside : Side::outside;
  if (along < 0)  // beneath the bottom's plate, cap or annulus
    return radial >= wall.bottom_inner && radial <= wall.bottom_outer ? Side::outside
                                                                      : Side::unknown;
  return radial <= wall.top_radius ? Side::outside : Side::unknown;  // above a top cap
}

// Where x lies with respect to generated wall `wall` (not a mesh), at t = 0.
Side generated_side(const WallSpec& wall, const Vec3d& x) {
  if (const auto* plane = std::get_if<PlaneWall>(&wall.shape)) {
    Vec3d u, v;
    axis_basis(plane->normal, u, v);
    const Vec3d r = x - plane->point;
    const double h = plane->size / 2;
    if (std::fabs(dot(r, u)) > h || std::fabs(dot(r, v)) > h) return Side::unknown;  // beside
    return dot(r, plane->normal) < 0 ? Side::outside : Side::inside;
  }
  if (const auto* box = std::get_if<BoxWall>(&wall.shape)) {
    bool in[3];
    for (int k = 0; k < 3; ++k) in[k] = x[k] >= box->min[k] && x[k] <= box->max[k];
    if (in[0] && in[1] && in[2]) return Side::inside;
    if (!box->open_top) return Side::outside;
    // Open top: beside the side walls, or beneath the floor; above the rim it may fall in.
    if (x.z > box->max.z) return Side::unknown;
    return in[2] || (in[0] && in[1]) ? Side::outside : Side::unknown;
  }
  if (const auto* cylinder = std::get_if<CylinderWall>(&wall.shape)) {
    Axial a{cylinder->base, cylinder->axis, cylinder->height};
    if (cylinder->bottom_cap) a.bottom_outer = cylinder->radius;
    if (cylinder->top_cap) a.top_radius = cylinder->radius;
    const Side side = axial_side(a, x, [&](double) { return cylinder->radius; });
    return closed_container(wall) && side == Side::unknown ? Side::outside : side;
  }
  if (const auto* drum = std::get_if<DrumWall>(&wall.shape)) {
    Axial a{drum->center - drum->axis * (drum->length / 2), drum->axis, drum->length};
    a.bottom_outer = a.top_radius = drum->radius;
    const Side side = axial_side(a, x, [&](double) { return drum->radius; });
    return side == Side::unknown ? Side::outside : side;  // closed: outside everywhere else
  }
  if (const auto* hopper = std::get_if<HopperWall>(&wall.shape)) {
    Axial a{hopper->base, hopper->axis, hopper->height};
    if (outlet_closed_at(wall, 0.0)) a.bottom_outer = hopper->bottom_radius;  // the plate
    return axial_side(a, x, [&](double along) {
      return hopper->bottom_radius +
             (hopper->top_radius - hopper->bottom_radius) * (along / hopper->height);
    });
  }
  if (const auto* silo = std::get_if<SiloWall>(&wall.shape)) {
    Axial a{silo->base, silo->axis, silo->cone_height + silo->height};
    const bool plate = outlet_closed_at(wall, 0.0);
    if (silo->cone_height == 0) {  // the flat annulus, and the plate inside it
      a.bottom_inner = plate ? 0 : silo->outlet_radius;
      a.bottom_outer = silo->radius;
    } else if (plate) {
      a.bottom_outer = silo->outlet_radius;
    }
    return axial_side(a, x, [&](double along) {
      return along >= silo->cone_height
                 ? silo->radius
                 : silo->outlet_radius +
                       (silo->radius - silo->outlet_radius) * (along / silo->cone_height);
    });
  }
  return Side::unknown;
}

// The triangles of one mesh wall in a bounding-volume tree: the nearest triangle to a point in
// O(log T). Leaves hold up to 4 triangles; nodes split at the median of the triangles' centroids
// along the longest axis of their box.
class NearestTriangle {
 public:
  explicit NearestTriangle(const TriangleMesh& mesh) : mesh_(mesh) {
    order_.resize(mesh.triangles.size());
    centroid_.resize(mesh.triangles.size());
    for (std::size_t t = 0; t < order_.size(); ++t) {
      order_[t] = static_cast<int>(t);
      centroid_[t] = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
    }
    if (!order_.empty()) build(0, static_cast<int>(order_.size()));
  }

  // The triangle nearest to x (-1 for an empty mesh). `hint`: a triangle likely near it (the
  // previous particle's), whose distance starts the search's bound; -1 for none. Among equally
  // near triangles the first found wins, so the answer depends on the hint only there.
  int nearest(const Vec3d& x, int hint) const {
    if (nodes_.empty()) return -1;
    int best = hint;
    double best2 = hint < 0 ? INFINITY : distance2(x, hint);
    // Nodes still to search with their boxes' distances, the nearest on top. A median split
    // keeps the depth below 32, so the stack below 64 entries.
    std::array<std::pair<int, double>, 64> stack;
    int top = 0;
    stack[top++] = {0, box_distance2(nodes_[0], x)};
    while (top > 0) {
      const auto [index, box2] = stack[--top];
      if (!(box2 < best2)) continue;
      const Node& node = nodes_[index];
      if (node.right < 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          const double d2 = distance2(x, order_[i]);
          if (d2 < best2) best2 = d2, best = order_[i];
        }
        continue;
      }
      // The nearer child on top; a child no nearer than the best so far is left out.
      std::pair<int, double> near{node.left, box_distance2(nodes_[node.left], x)};
      std::pair<int, double> far{node.right, box_distance2(nodes_[node.right], x)};
      if (far.second < near.second) std::swap(near, far);
      if (far.second < best2) stack[top++] = far;
      if (near.second < best2) stack[top++] = near;
    }
    return best;
  }

  Vec3d corner(std::size_t t, int k) const { return mesh_.vertices[mesh_.triangles[t][k]]; }
  double distance2(const Vec3d& x, std::size_t t) const {
    return point_triangle_distance2(x, corner(t, 0), corner(t, 1), corner(t, 2));
  }

 private:
  struct Node {
    Vec3d low, high;
    int first = 0, count = 0;
    int left = -1, right = -1;  // right < 0: a leaf
  };

  int build(int first, int count) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    Vec3d low = corner(order_[first], 0), high = low, clow = centroid_[order_[first]], chigh = clow;
    for (int i = first; i < first + count; ++i)
      for (int k = 0; k < 3; ++k) {
        const Vec3d c = corner(order_[i], k), m = centroid_[order_[i]];
        for (int a = 0; a < 3; ++a) {
          low[a] = std::min(low[a], c[a]), high[a] = std::max(high[a], c[a]);
          clow[a] = std::min(clow[a], m[a]), chigh[a] = std::max(chigh[a], m[a]);
        }
      }
    nodes_[index].low = low, nodes_[index].high = high;
    nodes_[index].first = first, nodes_[index].count = count;
    if (count <= 4) return index;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (chigh[a] - clow[a] > chigh[axis] - clow[axis]) axis = a;
    const int half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half,
                     order_.begin() + first + count,
                     [&](int a, int b) { return centroid_[a][axis] < centroid_[b][axis]; });
    const int left = build(first, half);
    const int right = build(first + half, count - half);
    nodes_[index].left = left, nodes_[index].right = right;
    return index;
  }

  static double box_distance2(const Node& node, const Vec3d& x) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = std::max({node.low[a] - x[a], 0.0, x[a] - node.high[a]});
      d2 += d * d;
    }
    return d2;
  }

  const TriangleMesh& mesh_;
  std::vector<int> order_;
  std::vector<Vec3d> centroid_;
  std::vector<Node> nodes_;
};

// Where x lies with respect to a mesh wall: decided only when x projects onto the inside of its
// nearest triangle (not onto an edge or a corner), by the side of that triangle it is on. A
// closed mesh whose normals face in then gives inside or outside for every such point, an open
// one (a funnel, a sheet) says outside only behind the triangles that x faces.
Side mesh_side(const NearestTriangle& tree, const Vec3d& x, int& hint) {
  const int t = tree.nearest(x, hint);
  hint = t;
  if (t < 0) return Side::unknown;
  const Vec3d a = tree.corner(t, 0), b = tree.corner(t, 1), c = tree.corner(t, 2);
  const Vec3d normal = cross(b - a, c - a);
  const double area2 = dot(normal, normal);
  if (!(area2 > 0)) return Side::unknown;
  // Barycentric coordinates of x's projection: each of the three sub-triangles' signed areas.
  const double margin = 1e-9;
  const double wa = dot(cross(b - x, c - x), normal) / area2;
  const double wb = dot(cross(c - x, a - x), normal) / area2;
  if (!(wa > margin && wb > margin && 1 - wa - wb > margin)) return Side::unknown;
  return dot(normal, x - a) < 0 ? Side::outside : Side::inside;
}

void check_walls(const Scene& scene, const std::vector<Body>& bodies,
                 const std::vector<ParticleState>& particles, std::vector<std::string>& warnings) {
  if (scene.walls.empty() || particles.empty()) return;
  const std::vector<TriangleMesh> walls = walls_at(scene, make_wall_meshes(scene), 0.0);
  Vec3d low = particles[0].position, high = low;
  double reach = 0;
  for (const ParticleState& p : particles) {
    for (int k = 0; k < 3; ++k)
      low[k] = std::min(low[k], p.position[k]), high[k] = std::max(high[k], p.position[k]);
    reach = std::max(reach, bodies[p.template_index].bounding);
  }
  // The random fill each particle comes from, -1 for none (initial_particles.hpp: the fills'
  // particles come last, each fill's together).
  std::vector<int> fill_of(particles.size(), -1);
  for (std::size_t i = 0, f = 0; i < particles.size(); ++i) {
    const SourceRef& s = particles[i].source;
    const auto is_fill = [&](std::size_t k) {
      const SourceRef& r = scene.random_fills[k].source;
      return s.line == r.line && s.column == r.column && s.file == r.file && s.key == r.key;
    };
    while (f < scene.random_fills.size() && !is_fill(f)) ++f;
    if (f == scene.random_fills.size())
      f = 0;  // not from a fill: search from the first again
    else
      fill_of[i] = static_cast<int>(f);
  }
  Groups straddling("ids"), outside("ids");
  long long behind = 0;
  std::size_t first_behind = 0, first_behind_wall = 0;
  double first_behind_distance = 0;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const WallSpec& spec = scene.walls[w];
    const std::string wall = fmt::format("'{}' ({})", spec.name, spec.source.where());
    // Triangles within the largest bounding radius of any centroid, found in constant time.
    PlacementGrid grid(low, high, reach, 0);
    grid.add_mesh(walls[w]);
    std::optional<NearestTriangle> tree;
    if (spec.kind == WallKind::mesh) tree.emplace(walls[w]);
    // A mesh wall's sides first, on all cores: fixed blocks of particles, each searched in order
    // from its previous particle's nearest triangle (lattice and fill neighbours lie near each
    // other), so the sides do not depend on the thread count.
    std::vector<Side> mesh_sides;
    if (tree) {
      mesh_sides.resize(particles.size());
      constexpr long long kBlock = 1024;
      const long long blocks = (static_cast<long long>(particles.size()) + kBlock - 1) / kBlock;
      parallel_for_dynamic(host_thread_count(), blocks, 1, [&](long long block) {
        int hint = -1;
        const std::size_t end =
            std::min(particles.size(), std::size_t(block + 1) * std::size_t(kBlock));
        for (std::size_t i = std::size_t(block * kBlock); i < end; ++i)
          mesh_sides[i] = mesh_side(*tree, particles[i].position, hint);
      });
    }
    std::vector<long long> fill_inside(scene.random_fills.size());
    std::vector<std::vector<std::size_t>> fill_outside(scene.random_fills.size());
    const auto add_outside = [&](const SourceRef& entry, const std::string& id) {
      if (closed_container(spec))
        outside.add(
            entry,
            "particle lies outside the closed container " + wall + ", which it can never enter",
            "particles lie outside the closed container " + wall + ", which they can never enter",
            id);
      else
        outside.add(entry,
                    "particle lies behind wall " + wall +
                        ", on the side away from the particles; it can reach their side only "
                        "around the wall's edge, never through it",
                    "particles lie behind wall " + wall +
                        ", on the side away from the particles; they can reach their side only "
                        "around the wall's edge, never through it",
                    id);
    };
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const ParticleState& p = particles[i];
      const Body& body = bodies[p.template_index];
      bool front = false, back = false;
      double back_distance = 0;
      grid.for_each_triangle_near(p.position, [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
        const double distance = std::sqrt(point_triangle_distance2(p.position, a, b, c));
        if (!(distance < body.bounding)) return;
        const Vec3d normal = cross(b - a, c - a);
        if (!(norm(normal) > 0)) return;  // a degenerate triangle holds nothing
        const Vec3d n = normal / norm(normal);
        const double side = dot(n, p.position - a);
        if (!crosses(body, p, a, b, c, n, side, distance)) return;
        if (side < 0) {
          if (!back || distance < back_distance) back_distance = distance;
          back = true;
        } else {
          front = true;
        }
      });
      const std::string id = std::to_string(i);
      if (back) {
        if (behind++ == 0)
          first_behind = i, first_behind_wall = w, first_behind_distance = back_distance;
      } else if (front) {
        straddling.add(p.source,
                       "particle crosses wall " + wall +
                           " at the start, its centroid on the particles' side; the wall pushes "
                           "it out at the first step",
                       "particles cross wall " + wall +
                           " at the start, their centroids on the particles' side; the wall "
                           "pushes them out at the first step",
                       id);
      } else {
        const Side side = tree ? mesh_sides[i] : generated_side(spec, p.position);
        const int fill = fill_of[i];
        if (fill >= 0 && side != Side::unknown) {
          if (side == Side::inside)
            ++fill_inside[fill];
          else
            fill_outside[fill].push_back(i);
        } else if (side == Side::outside) {
          add_outside(p.source, id);
        }
      }
    }
    // A random fill with particles on both sides of the wall: its region reaches beyond it.
    for (std::size_t f = 0; f < fill_outside.size(); ++f) {
      const SourceRef& entry = scene.random_fills[f].source;
      for (const std::size_t i : fill_outside[f]) {
        if (fill_inside[f] == 0) {
          add_outside(entry, std::to_string(i));
          continue;
        }
        outside.add(entry,
                    "particle of this random fill lies outside wall " + wall +
                        ", which holds the fill's other particles: the fill's region reaches "
                        "beyond the wall; keep it on the particles' side",
                    "particles of this random fill lie outside wall " + wall +
                        ", which holds the fill's other particles: the fill's region reaches "
                        "beyond the wall; keep it on the particles' side",
                    std::to_string(i));
      }
    }
  }
  if (behind > 0) {
    const ParticleState& p = particles[first_behind];
    const WallSpec& spec = scene.walls[first_behind_wall];
    throw SceneError(
        p.source.file.empty() ? scene.file : p.source.file, p.source.line, p.source.column,
        p.source.key,
        fmt::format("particle {} crosses wall '{}' ({}) with its centroid {} behind it, on the "
                    "side away from the particles: the wall's contact pushes it along the "
                    "wall's normal, through the wall; place it on the particles' side ({} such "
                    "particle{} in all)",
                    first_behind, spec.name, spec.source.where(), metres(first_behind_distance),
                    behind, behind == 1 ? "" : "s"));
  }
  straddling.append_lines(warnings);
  outside.append_lines(warnings);
}

}  // namespace

std::vector<std::string> check_initial_state(const Scene& scene,
                                             const std::vector<ParticleState>& particles) {
  std::vector<std::string> warnings;
  const std::vector<Body> bodies = template_bodies(scene);
  check_pairs(scene, bodies, particles, warnings);
  check_walls(scene, bodies, particles, warnings);
  return warnings;
}

}  // namespace talus
