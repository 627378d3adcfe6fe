#include "solver/shape/builtins.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>

#include "solver/io/input_files.hpp"
#include "solver/shape/template_builder.hpp"

namespace talus {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kGolden = (1 + std::sqrt(5.0)) / 2;

// Comma-separated numbers; false unless every item is a finite number.
bool parse_numbers(const std::string& text, std::vector<double>& numbers) {
  numbers.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    char* end = nullptr;
    const double value = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(value)) return false;
    numbers.push_back(value);
    if (comma == std::string::npos) return true;
    start = comma + 1;
  }
}

std::vector<Vec3d> scaled(std::vector<Vec3d> points, double factor) {
  for (Vec3d& p : points) p *= factor;
  return points;
}

// Regular solids with circumradius 1, centred at the origin.
std::vector<Vec3d> platonic_points(const std::string& name) {
  const double phi = kGolden, s3 = std::sqrt(3.0);
  std::vector<Vec3d> points;
  if (name == "tetrahedron") {
    points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    return scaled(points, 1 / s3);
  }
  if (name == "octahedron")
    return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  if (name == "cube" || name == "dodecahedron") {
    for (int i = 0; i < 8; ++i)
      points.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    if (name == "dodecahedron")
      for (int i = 0; i < 4; ++i) {
        const double a = i & 1 ? 1 / phi : -1 / phi, b = i & 2 ? phi : -phi;
        points.push_back({0, a, b});  // cyclic permutations of (0, ±1/phi, ±phi)
        points.push_back({a, b, 0});
        points.push_back({b, 0, a});
      }
    return scaled(points, 1 / s3);
  }
  // icosahedron: cyclic permutations of (0, ±1, ±phi)
  for (int i = 0; i < 4; ++i) {
    const double a = i & 1 ? 1.0 : -1.0, b = i & 2 ? phi : -phi;
    points.push_back({0, a, b});
    points.push_back({a, b, 0});
    points.push_back({b, 0, a});
  }
  return scaled(points, 1 / std::sqrt(1 + phi * phi));
}

// A dent-corn kernel (BLAZE-DEM Fig. 19), length 1.3 along z, width 1: a wide, flat crown
// (hexagon), a bevelled shoulder, a waist and a narrow rounded tip; flattened in y (thickness ~
// half the width). Every point is a hull vertex, and neighbouring faces bend by more than 5
// degrees (both asserted by the tests): nearly coplanar faces only add ill-conditioned planes.
std::vector<Vec3d> corn_points() {
  std::vector<Vec3d> points;
  const auto ring = [&](int n, double phase_deg, double half_width, double half_thickness,
                        double z) {
    for (int k = 0; k < n; ++k) {
      const double angle = (phase_deg + 360.0 * k / n) * kPi / 180;
      points.push_back({half_width * std::cos(angle), half_thickness * std::sin(angle), z});
    }
  };
  ring(6, 0, 0.42, 0.20, 1.30);   // crown
  ring(6, 30, 0.50, 0.26, 1.10);  // shoulder
  ring(4, 45, 0.34, 0.15, 0.55);  // waist
  ring(4, 45, 0.10, 0.05, 0.0);   // tip
  return points;
}

// True when the template has the mineral's topology with clearly distinct faces.
bool is_good_mineral(const ShapeTemplate& shape) {
  return shape.vertices.size() == 18 && shape.faces.size() == 32 &&
         smallest_edge_bend_degrees(shape) > 5;
}

// 18 points spread over an ellipsoid (Fibonacci sphere, semi-axes 1 : 0.78 : 0.62), each jittered
// in direction and radius by a fixed-seed mt19937; the first seed giving 18 hull vertices and 32
// clearly distinct triangular faces is used, so the shape is the same on every platform.
std::vector<Vec3d> mineral_points() {
  for (std::uint32_t seed = 1; seed < 1000; ++seed) {
    std::mt19937 rng(seed);
    const auto uniform = [&](double low, double high) {
      return low + (high - low) * ((double(rng()) + 0.5) / 4294967296.0);  // 2^32
    };
    std::vector<Vec3d> points;
    for (int i = 0; i < 18; ++i) {
      const double z = 1 - (2 * i + 1) / 18.0, r = std::sqrt(1 - z * z);
      const double azimuth = i * kPi * (3 - std::sqrt(5.0));  // golden angle
      Vec3d d{r * std::cos(azimuth), r * std::sin(azimuth), z};
      d += Vec3d{uniform(-0.3, 0.3), uniform(-0.3, 0.3), uniform(-0.3, 0.3)};
      d = d * (uniform(0.85, 1.1) / norm(d));
      points.push_back({d.x, 0.78 * d.y, 0.62 * d.z});
    }
    if (is_good_mineral(make_template("mineral", points))) return points;
  }
  throw std::logic_error("mineral_points: no seed gave an 18-vertex, 32-face hull");
}

// Builds the template, then rescales the points so that the circumscribed diameter (about the
// centroid) is `diameter`.
ShapeTemplate with_diameter(const std::string& spec, const std::vector<Vec3d>& unit_points,
                            double diameter) {
  const ShapeTemplate unit = make_template(spec, unit_points);
  return make_template(spec, scaled(unit_points, diameter / (2 * unit.bounding_radius)));
}

// True when an unknown name looks like a file path with an extension talus does not read.
bool looks_like_file(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  if (name.find('/') != std::string::npos) return true;
  return dot != std::string::npos && dot + 1 < name.size() &&
         std::isalpha(static_cast<unsigned char>(name[dot + 1]));
}

// Throws when a size of the spec lies outside the range talus supports.
void check_size(const std::string& quoted, const std::string& what, double metres) {
  const std::string problem = shape_size_problem(metres);
  if (!problem.empty()) throw std::invalid_argument(quoted + what + " " + problem);
}

std::string names_list() {
  std::string list;
  for (const std::string& name : builtin_names()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

}  // namespace

std::vector<std::string> builtin_names() {
  return {"tetrahedron", "cube",     "octahedron", "dodecahedron", "icosahedron",
          "cuboid",      "cylinder", "corn",       "mineral"};
}

TriangleMesh cylinder_mesh(double diameter, double length, int sides) {
  if (!(diameter > 0) || !(length > 0) || sides < 3)
    throw std::invalid_argument("cylinder_mesh: needs positive diameter and length and >= 3 sides");
  TriangleMesh mesh;
  const double radius = diameter / 2, half = length / 2;
  // Vertices: bottom rim 0..N-1, top rim N..2N-1, bottom centre 2N, top centre 2N+1.
  for (int level = 0; level < 2; ++level)
    for (int k = 0; k < sides; ++k) {
      const double angle = 2 * kPi * k / sides;
      mesh.vertices.push_back(
          {radius * std::cos(angle), radius * std::sin(angle), level == 0 ? -half : half});
    }
  mesh.vertices.push_back({0, 0, -half});
  mesh.vertices.push_back({0, 0, half});
  const int bottom = 2 * sides, top = 2 * sides + 1;
  for (int k = 0; k < sides; ++k) {
    const int next = (k + 1) % sides;
    mesh.triangles.push_back({bottom, next, k});               // bottom cap, normal -z
    mesh.triangles.push_back({top, sides + k, sides + next});  // top cap, normal +z
    mesh.triangles.push_back({k, next, sides + next});         // side quad, two triangles
    mesh.triangles.push_back({k, sides + next, sides + k});
  }
  return mesh;
}

ShapeTemplate make_builtin(const std::string& spec) {
  const std::size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const std::string quoted = "shape spec '" + shown_input(spec, kShownSpecLimit) + "': ";
  bool known = false;
  for (const std::string& n : builtin_names()) known = known || n == name;
  if (!known && looks_like_file(name))
    throw std::invalid_argument(quoted + "'" + shown_input(name) +
                                "' is not a mesh file talus reads (.obj or .stl, any case) nor "
                                "a built-in shape");
  if (name == "sphere")
    throw std::invalid_argument(quoted +
                                "a sphere is not a polyhedron shape; a scene template takes "
                                "'sphere: R' (the radius in m) in place of 'shape'");
  if (!known)
    throw std::invalid_argument(quoted + "unknown shape '" + shown_input(name) +
                                "'; expected one of " + names_list() +
                                " (followed by ':size'), or an .obj/.stl file");
  std::vector<double> numbers;
  const bool parsed = colon != std::string::npos && parse_numbers(spec.substr(colon + 1), numbers);
  bool positive = parsed;
  for (double x : numbers) positive = positive && x > 0;
  const std::string got = colon == std::string::npos
                              ? ", got no size"
                              : ", got '" + shown_input(spec.substr(colon + 1)) + "'";

  if (name == "cuboid") {
    if (!positive || numbers.size() != 3)
      throw std::invalid_argument(quoted +
                                  "cuboid needs three positive side lengths a,b,c in metres, "
                                  "as in 'cuboid:0.01,0.02,0.03'" +
                                  got);
    for (int k = 0; k < 3; ++k) check_size(quoted, std::string("side ") + "abc"[k], numbers[k]);
    std::vector<Vec3d> points;
    for (int i = 0; i < 8; ++i)
      points.push_back({(i & 1 ? 0.5 : -0.5) * numbers[0], (i & 2 ? 0.5 : -0.5) * numbers[1],
                        (i & 4 ? 0.5 : -0.5) * numbers[2]});
    return make_template(spec, points);
  }
  if (name == "cylinder") {
    const std::string usage =
        "cylinder needs 'D,L' or 'D,L,N': positive diameter D and length L in metres and an "
        "integer number of sides N from 3 to 100000, as in 'cylinder:0.008,0.0053,20'";
    const bool has_sides = numbers.size() == 3;
    if (!parsed || (numbers.size() != 2 && !has_sides))
      throw std::invalid_argument(quoted + usage + got);
    if (has_sides &&
        !(numbers[2] >= 3 && numbers[2] <= 100000 && numbers[2] == std::floor(numbers[2]))) {
      char got[32];
      std::snprintf(got, sizeof got, "%g", numbers[2]);
      throw std::invalid_argument(quoted + "N = " + got +
                                  ": expected an integer number of sides from 3 to 100000");
    }
    if (!(numbers[0] > 0 && numbers[1] > 0)) throw std::invalid_argument(quoted + usage + got);
    check_size(quoted, "diameter D", numbers[0]);
    check_size(quoted, "length L", numbers[1]);
    const int sides = has_sides ? int(numbers[2]) : 20;
    return make_template(spec, cylinder_mesh(numbers[0], numbers[1], sides).vertices);
  }
  if (!positive || numbers.size() != 1)
    throw std::invalid_argument(quoted + name +
                                " needs one positive size D, the circumscribed-sphere diameter "
                                "in metres, as in '" +
                                name + ":0.01'" + got);
  const double diameter = numbers[0];
  check_size(quoted, "size D", diameter);
  if (name == "corn") return with_diameter(spec, corn_points(), diameter);
  if (name == "mineral") {
    static const std::vector<Vec3d> unit_mineral = mineral_points();  // searched once
    return with_diameter(spec, unit_mineral, diameter);
  }
  return make_template(spec, scaled(platonic_points(name), diameter / 2));
}

}  // namespace talus
