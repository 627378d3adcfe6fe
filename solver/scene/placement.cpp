#include "solver/scene/placement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "solver/scene/wall_meshes.hpp"

namespace talus {

double PlacementRandom::uniform() {
  return double(engine_() >> 11) * 0x1.0p-53;  // k / 2^53, k uniform in [0, 2^53)
}

double PlacementRandom::uniform(double low, double high) {
  return low + (high - low) * uniform();
}

Quatd PlacementRandom::orientation() {
  // A point uniform in the 4-ball, normalised, is uniform on the unit 3-sphere, and unit
  // quaternions uniform on the sphere are rotations uniform on SO(3) (Haar measure). Points near
  // the centre are rejected too: they would lose digits when normalised.
  for (;;) {
    const double w = uniform(-1, 1), x = uniform(-1, 1), y = uniform(-1, 1), z = uniform(-1, 1);
    const double s = w * w + x * x + y * y + z * z;
    if (s > 1 || s < 1e-4) continue;
    const double inverse = (w < 0 ? -1 : 1) / std::sqrt(s);  // q and -q are the same rotation
    return {w * inverse, x * inverse, y * inverse, z * inverse};
  }
}

CentreSampler::CentreSampler(const Region& region, double radius)
    : region_(region), radius_(radius) {
  if (region.kind == RegionKind::box) {
    low_ = region.box_min + Vec3d(radius, radius, radius);
    high_ = region.box_max - Vec3d(radius, radius, radius);
    return;
  }
  axis_basis(region.axis, u_, v_);
  const double r = region.radius - radius;
  const Vec3d bottom = region.base + region.axis * radius;
  const Vec3d top = region.base + region.axis * (region.height - radius);
  for (int k = 0; k < 3; ++k) {
    // A disc of radius r about a unit axis a spans r sqrt(1 - a_k^2) either side on axis k.
    const double half = r * std::sqrt(std::max(0.0, 1 - region.axis[k] * region.axis[k]));
    low_[k] = std::min(bottom[k], top[k]) - half;
    high_[k] = std::max(bottom[k], top[k]) + half;
  }
}

Vec3d CentreSampler::sample(PlacementRandom& random) const {
  if (region_.kind == RegionKind::box) {
    Vec3d p;
    for (int k = 0; k < 3; ++k) p[k] = random.uniform(low_[k], high_[k]);
    return p;
  }
  // Uniform in the disc by rejection from its square, then uniform along the axis.
  double x, y;
  do {
    x = random.uniform(-1, 1);
    y = random.uniform(-1, 1);
  } while (x * x + y * y > 1);
  const double r = region_.radius - radius_;
  const double along = random.uniform(radius_, region_.height - radius_);
  return region_.base + region_.axis * along + u_ * (r * x) + v_ * (r * y);
}

double point_triangle_distance2(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm2(ap);  // vertex a
  const Vec3d bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm2(bp);  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm2(ap - ab * (d1 / (d1 - d3)));  // edge ab
  const Vec3d cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm2(cp);  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm2(ap - ac * (d2 / (d2 - d6)));  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)  // edge bc
    return norm2(bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denominator = 1 / (va + vb + vc);  // inside the face
  return norm2(ap - ab * (vb * denominator) - ac * (vc * denominator));
}

void PlacementGrid::Cells::init(const Vec3d& low_corner, const Vec3d& high_corner, double min_size,
                                std::size_t max_cells) {
  low = low_corner;
  size = min_size;
  if (!(size > 0)) size = std::max(1e-12, norm(high_corner - low_corner));  // a zero radius
  for (;;) {
    double count = 1;
    for (int k = 0; k < 3; ++k)
      count *= std::max(1.0, std::ceil((high_corner[k] - low_corner[k]) / size));
    if (count <= double(max_cells)) break;
    size *= 1.25;
  }
  for (int k = 0; k < 3; ++k)
    n[k] = int(std::max(1.0, std::ceil((high_corner[k] - low_corner[k]) / size)));
  head.assign(std::size_t(n[0]) * n[1] * n[2], -1);
  node.clear();
}

int PlacementGrid::Cells::coordinate(double x, int axis) const {
  const double t = std::floor((x - low[axis]) / size);
  if (!(t >= 0)) return 0;  // also NaN
  return t >= n[axis] ? n[axis] - 1 : int(t);
}

int PlacementGrid::Cells::cell_of(const Vec3d& p) const {
  return (coordinate(p.z, 2) * n[1] + coordinate(p.y, 1)) * n[0] + coordinate(p.x, 0);
}

void PlacementGrid::Cells::add(int cell, int item) {
  node.emplace_back(head[cell], item);
  head[cell] = int(node.size()) - 1;
}

namespace {

// Cells are this much wider than the reach they are cut for, and a sphere is listed once only
// when its reach is this much narrower than a cell: far above the round-off of a cell index
// (1e-13 of a cell at a thousand cells from the corner), so two points closer than the reach
// always lie in the same or neighbouring cells.
constexpr double kCellMargin = 1 + 1e-9;

}  // namespace

PlacementGrid::PlacementGrid(const Vec3d& low, const Vec3d& high, double radius,
                             std::size_t expected)
    : radius_(radius) {
  // Widen the box by far more than the round-off of a sampled centre (a cylinder's box is
  // computed apart from its samples), so that no query falls outside it.
  const double slack = 1e-9 * (radius + norm(high - low));
  low_ = low - Vec3d(slack, slack, slack);
  high_ = high + Vec3d(slack, slack, slack);
  // Cells one reach (two radii) wide, at most four per expected sphere (a random fill's spheres
  // fill at most 0.38 of the box, 2.2 reach-wide cells a sphere at 0.25) and 2^27 in all.
  const std::size_t sphere_cells =
      std::min<std::size_t>(std::max<std::size_t>(4096, 4 * expected), std::size_t(1) << 27);
  sphere_cells_.init(low_, high_, 2 * radius * kCellMargin, sphere_cells);
  near_.reserve(std::min<std::size_t>(expected, std::size_t(1) << 27));
  init_triangle_cells(0);
}

void PlacementGrid::init_triangle_cells(std::size_t triangles) {
  // A triangle may span many cells, so these are coarser: four per triangle, at least 32^3 and
  // at most 2^22. Reach-wide cells list only the triangles near a wall; coarse ones would make
  // every query near a finely meshed floor read hundreds.
  const std::size_t cells =
      std::min<std::size_t>(std::max<std::size_t>(32768, 4 * triangles), std::size_t(1) << 22);
  triangle_cells_.init(low_, high_, 2 * radius_, cells);
}

void PlacementGrid::add_sphere(const Vec3d& centre, double radius) {
  // A new sphere can touch this one only with its centre within radius + radius_ of it.
  const double reach = radius + radius_;
  for (int k = 0; k < 3; ++k)
    if (centre[k] + reach < low_[k] || centre[k] - reach > high_[k]) return;
  const Cells& g = sphere_cells_;
  if (reach * kCellMargin <= g.size) {
    const int cell = g.cell_of(centre);
    near_.push_back({centre, reach * reach, g.head[cell]});
    sphere_cells_.head[cell] = int(near_.size()) - 1;
    return;
  }
  if (wide_cells_.head.empty()) {  // the same cells as sphere_cells_
    wide_cells_.low = g.low;
    wide_cells_.size = g.size;
    for (int k = 0; k < 3; ++k) wide_cells_.n[k] = g.n[k];
    wide_cells_.head.assign(g.head.size(), -1);
  }
  const int item = int(wide_centres_.size());
  wide_centres_.push_back(centre);
  wide_radii_.push_back(radius);
  int from[3], to[3];
  for (int k = 0; k < 3; ++k) {
    from[k] = g.coordinate(centre[k] - reach, k);
    to[k] = g.coordinate(centre[k] + reach, k);
  }
  for (int z = from[2]; z <= to[2]; ++z)
    for (int y = from[1]; y <= to[1]; ++y)
      for (int x = from[0]; x <= to[0]; ++x) wide_cells_.add((z * g.n[1] + y) * g.n[0] + x, item);
}

void PlacementGrid::add_triangle(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  Vec3d lo, hi;
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min({a[k], b[k], c[k]}) - radius_;
    hi[k] = std::max({a[k], b[k], c[k]}) + radius_;
    if (hi[k] < low_[k] || lo[k] > high_[k]) return;
  }
  const int item = int(triangle_vertices_.size() / 3);
  triangle_vertices_.insert(triangle_vertices_.end(), {a, b, c});
  const Cells& g = triangle_cells_;
  // A query point lies in its cell (or, clamped, within round-off of the grid's edge cell), so
  // within half a diagonal of the cell's centre; the slack covers the round-off of the centre.
  const double half_diagonal = g.size * std::sqrt(3.0) / 2;
  const double reach = (radius_ + half_diagonal) * (1 + 1e-9);
  int from[3], to[3];
  for (int k = 0; k < 3; ++k) {
    from[k] = g.coordinate(lo[k], k);
    to[k] = g.coordinate(hi[k], k);
  }
  for (int z = from[2]; z <= to[2]; ++z)
    for (int y = from[1]; y <= to[1]; ++y)
      for (int x = from[0]; x <= to[0]; ++x) {
        const Vec3d centre = g.low + Vec3d(x + 0.5, y + 0.5, z + 0.5) * g.size;
        if (point_triangle_distance2(centre, a, b, c) <= reach * reach)
          triangle_cells_.add((z * g.n[1] + y) * g.n[0] + x, item);
      }
}

void PlacementGrid::add_mesh(const TriangleMesh& mesh) {
  if (triangle_vertices_.empty()) init_triangle_cells(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    add_triangle(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
}

void PlacementGrid::take_triangles_of(const PlacementGrid& other) {
  bool same = other.radius_ == radius_;
  for (int k = 0; k < 3; ++k) same = same && other.low_[k] == low_[k] && other.high_[k] == high_[k];
  if (!same)
    throw std::invalid_argument(
        "PlacementGrid::take_triangles_of: a grid of another box or radius");
  triangle_cells_ = other.triangle_cells_;
  triangle_vertices_ = other.triangle_vertices_;
}

bool PlacementGrid::is_free(const Vec3d& centre) const {
  // The spheres listed once: the 27 cells about the centre's (every one within a reach of it).
  const Cells& g = sphere_cells_;
  int from[3], to[3];
  for (int k = 0; k < 3; ++k) {
    const int c = g.coordinate(centre[k], k);
    from[k] = c > 0 ? c - 1 : 0;
    to[k] = c + 1 < g.n[k] ? c + 1 : c;
  }
  for (int z = from[2]; z <= to[2]; ++z)
    for (int y = from[1]; y <= to[1]; ++y) {
      const int row = (z * g.n[1] + y) * g.n[0];
      for (int x = from[0]; x <= to[0]; ++x)
        for (int i = g.head[row + x]; i >= 0;) {
          const Near& s = near_[i];
          if (norm2(centre - s.centre) < s.reach2) return false;
          i = s.next;
        }
    }
  if (!wide_cells_.head.empty())
    for (int i = wide_cells_.head[wide_cells_.cell_of(centre)]; i >= 0;) {
      const auto [next, item] = wide_cells_.node[i];
      const double reach = radius_ + wide_radii_[item];
      if (norm2(centre - wide_centres_[item]) < reach * reach) return false;
      i = next;
    }
  bool free = true;
  for_each_triangle_near(centre, [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    free = free && !(point_triangle_distance2(centre, a, b, c) < radius_ * radius_);
  });
  return free;
}

bool place_one(const CentreSampler& sampler, PlacementGrid& grid, PlacementRandom& random,
               int attempts, int template_index, bool random_orientation, const Vec3d& velocity,
               const SourceRef& source, ParticleState& particle) {
  for (int attempt = 0; attempt < attempts; ++attempt) {
    const Vec3d centre = sampler.sample(random);
    if (!grid.is_free(centre)) continue;
    particle = ParticleState();
    particle.template_index = template_index;
    particle.position = centre;
    if (random_orientation) particle.orientation = random.orientation();
    particle.velocity = velocity;
    particle.source = source;
    grid.add_sphere(centre, grid.radius());
    return true;
  }
  return false;
}

}  // namespace talus
