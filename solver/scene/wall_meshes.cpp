#include "solver/scene/wall_meshes.hpp"

#include <cmath>
#include <stdexcept>

#include "solver/scene/wall_motion.hpp"

namespace talus {
namespace {

// Builds a mesh: vertices, rings of a polygon about an axis, and faces wound so that their
// normal (b - a) x (c - a) points where the caller says (see the header's convention).
class MeshBuilder {
 public:
  MeshBuilder(const Vec3d& axis, int segments) : axis_(axis), segments_(segments) {
    axis_basis(axis, u_, v_);
    for (int k = 0; k < segments; ++k) {
      const double angle = 2 * M_PI * k / segments;
      cos_.push_back(std::cos(angle));
      sin_.push_back(std::sin(angle));
    }
  }

  int add_vertex(const Vec3d& p) {
    mesh_.vertices.push_back(p);
    return int(mesh_.vertices.size()) - 1;
  }
  void add_triangle(int a, int b, int c) { mesh_.triangles.push_back({a, b, c}); }
  // A planar quad a, b, c, d in order; normal (b - a) x (c - a).
  void add_quad(int a, int b, int c, int d) {
    add_triangle(a, b, c);
    add_triangle(a, c, d);
  }

  // The `segments` corners of the circle of `radius` about `centre`, counter-clockwise seen
  // from the tip of the axis; returns the index of the first.
  int add_ring(const Vec3d& centre, double radius) {
    const int first = int(mesh_.vertices.size());
    for (int k = 0; k < segments_; ++k)
      add_vertex(centre + u_ * (radius * cos_[k]) + v_ * (radius * sin_[k]));
    return first;
  }
  int next(int ring, int k) const { return ring + (k + 1) % segments_; }

  // The band between a lower ring and an upper ring (the upper further along the axis), facing
  // the axis: for corners B_k, B_k+1 below and T_k, T_k+1 above, the normal is
  // proportional to (r_top - r_bottom) axis - h radial, i.e. inward (and upward for a funnel).
  void add_band_facing_axis(int lower, int upper) {
    for (int k = 0; k < segments_; ++k) {
      add_triangle(lower + k, next(upper, k), next(lower, k));
      add_triangle(lower + k, upper + k, next(upper, k));
    }
  }
  // A disc as a fan about its centre; facing_axis: the normal is +axis, else -axis.
  void add_disc(const Vec3d& centre, int ring, bool facing_axis) {
    const int c = add_vertex(centre);
    for (int k = 0; k < segments_; ++k)
      facing_axis ? add_triangle(c, ring + k, next(ring, k))
                  : add_triangle(c, next(ring, k), ring + k);
  }
  // The annulus between an inner and an outer ring in one plane, normal +axis.
  void add_annulus_facing_axis(int inner, int outer) {
    for (int k = 0; k < segments_; ++k) {
      add_triangle(inner + k, outer + k, next(outer, k));
      add_triangle(inner + k, next(outer, k), next(inner, k));
    }
  }

  int triangle_count() const { return int(mesh_.triangles.size()); }
  TriangleMesh take() { return std::move(mesh_); }

 private:
  Vec3d axis_, u_, v_;
  int segments_;
  std::vector<double> cos_, sin_;
  TriangleMesh mesh_;
};

TriangleMesh transformed_mesh(const MeshWall& wall) {
  TriangleMesh mesh = wall.mesh;
  for (Vec3d& p : mesh.vertices) p = wall.translation + rotate(wall.rotation, p * wall.scale);
  return mesh;
}

TriangleMesh plane_mesh(const PlaneWall& wall) {
  Vec3d u, v;
  axis_basis(wall.normal, u, v);
  const double h = wall.size / 2;
  MeshBuilder b(wall.normal, 3);
  // Corners counter-clockwise seen from the normal's tip: (s u) x (s v) = s^2 normal.
  const int c0 = b.add_vertex(wall.point - u * h - v * h);
  const int c1 = b.add_vertex(wall.point + u * h - v * h);
  const int c2 = b.add_vertex(wall.point + u * h + v * h);
  const int c3 = b.add_vertex(wall.point - u * h + v * h);
  b.add_quad(c0, c1, c2, c3);
  return b.take();
}

TriangleMesh box_mesh(const BoxWall& wall) {
  MeshBuilder b(Vec3d(0, 0, 1), 3);
  // Corner (i, j, k) of the box, i, j, k in {0, 1} selecting min or max on x, y, z.
  int corner[2][2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k)
        corner[i][j][k] = b.add_vertex({i ? wall.max.x : wall.min.x, j ? wall.max.y : wall.min.y,
                                        k ? wall.max.z : wall.min.z});
  auto at = [&](int axis, int side, int s, int t) {
    // The corner on face (axis, side) at offsets s along axis+1 and t along axis+2 (cyclic).
    int index[3];
    index[axis] = side;
    index[(axis + 1) % 3] = s;
    index[(axis + 2) % 3] = t;
    return corner[index[0]][index[1]][index[2]];
  };
  for (int axis = 0; axis < 3; ++axis) {
    // e_{axis+1} x e_{axis+2} = e_axis: the min face wound (00, 10, 11, 01) faces +e_axis,
    // into the box; the max face is wound the other way.
    b.add_quad(at(axis, 0, 0, 0), at(axis, 0, 1, 0), at(axis, 0, 1, 1), at(axis, 0, 0, 1));
    if (axis == 2 && wall.open_top) continue;
    b.add_quad(at(axis, 1, 0, 0), at(axis, 1, 0, 1), at(axis, 1, 1, 1), at(axis, 1, 1, 0));
  }
  return b.take();
}

TriangleMesh cylinder_mesh(const Vec3d& base, const Vec3d& axis, double radius, double height,
                           bool bottom_cap, bool top_cap, int segments) {
  MeshBuilder b(axis, segments);
  const Vec3d top = base + axis * height;
  const int lower = b.add_ring(base, radius), upper = b.add_ring(top, radius);
  b.add_band_facing_axis(lower, upper);
  if (bottom_cap) b.add_disc(base, lower, true);
  if (top_cap) b.add_disc(top, upper, false);
  return b.take();
}

WallMesh hopper_mesh(const HopperWall& wall) {
  MeshBuilder b(wall.axis, wall.segments);
  const int outlet = b.add_ring(wall.base, wall.bottom_radius);
  const int top = b.add_ring(wall.base + wall.axis * wall.height, wall.top_radius);
  b.add_band_facing_axis(outlet, top);
  WallMesh result;
  if (wall.outlet.closed) {
    const int before = b.triangle_count();
    b.add_disc(wall.base, outlet, true);
    result.plate_triangles = b.triangle_count() - before;
  }
  result.mesh = b.take();
  return result;
}

WallMesh silo_mesh(const SiloWall& wall) {
  MeshBuilder b(wall.axis, wall.segments);
  const int outlet = b.add_ring(wall.base, wall.outlet_radius);
  const Vec3d bin_bottom = wall.base + wall.axis * wall.cone_height;
  const int bin_lower = b.add_ring(bin_bottom, wall.radius);
  const int bin_upper = b.add_ring(bin_bottom + wall.axis * wall.height, wall.radius);
  if (wall.cone_height > 0)
    b.add_band_facing_axis(outlet, bin_lower);
  else
    b.add_annulus_facing_axis(outlet, bin_lower);
  b.add_band_facing_axis(bin_lower, bin_upper);
  WallMesh result;
  if (wall.outlet.closed) {
    const int before = b.triangle_count();
    b.add_disc(wall.base, outlet, true);
    result.plate_triangles = b.triangle_count() - before;
  }
  result.mesh = b.take();
  return result;
}

}  // namespace

void axis_basis(const Vec3d& axis, Vec3d& u, Vec3d& v) {
  // Cross with the coordinate axis least aligned with `axis`, so that u is well conditioned.
  const double ax = std::fabs(axis.x), ay = std::fabs(axis.y), az = std::fabs(axis.z);
  const Vec3d pick = (ax <= ay && ax <= az) ? Vec3d(1, 0, 0)
                     : (ay <= az)           ? Vec3d(0, 1, 0)
                                            : Vec3d(0, 0, 1);
  u = cross(pick, axis);
  u = u / norm(u);
  v = cross(axis, u);  // axis x u = v gives u x v = axis for a unit axis
  v = v / norm(v);
}

WallMesh make_wall_mesh(const WallSpec& wall) {
  WallMesh result;
  switch (wall.kind) {
    case WallKind::mesh:
      result.mesh = transformed_mesh(std::get<MeshWall>(wall.shape));
      break;
    case WallKind::plane:
      result.mesh = plane_mesh(std::get<PlaneWall>(wall.shape));
      break;
    case WallKind::box:
      result.mesh = box_mesh(std::get<BoxWall>(wall.shape));
      break;
    case WallKind::cylinder: {
      const CylinderWall& c = std::get<CylinderWall>(wall.shape);
      result.mesh =
          cylinder_mesh(c.base, c.axis, c.radius, c.height, c.bottom_cap, c.top_cap, c.segments);
      break;
    }
    case WallKind::drum: {
      const DrumWall& d = std::get<DrumWall>(wall.shape);
      result.mesh = cylinder_mesh(d.center - d.axis * (d.length / 2), d.axis, d.radius, d.length,
                                  true, true, d.segments);
      break;
    }
    case WallKind::hopper:
      result = hopper_mesh(std::get<HopperWall>(wall.shape));
      break;
    case WallKind::silo:
      result = silo_mesh(std::get<SiloWall>(wall.shape));
      break;
  }
  if (result.mesh.triangles.empty())
    throw std::runtime_error(wall.source.where() + ": wall '" + wall.name + "' has no triangles");
  return result;
}

std::vector<WallMesh> make_wall_meshes(const Scene& scene) {
  std::vector<WallMesh> meshes;
  meshes.reserve(scene.walls.size());
  for (const WallSpec& wall : scene.walls) meshes.push_back(make_wall_mesh(wall));
  return meshes;
}

bool outlet_closed_at(const WallSpec& wall, double time) {
  const Outlet* outlet = nullptr;
  if (wall.kind == WallKind::hopper) outlet = &std::get<HopperWall>(wall.shape).outlet;
  if (wall.kind == WallKind::silo) outlet = &std::get<SiloWall>(wall.shape).outlet;
  if (!outlet || !outlet->closed) return false;
  return !outlet->opens_at || time < *outlet->opens_at;
}

int present_triangle_count(const WallSpec& wall, const WallMesh& mesh, double time) {
  return static_cast<int>(mesh.mesh.triangles.size()) -
         (outlet_closed_at(wall, time) ? 0 : mesh.plate_triangles);
}

std::vector<TriangleMesh> walls_at(const Scene& scene, const std::vector<WallMesh>& meshes,
                                   double time) {
  std::vector<TriangleMesh> walls;
  for (std::size_t w = 0; w < meshes.size(); ++w) {
    walls.push_back(transformed(meshes[w].mesh, wall_transform(scene.walls[w].motion, time)));
    walls.back().triangles.resize(present_triangle_count(scene.walls[w], meshes[w], time));
  }
  return walls;
}

double mesh_area(const TriangleMesh& mesh) {
  double area = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3d& a = mesh.vertices[t[0]];
    area += norm(cross(mesh.vertices[t[1]] - a, mesh.vertices[t[2]] - a)) / 2;
  }
  return area;
}

}  // namespace talus
