#include "solver/render/frame_drawing.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

namespace talus {
namespace {

// Shading: ambient plus Lambert from a light above and to the left of the camera.
double shade(const ViewAxes& axes, const Vec3d& normal) {
  const Vec3d toward_light = axes.toward_viewer + axes.up * 0.6 - axes.right * 0.4;
  const Vec3d light = toward_light / norm(toward_light);
  return 0.35 + 0.65 * std::max(0.0, dot(normal, light));
}

Rgb scaled(const Rgb& c, double factor) {
  auto channel = [&](std::uint8_t v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v * factor, 0.0, 255.0)));
  };
  return {channel(c.r), channel(c.g), channel(c.b)};
}

// HSV (h in turns, s and v in [0, 1]) to 8-bit RGB.
Rgb hsv(double h, double s, double v) {
  h = 6 * (h - std::floor(h));
  const int sector = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  if (sector == 1) r = q, g = v, b = p;
  if (sector == 2) r = p, g = v, b = t;
  if (sector == 3) r = p, g = q, b = v;
  if (sector == 4) r = t, g = p, b = v;
  if (sector == 5) r = v, g = p, b = q;
  auto byte = [](double x) { return static_cast<std::uint8_t>(std::lround(255 * x)); };
  return {byte(r), byte(g), byte(b)};
}

Vec3d face_normal(const std::vector<Vec3d>& corners) {
  Vec3d n;  // Newell's method: exact for planar polygons, robust for slivers
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3d& a = corners[i];
    const Vec3d& b = corners[(i + 1) % corners.size()];
    n += Vec3d{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  const double length = norm(n);
  return length > 0 ? n / length : n;
}

// The convex hull of points in the picture, counter-clockwise in (column, row) without repeats
// (Andrew's monotone chain).
std::vector<PixelPoint> hull_2d(std::vector<PixelPoint> points) {
  std::sort(points.begin(), points.end(), [](const PixelPoint& a, const PixelPoint& b) {
    return a.column < b.column || (a.column == b.column && a.row < b.row);
  });
  if (points.size() < 3) return points;
  const auto turn = [](const PixelPoint& o, const PixelPoint& a, const PixelPoint& b) {
    return (a.column - o.column) * (b.row - o.row) - (a.row - o.row) * (b.column - o.column);
  };
  std::vector<PixelPoint> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {  // lower chain
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);  // the last point is the first
  return hull;
}

void add_wall_outline(const Projection& projection, const TriangleMesh& mesh,
                      std::vector<DrawSegment>& out) {
  const double crease_cos = std::cos(30.0 * 3.14159265358979323846 / 180.0);
  std::vector<Vec3d> normals;
  for (const auto& t : mesh.triangles)
    normals.push_back(face_normal({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]}));
  // Each undirected edge with the triangles that share it.
  std::map<std::pair<int, int>, std::vector<int>> edges;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
    for (int e = 0; e < 3; ++e) {
      const int a = mesh.triangles[k][e], b = mesh.triangles[k][(e + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(k));
    }
  for (const auto& [edge, triangles] : edges) {
    bool draw = triangles.size() != 2;  // a boundary (or a non-manifold edge)
    if (!draw) {
      const Vec3d& n0 = normals[triangles[0]];
      const Vec3d& n1 = normals[triangles[1]];
      const double f0 = dot(n0, projection.axes.toward_viewer);
      const double f1 = dot(n1, projection.axes.toward_viewer);
      draw = dot(n0, n1) < crease_cos || (f0 > 0) != (f1 > 0);
    }
    if (draw)
      out.push_back({projection.project(mesh.vertices[edge.first]),
                     projection.project(mesh.vertices[edge.second])});
  }
}

}  // namespace

const char* to_string(ColorMode mode) {
  switch (mode) {
    case ColorMode::velocity:
      return "velocity";
    case ColorMode::id:
      return "id";
    case ColorMode::normal:
      break;
  }
  return "normal";
}

Rgb id_color(long long id) {
  constexpr double kGoldenTurn = 0.6180339887498949;
  const long long level = ((id % 3) + 3) % 3;
  return hsv(0.07 + kGoldenTurn * double(id), level == 1 ? 0.55 : 0.85, level == 2 ? 0.65 : 0.95);
}

Rgb speed_color(double fraction) {
  fraction = std::clamp(std::isfinite(fraction) ? fraction : 1.0, 0.0, 1.0);
  return hsv((2.0 / 3.0) * (1 - fraction), 0.85, 0.95);  // hue 240 (blue) to 0 (red)
}

FrameDrawing draw_frame(const Projection& projection, const std::vector<TemplateSurface>& surfaces,
                        const std::vector<TrajectoryRow>& rows,
                        const std::vector<TriangleMesh>& walls, const DrawSettings& settings) {
  static const Rgb kBase{150, 170, 200};
  FrameDrawing drawing;
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return dot(projection.axes.toward_viewer, rows[a].position) <
           dot(projection.axes.toward_viewer, rows[b].position);
  });
  std::vector<Vec3d> posed, corners;
  for (const std::size_t k : order) {
    const TrajectoryRow& row = rows[k];
    const TemplateSurface& surface = surfaces.at(row.template_index);
    posed.clear();
    for (const Vec3d& v : surface.vertices)
      posed.push_back(row.position + rotate(row.orientation, v));
    Rgb base = kBase;
    if (settings.color == ColorMode::id) base = id_color(row.id);
    if (settings.color == ColorMode::velocity)
      base = speed_color(settings.max_speed > 0 ? norm(row.velocity) / settings.max_speed : 0);
    for (const std::vector<int>& face : surface.faces) {
      corners.clear();
      for (const int v : face) corners.push_back(posed[v]);
      const Vec3d normal = face_normal(corners);
      if (dot(normal, projection.axes.toward_viewer) <= 0) continue;  // faces away
      DrawPolygon polygon;
      polygon.particle = static_cast<int>(k);
      polygon.color =
          settings.color == ColorMode::id ? base : scaled(base, shade(projection.axes, normal));
      for (const Vec3d& c : corners) polygon.corners.push_back(projection.project(c));
      drawing.polygons.push_back(std::move(polygon));
    }
    if (settings.outline) {
      std::vector<PixelPoint> projected;
      for (const Vec3d& v : posed) projected.push_back(projection.project(v));
      DrawPolygon outline;
      outline.corners = hull_2d(std::move(projected));
      outline.color = kOutlineColor;
      outline.particle = static_cast<int>(k);
      outline.outline = true;
      drawing.polygons.push_back(std::move(outline));
    }
  }
  for (const TriangleMesh& wall : walls) add_wall_outline(projection, wall, drawing.wall_edges);
  return drawing;
}

}  // namespace talus
