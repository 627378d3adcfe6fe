// The `walls` section: mesh files and generated shapes, each with a material and optional motion.
#include <cmath>
#include <cstdio>
#include <exception>

#include "solver/scene/scene_sections.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus {
namespace {

const std::vector<std::string> kCommonKeys = {"name", "material", "motion"};
const std::string kLength = "a positive number in m";
constexpr int kDefaultSegments = 64;  // sides of the polygon approximating a circle

// The keys a wall kind takes, after the common ones.
std::vector<std::string> wall_keys(std::initializer_list<const char*> own) {
  std::vector<std::string> keys = kCommonKeys;
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

std::string expected_wall(const std::string& kind, const std::vector<std::string>& keys) {
  return "a " + kind + " wall: a map with keys " + join_options(keys);
}

double length(const SceneNode& body, const std::string& key) {
  return body.at(key, kLength).positive("m");
}

Vec3d point(const SceneNode& body, const std::string& key, const std::string& what) {
  const std::string expected = what + " [x, y, z] in m";
  return body.at(key, expected).vec3(expected);
}

Vec3d axis_or_z(const SceneNode& body) {
  const std::optional<SceneNode> axis = body.find("axis");
  return axis ? axis->direction("an axis") : Vec3d(0, 0, 1);
}

int segments(const SceneNode& body) {
  const std::optional<SceneNode> node = body.find("segments");
  return node ? int(node->integer("an integer number of polygon sides, at least 3", 3, 100000))
              : kDefaultSegments;
}

Outlet parse_outlet(const SceneNode& body) {
  Outlet outlet;
  if (auto state = body.find("outlet"))
    outlet.closed = state->choice({"open", "closed"}, "the outlet's state") == "closed";
  if (auto opens_at = body.find("outlet_opens_at")) {
    if (!outlet.closed)
      opens_at->fail("outlet_opens_at applies to a closed outlet; add 'outlet: closed'");
    outlet.opens_at = opens_at->positive("s");
  }
  return outlet;
}

WallMotion parse_motion(const SceneNode& node) {
  const auto [kind, body] = node.one_of({"rotation", "translation", "oscillation"}, "motion");
  WallMotion motion;
  if (kind == "rotation") {
    body.keys({"axis", "point", "rpm"}, "a rotation: a map with keys axis, point, rpm");
    motion.kind = WallMotion::Kind::rotation;
    motion.axis = body.at("axis", "an axis [x, y, z]").direction("an axis");
    motion.point = point(body, "point", "a point on the axis");
    motion.rpm = body.at("rpm", "a number in revolutions per minute")
                     .number("a number in revolutions per minute");
  } else if (kind == "oscillation") {
    body.keys({"direction", "amplitude", "frequency", "start", "cycles"},
              "an oscillation: a map with keys direction, amplitude, frequency, start, cycles");
    motion.kind = WallMotion::Kind::oscillation;
    motion.direction = body.at("direction", "a direction [x, y, z]").direction("a direction");
    motion.amplitude = body.at("amplitude", "a positive amplitude in m").positive("m");
    motion.frequency = body.at("frequency", "a positive frequency in Hz").positive("Hz");
    if (auto start = body.find("start"))
      motion.start =
          start->number("a start time in s, at least 0", [](double v) { return v >= 0; });
    if (auto cycles = body.find("cycles"))
      motion.cycles = int(cycles->integer("a whole number of cycles, at least 1", 1, 100000000));
  } else {
    body.keys({"velocity"}, "a translation: a map with key velocity");
    motion.kind = WallMotion::Kind::translation;
    motion.velocity =
        body.at("velocity", "a velocity [x, y, z] in m/s").vec3("a velocity [x, y, z] in m/s");
  }
  return motion;
}

MeshWall parse_mesh(const SceneNode& body, const Scene& scene, const std::string& name) {
  const std::vector<std::string> keys = wall_keys({"file", "scale", "rotation", "translation"});
  body.keys(keys, expected_wall("mesh", keys));
  MeshWall wall;
  const SceneNode file = body.at("file", "an .obj or .stl file");
  const std::string path = file.text("an .obj or .stl file");
  if (!is_mesh_path(path)) file.fail_expected("an .obj or .stl file");
  wall.file = resolve_path(path, scene.directory);
  check_mesh_file_readable(file, wall.file);
  if (auto scale = body.find("scale"))
    wall.scale =
        scale->number("a positive number of metres per file unit", [](double v) { return v > 0; });
  if (auto rotation = body.find("rotation")) wall.rotation = rotation->orientation();
  if (auto translation = body.find("translation"))
    wall.translation = translation->vec3("a translation [x, y, z] in m");
  // The reader's message names the file and, in a text file, the line.
  try {
    wall.mesh = read_mesh(wall.file);
  } catch (const std::exception& e) {
    file.fail("wall '" + name + "': " + e.what());
  }
  if (wall.mesh.triangles.empty())
    file.fail("wall '" + name + "': the mesh file '" + wall.file + "' has " +
              std::to_string(wall.mesh.vertices.size()) +
              " vertices but no triangles (a wall needs faces: 'f a b c' lines in .obj)");
  return wall;
}

PlaneWall parse_plane(const SceneNode& body) {
  const std::vector<std::string> keys = wall_keys({"point", "normal", "size"});
  body.keys(keys, expected_wall("plane", keys));
  PlaneWall wall;
  wall.point = point(body, "point", "the plane's centre");
  wall.normal = body.at("normal", "a normal [x, y, z]").direction("a normal");
  wall.size = body.at("size", "a positive number in m (the square's side)")
                  .positive("m (the square's side)");
  return wall;
}

BoxWall parse_box(const SceneNode& body) {
  const std::vector<std::string> keys = wall_keys({"min", "max", "open_top"});
  body.keys(keys, expected_wall("box", keys));
  BoxWall wall;
  wall.min = point(body, "min", "the lowest corner");
  const std::string expected_max = "a corner [x, y, z] in m above min on every axis";
  const SceneNode max = body.at("max", expected_max);
  wall.max = max.vec3(expected_max);
  for (int k = 0; k < 3; ++k)
    if (!(wall.max[k] > wall.min[k])) max.fail_expected(expected_max);
  if (auto open_top = body.find("open_top")) wall.open_top = open_top->boolean();
  return wall;
}

CylinderWall parse_cylinder(const SceneNode& body) {
  const std::vector<std::string> keys =
      wall_keys({"base", "axis", "radius", "height", "bottom_cap", "top_cap", "segments"});
  body.keys(keys, expected_wall("cylinder", keys));
  CylinderWall wall;
  wall.base = point(body, "base", "the centre of the bottom circle");
  wall.axis = axis_or_z(body);
  wall.radius = length(body, "radius");
  wall.height = length(body, "height");
  if (auto cap = body.find("bottom_cap")) wall.bottom_cap = cap->boolean();
  if (auto cap = body.find("top_cap")) wall.top_cap = cap->boolean();
  wall.segments = segments(body);
  return wall;
}

DrumWall parse_drum(const SceneNode& body) {
  const std::vector<std::string> keys =
      wall_keys({"center", "axis", "radius", "length", "segments"});
  body.keys(keys, expected_wall("drum", keys));
  DrumWall wall;
  wall.center = point(body, "center", "the drum's centre");
  wall.axis = axis_or_z(body);
  wall.radius = length(body, "radius");
  wall.length = length(body, "length");
  wall.segments = segments(body);
  return wall;
}

HopperWall parse_hopper(const SceneNode& body) {
  const std::vector<std::string> keys =
      wall_keys({"base", "axis", "top_radius", "bottom_radius", "height", "outlet",
                 "outlet_opens_at", "segments"});
  body.keys(keys, expected_wall("hopper", keys));
  HopperWall wall;
  wall.base = point(body, "base", "the centre of the outlet circle");
  wall.axis = axis_or_z(body);
  wall.top_radius = length(body, "top_radius");
  const std::string expected_bottom = "a positive number in m below top_radius (the outlet)";
  wall.bottom_radius =
      body.at("bottom_radius", expected_bottom).number(expected_bottom, [&](double v) {
        return v > 0 && v < wall.top_radius;
      });
  wall.height = length(body, "height");
  wall.outlet = parse_outlet(body);
  wall.segments = segments(body);
  return wall;
}

SiloWall parse_silo(const SceneNode& body) {
  const std::vector<std::string> keys =
      wall_keys({"base", "axis", "radius", "height", "cone_height", "outlet_radius", "outlet",
                 "outlet_opens_at", "segments"});
  body.keys(keys, expected_wall("silo", keys));
  SiloWall wall;
  wall.base = point(body, "base", "the centre of the outlet circle");
  wall.axis = axis_or_z(body);
  wall.radius = length(body, "radius");
  wall.height = length(body, "height");
  if (auto cone = body.find("cone_height")) wall.cone_height = cone->non_negative("m");
  const std::string expected_outlet = "a positive number in m below the silo's radius";
  wall.outlet_radius =
      body.at("outlet_radius", expected_outlet).number(expected_outlet, [&](double v) {
        return v > 0 && v < wall.radius;
      });
  wall.outlet = parse_outlet(body);
  wall.segments = segments(body);
  return wall;
}

std::string g_format(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// The wall's triangles at t = 0 must have finite corners within kMaxWallReach of the origin (a
// huge size or coordinate once reached the contact as a corner it could not clip) and some area.
void check_wall_mesh(const WallSpec& wall, const SceneNode& body) {
  const WallMesh built = make_wall_mesh(wall);
  const bool from_file = wall.kind == WallKind::mesh;
  const std::string what =
      "wall '" + wall.name +
      "': " + (from_file ? "mesh file '" + std::get<MeshWall>(wall.shape).file + "': " : "");
  const SceneNode at = from_file ? body.at("file", "an .obj or .stl file") : body;
  for (std::size_t v = 0; v < built.mesh.vertices.size(); ++v) {
    const Vec3d& p = built.mesh.vertices[v];
    const double reach = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (!(reach <= kMaxWallReach))
      at.fail(what +
              (from_file ? "vertex " + std::to_string(v + 1) + ", placed by scale, " +
                               "rotation and translation,"
                         : "a corner") +
              (std::isfinite(reach) ? " lies " + g_format(reach) + " m from the origin"
                                    : " is not a finite point") +
              ", beyond the largest distance talus supports, " + g_format(kMaxWallReach) + " m");
  }
  const std::size_t n = built.mesh.triangles.size();
  if (!(mesh_area(built.mesh) > 0))
    at.fail(what +
            (n == 1 ? "its one triangle has" : "all " + std::to_string(n) + " triangles have") +
            " zero area; a wall needs a surface");
}

}  // namespace

void parse_walls(const SceneNode& node, Scene& scene) {
  const std::vector<std::string> kinds = {"mesh", "plane",  "box", "cylinder",
                                          "drum", "hopper", "silo"};
  const std::vector<SceneNode> items =
      node.items("a list of walls ({plane: ...}, {mesh: ...}, ...)");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto [kind, body] = items[i].one_of(kinds, "wall");
    WallSpec wall;
    const std::optional<SceneNode> name = body.is_map() ? body.find("name") : std::nullopt;
    wall.name = name ? name->name("a wall name") : kind + "_" + std::to_string(i);
    if (kind == "mesh") wall.kind = WallKind::mesh, wall.shape = parse_mesh(body, scene, wall.name);
    if (kind == "plane") wall.kind = WallKind::plane, wall.shape = parse_plane(body);
    if (kind == "box") wall.kind = WallKind::box, wall.shape = parse_box(body);
    if (kind == "cylinder") wall.kind = WallKind::cylinder, wall.shape = parse_cylinder(body);
    if (kind == "drum") wall.kind = WallKind::drum, wall.shape = parse_drum(body);
    if (kind == "hopper") wall.kind = WallKind::hopper, wall.shape = parse_hopper(body);
    if (kind == "silo") wall.kind = WallKind::silo, wall.shape = parse_silo(body);
    wall.material = material_reference(body.at("material", "a material name"), scene);
    if (auto motion = body.find("motion")) wall.motion = parse_motion(*motion);
    for (const WallSpec& other : scene.walls)
      if (other.name == wall.name)
        (name ? *name : body)
            .fail("wall name '" + wall.name + "' is already used by " + other.source.key);
    wall.source = body.ref();
    check_wall_mesh(wall, body);
    scene.walls.push_back(std::move(wall));
  }
}

}  // namespace talus
