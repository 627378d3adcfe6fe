#include "solver/scene/initial_state_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

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

// A closed container (no opening): a box without open_top, a drum, a capped cylinder. True when
// x lies outside the solid it encloses (a drum's and cylinder's circle: its polygon's corners).
bool outside_closed_container(const WallSpec& wall, const Vec3d& x) {
  if (const auto* box = std::get_if<BoxWall>(&wall.shape)) {
    if (box->open_top) return false;
    for (int k = 0; k < 3; ++k)
      if (x[k] < box->min[k] || x[k] > box->max[k]) return true;
    return false;
  }
  const auto outside_cylinder = [&](const Vec3d& base, const Vec3d& axis, double radius,
                                    double height) {
    const double along = dot(x - base, axis);
    const double radial = norm(x - base - axis * along);
    return along < 0 || along > height || radial > radius;
  };
  if (const auto* drum = std::get_if<DrumWall>(&wall.shape))
    return outside_cylinder(drum->center - drum->axis * (drum->length / 2), drum->axis,
                            drum->radius, drum->length);
  if (const auto* cylinder = std::get_if<CylinderWall>(&wall.shape))
    return cylinder->bottom_cap && cylinder->top_cap &&
           outside_cylinder(cylinder->base, cylinder->axis, cylinder->radius, cylinder->height);
  return false;
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
      } else if (outside_closed_container(spec, p.position)) {
        outside.add(
            p.source,
            "particle lies outside the closed container " + wall + ", which it can never enter",
            "particles lie outside the closed container " + wall + ", which they can never enter",
            id);
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
