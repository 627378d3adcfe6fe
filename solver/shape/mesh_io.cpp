#include "solver/shape/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "solver/io/input_files.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/hull.hpp"
#include "solver/shape/template_builder.hpp"

namespace talus {
namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}
[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool parse_double(const std::string& token, double& value) {
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return !token.empty() && end == token.c_str() + token.size() && std::isfinite(value);
}

bool parse_long(const std::string& token, long& value) {
  char* end = nullptr;
  errno = 0;
  value = std::strtol(token.c_str(), &end, 10);
  return !token.empty() && end == token.c_str() + token.size() && errno != ERANGE;
}

// Why `token` is not a coordinate: "" when it is one, else "'abc' is not a number" or "'nan' is
// not a finite number".
std::string number_problem(const std::string& token) {
  double value;
  if (parse_double(token, value)) return "";
  char* end = nullptr;
  std::strtod(token.c_str(), &end);
  const bool whole = !token.empty() && end == token.c_str() + token.size();
  return "'" + shown_input(token) + (whole ? "' is not a finite number" : "' is not a number");
}

std::string g_format(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// Merges vertices with identical coordinates (STL stores each facet's corners separately).
class VertexMerger {
 public:
  explicit VertexMerger(TriangleMesh& mesh) : mesh_(mesh) {}
  int index(const Vec3d& p) {
    const auto inserted =
        index_.emplace(std::array<double, 3>{p.x, p.y, p.z}, int(mesh_.vertices.size()));
    if (inserted.second) mesh_.vertices.push_back(p);
    return inserted.first->second;
  }
  void add_triangle(const std::array<Vec3d, 3>& corners) {
    const std::array<int, 3> t = {index(corners[0]), index(corners[1]), index(corners[2])};
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) mesh_.triangles.push_back(t);
  }

 private:
  TriangleMesh& mesh_;
  std::map<std::array<double, 3>, int> index_;
};

void read_ascii_stl(const std::string& path, const std::string& data, TriangleMesh& mesh) {
  struct Token {
    std::string text;
    int line;
  };
  std::vector<Token> tokens;
  int line = 1;
  for (std::size_t i = 0; i < data.size();) {
    if (data[i] == '\n') ++line;
    if (std::isspace(static_cast<unsigned char>(data[i]))) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < data.size() && !std::isspace(static_cast<unsigned char>(data[j]))) ++j;
    tokens.push_back({data.substr(i, j - i), line});
    i = j;
  }
  std::size_t pos = 0;
  const int last_line = line;
  const auto next = [&](const std::string& expected) -> const Token& {
    if (pos >= tokens.size()) fail(path, last_line, "unexpected end of file; expected " + expected);
    return tokens[pos++];
  };
  const auto expect = [&](const std::string& keyword, const std::string& context) {
    const Token& t = next("'" + context + "'");
    if (lower(t.text) != keyword)
      fail(path, t.line, "expected '" + context + "', got '" + shown_input(t.text) + "'");
  };
  const auto number = [&](const std::string& context) {
    const Token& t = next("'" + context + "'");
    double value;
    if (!parse_double(t.text, value))
      fail(path, t.line, number_problem(t.text) + "; expected '" + context + "'");
    return value;
  };
  // 'solid' and the rest of its line (the solid's name).
  const int solid_line = tokens[pos].line;
  ++pos;
  while (pos < tokens.size() && tokens[pos].line == solid_line) ++pos;
  VertexMerger merger(mesh);
  for (;;) {
    const Token& t = next("'facet normal nx ny nz' or 'endsolid'");
    const std::string keyword = lower(t.text);
    if (keyword == "endsolid") break;
    if (keyword != "facet")
      fail(path, t.line,
           "expected 'facet normal nx ny nz' or 'endsolid', got '" + shown_input(t.text) + "'");
    expect("normal", "facet normal nx ny nz");
    for (int k = 0; k < 3; ++k) number("facet normal nx ny nz");
    expect("outer", "outer loop");
    expect("loop", "outer loop");
    std::array<Vec3d, 3> corners;
    for (Vec3d& corner : corners) {
      expect("vertex", "vertex x y z");
      for (int k = 0; k < 3; ++k) corner[k] = number("vertex x y z");
    }
    expect("endloop", "endloop");
    expect("endfacet", "endfacet");
    merger.add_triangle(corners);
  }
}

void read_binary_stl(const std::string& path, const std::string& data, std::uint32_t n_triangles,
                     TriangleMesh& mesh) {
  VertexMerger merger(mesh);
  for (std::uint32_t t = 0; t < n_triangles; ++t) {
    const std::size_t offset = 84 + 50 * std::size_t(t);
    float values[12];  // normal, then the three corners; little-endian IEEE floats
    std::memcpy(values, data.data() + offset, sizeof values);
    std::array<Vec3d, 3> corners;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) {
        const float value = values[3 + 3 * c + k];
        // The text readers refuse "nan" and "inf" the same way; a NaN would otherwise reach the
        // hull as a point that is neither inside nor outside any plane.
        if (!std::isfinite(value))
          fail(path, "binary STL triangle " + std::to_string(t) + " (record at byte " +
                         std::to_string(offset) + "): vertex " + std::to_string(c + 1) + " " +
                         "xyz"[k] + " is " + (std::isnan(value) ? "NaN" : "infinite") +
                         "; expected a finite number");
        corners[c][k] = double(value);
      }
    merger.add_triangle(corners);
  }
}

// Finds whether mesh points lie on the surface of its hull (a template), looking first at the
// faces around nearby template vertices so that a convex mesh is checked in O(n) rather than
// against every face.
class SurfaceProbe {
 public:
  SurfaceProbe(const std::vector<Vec3d>& points, const TriangleMesh& mesh,
               const ShapeTemplate& hull, double tol)
      : hull_(hull),
        tol_(tol),
        vertex_of_point_(points.size(), -1),
        neighbours_(points.size()),
        faces_of_vertex_(hull.vertices.size()) {
    for (std::size_t v = 0; v < hull.input_indices.size(); ++v)
      vertex_of_point_[hull.input_indices[v]] = int(v);
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) neighbours_[t[k]].push_back(t[(k + 1) % 3]);
    for (std::size_t f = 0; f < hull.faces.size(); ++f)
      for (int v : hull.faces[f].loop) faces_of_vertex_[v].push_back(int(f));
  }

  // True when the input-frame point x is within tol of some face plane (it cannot be outside:
  // it is one of the hull's points or a triangle's centroid), trying the faces around the
  // template vertices among `near` and their mesh neighbours before all faces.
  bool on_surface(const Vec3d& x, const std::vector<int>& near) const {
    const Vec3d body = rotate_inverse(hull_.body_to_input, x - hull_.input_centroid);
    const auto touches = [&](int f) {
      return dot(hull_.faces[f].normal, body) - hull_.faces[f].offset >= -tol_;
    };
    const auto around = [&](int point) {
      const int v = vertex_of_point_[point];
      if (v >= 0)
        for (int f : faces_of_vertex_[v])
          if (touches(f)) return true;
      return false;
    };
    for (int p : near)
      if (around(p)) return true;
    for (int p : near)
      for (int q : neighbours_[p])
        if (around(q)) return true;
    for (int f = 0; f < int(hull_.faces.size()); ++f)
      if (touches(f)) return true;
    return false;
  }

 private:
  const ShapeTemplate& hull_;
  const double tol_;
  std::vector<int> vertex_of_point_;          // template vertex of each point, or -1
  std::vector<std::vector<int>> neighbours_;  // mesh neighbours of each point
  std::vector<std::vector<int>> faces_of_vertex_;
};

// True when the mesh is convex within tol: every vertex, and the centroid of every triangle, lies
// on the surface of its hull (a vertex strictly inside is a dent; a triangle whose centroid is
// strictly inside cuts through the body). Either orientation of the triangles is accepted. A
// convex mesh costs O(n); the first point found strictly inside ends the check.
bool is_convex(const std::vector<Vec3d>& points, const TriangleMesh& mesh,
               const ShapeTemplate& hull, double tol) {
  const SurfaceProbe probe(points, mesh, hull, tol);
  for (int p = 0; p < int(points.size()); ++p)
    if (!probe.on_surface(points[p], {p})) return false;
  for (const auto& t : mesh.triangles)
    if (!probe.on_surface((points[t[0]] + points[t[1]] + points[t[2]]) / 3.0, {t[0], t[1], t[2]}))
      return false;
  return true;
}

}  // namespace

bool is_mesh_path(const std::string& path) {
  const std::string l = lower(path);
  return ends_with(l, ".obj") || ends_with(l, ".stl");
}

TriangleMesh read_obj(const std::string& path) {
  std::istringstream in(read_input_file(path));
  TriangleMesh mesh;
  struct FaceRef {
    long index;  // 0-based
    int line;
  };
  std::vector<std::vector<FaceRef>> faces;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const std::string content = text.substr(0, text.find('#'));
    std::istringstream stream(content);
    std::string keyword;
    if (!(stream >> keyword)) continue;
    std::vector<std::string> args{std::istream_iterator<std::string>(stream),
                                  std::istream_iterator<std::string>()};
    if (keyword == "v") {
      // x y z, optionally w or an r g b colour.
      double xyz[3];
      if (args.size() < 3 || args.size() > 7)
        fail(path, line,
             "expected 'v x y z' with three numbers (then an optional w or r g b), got " +
                 std::to_string(args.size()) + " values");
      for (std::size_t k = 0; k < args.size(); ++k) {
        double value;
        if (!parse_double(args[k], value))
          fail(path, line,
               std::string("vertex ") +
                   (k < 3 ? std::string(1, "xyz"[k]) : "value " + std::to_string(k + 1)) + " " +
                   number_problem(args[k]) + "; expected 'v x y z' with three numbers");
        if (k < 3) xyz[k] = value;
      }
      mesh.vertices.push_back({xyz[0], xyz[1], xyz[2]});
    } else if (keyword == "f") {
      if (args.size() < 3)
        fail(path, line,
             "expected 'f a b c' with at least three vertex indices, got " +
                 std::to_string(args.size()));
      std::vector<FaceRef> face;
      for (const std::string& arg : args) {
        long ref;
        const std::string index_text = arg.substr(0, arg.find('/'));
        if (!parse_long(index_text, ref) && errno == ERANGE)
          fail(path, line,
               "face vertex index '" + shown_input(index_text) +
                   "' is beyond the vertices any file can hold");
        if (!parse_long(index_text, ref) || ref == 0)
          fail(path, line,
               "expected a vertex index (1-based, or negative from the end), got '" +
                   shown_input(arg) + "'");
        const long index = ref > 0 ? ref - 1 : long(mesh.vertices.size()) + ref;
        if (index < 0)
          fail(path, line,
               "face vertex " + std::to_string(ref) + " refers before the first vertex");
        face.push_back({index, line});
      }
      faces.push_back(std::move(face));
    } else if (keyword != "vt" && keyword != "vn" && keyword != "vp" && keyword != "g" &&
               keyword != "o" && keyword != "s" && keyword != "l" && keyword != "p" &&
               keyword != "usemtl" && keyword != "mtllib") {
      fail(path, line,
           "unknown statement '" + shown_input(keyword) +
               "'; expected 'v' or 'f' (vt, vn, vp, g, o, s, l, p, usemtl and mtllib "
               "are ignored)");
    }
  }
  if (mesh.vertices.empty()) fail(path, "no vertices; expected 'v x y z' lines");
  for (const auto& face : faces) {
    for (const FaceRef& ref : face)
      if (ref.index >= long(mesh.vertices.size()))
        fail(path, ref.line,
             "face refers to vertex " + std::to_string(ref.index + 1) + ", but the file has " +
                 std::to_string(mesh.vertices.size()) + " vertices");
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const std::array<int, 3> t = {int(face[0].index), int(face[k].index), int(face[k + 1].index)};
      if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) mesh.triangles.push_back(t);
    }
  }
  return mesh;
}

TriangleMesh read_stl(const std::string& path) {
  const std::string data = read_input_file(path);
  TriangleMesh mesh;
  std::uint64_t announced = 0;
  if (data.size() >= 84) {
    std::uint32_t n_triangles;
    std::memcpy(&n_triangles, data.data() + 80, 4);
    announced = n_triangles;
    if (84 + 50 * announced == data.size()) {
      read_binary_stl(path, data, n_triangles, mesh);
      if (announced == 0) fail(path, "binary STL has no facets (its header announces 0)");
      if (mesh.triangles.empty())
        fail(path, "binary STL: all " + std::to_string(announced) +
                       " facets collapse to a line or a point");
      return mesh;
    }
  }
  const std::size_t first = data.find_first_not_of(" \t\r\n");
  // A binary STL whose 80-byte header starts with "solid" (some exporters write one) and whose
  // size does not match its count is reported as a binary file: ASCII STL has no NUL bytes.
  const bool binary_bytes = data.size() >= 84 && data.find('\0', 80) != std::string::npos;
  const bool starts_solid = first != std::string::npos && lower(data.substr(first, 5)) == "solid";
  if (starts_solid && !binary_bytes) {
    read_ascii_stl(path, data.substr(first), mesh);
    if (mesh.triangles.empty()) fail(path, "ASCII STL has no facets; expected 'facet normal ...'");
    return mesh;
  }
  if (data.size() < 84)
    fail(path,
         "expected an ASCII STL starting with 'solid' or a binary STL of at least 84 bytes; "
         "the file has " +
             std::to_string(data.size()) + " bytes");
  fail(path, "binary STL header announces " + std::to_string(announced) + " triangles (" +
                 std::to_string(84 + 50 * announced) + " bytes), but the file has " +
                 std::to_string(data.size()) + " bytes" +
                 (starts_solid ? " (it starts with 'solid' but holds NUL bytes, so it is not an "
                                 "ASCII STL)"
                               : " (and it does not start with 'solid')"));
}

TriangleMesh read_mesh(const std::string& path) {
  const std::string l = lower(path);
  if (ends_with(l, ".obj")) return read_obj(path);
  if (ends_with(l, ".stl")) return read_stl(path);
  fail(path, "unknown mesh file type; expected an .obj or .stl file");
}

void write_obj(const std::string& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  if (!out) fail(path, "cannot open the file for writing");
  char buffer[128];
  for (const Vec3d& v : mesh.vertices) {
    std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n", v.x, v.y, v.z);
    out << buffer;
  }
  for (const auto& t : mesh.triangles)
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  if (!out) fail(path, "write failed");
}

void write_stl(const std::string& path, const TriangleMesh& mesh, bool binary) {
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(path, "cannot open the file for writing");
  const auto facet_normal = [&](const std::array<int, 3>& t) {
    const Vec3d n =
        cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    return norm(n) > 0 ? n / norm(n) : n;
  };
  if (binary) {
    char header[80] = "talus binary STL";
    out.write(header, 80);
    const std::uint32_t n = std::uint32_t(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : mesh.triangles) {
      const Vec3d n_facet = facet_normal(t);
      float values[12] = {float(n_facet.x), float(n_facet.y), float(n_facet.z)};
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) values[3 + 3 * c + k] = float(mesh.vertices[t[c]][k]);
      out.write(reinterpret_cast<const char*>(values), sizeof values);
      const std::uint16_t attribute = 0;
      out.write(reinterpret_cast<const char*>(&attribute), 2);
    }
  } else {
    char buffer[160];
    out << "solid talus\n";
    for (const auto& t : mesh.triangles) {
      const Vec3d n = facet_normal(t);
      std::snprintf(buffer, sizeof buffer, "  facet normal %.17g %.17g %.17g\n    outer loop\n",
                    n.x, n.y, n.z);
      out << buffer;
      for (int c = 0; c < 3; ++c) {
        const Vec3d& v = mesh.vertices[t[c]];
        std::snprintf(buffer, sizeof buffer, "      vertex %.17g %.17g %.17g\n", v.x, v.y, v.z);
        out << buffer;
      }
      out << "    endloop\n  endfacet\n";
    }
    out << "endsolid talus\n";
  }
  if (!out) fail(path, "write failed");
}

ShapeTemplate load_shape_file(const std::string& path, double scale) {
  if (!(scale > 0) || !std::isfinite(scale))
    throw std::invalid_argument(path + ": scale must be a positive finite number, got " +
                                g_format(scale));
  const TriangleMesh mesh = read_mesh(path);
  std::vector<Vec3d> points = mesh.vertices;
  for (Vec3d& p : points) p *= scale;
  // The size range of shapes (template_builder.hpp), on the scaled mesh: its extent and its
  // farthest vertex from the origin (where round-off would swamp a small shape far away).
  const std::string scaled = scale == 1 ? "" : " (scaled by " + g_format(scale) + ")";
  double reach = 0;
  Vec3d lo = points.front(), hi = points.front();
  for (const Vec3d& p : points)
    for (int k = 0; k < 3; ++k) {
      reach = std::max(reach, std::abs(p[k]));
      lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
  if (!(reach <= kMaxShapeSize))
    fail(path, "a vertex lies " + g_format(reach) + " m from the origin" + scaled +
                   ", beyond the largest size talus supports, " + g_format(kMaxShapeSize) + " m");
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (extent > 0 && extent < kMinShapeSize)
    fail(path, "the mesh is " + g_format(extent) + " m across" + scaled +
                   ", below the smallest size talus supports, " + g_format(kMinShapeSize) + " m");
  ShapeTemplate shape;
  try {
    shape = make_template(path, points, kMeshFileRelTol);
  } catch (const std::runtime_error& e) {
    fail(path, std::string("cannot build a convex shape from the mesh: ") + e.what());
  }
  if (!is_convex(points, mesh, shape, hull_tolerance(points, kMeshFileRelTol)))
    std::cerr << path << ": mesh is not convex; using its convex hull\n";
  return shape;
}

ShapeTemplate make_shape(const std::string& spec) {
  if (is_mesh_path(spec)) return load_shape_file(spec);
  const std::size_t colon = spec.rfind(':');
  if (colon != std::string::npos && is_mesh_path(spec.substr(0, colon))) {
    double scale;
    if (!parse_double(spec.substr(colon + 1), scale) || !(scale > 0))
      throw std::invalid_argument("shape spec '" + shown_input(spec, kShownSpecLimit) +
                                  "': expected 'path:scale' with a positive scale factor (file "
                                  "units to metres), as in 'grain.stl:0.001', got '" +
                                  shown_input(spec.substr(colon + 1)) + "'");
    return load_shape_file(spec.substr(0, colon), scale);
  }
  return make_builtin(spec);
}

}  // namespace talus
