// The `materials`, `material_pairs` and `templates` sections, and the name references into them.
#include <cmath>
#include <exception>
#include <filesystem>

#include "solver/io/input_files.hpp"
#include "solver/scene/scene_sections.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus {
namespace {

const std::string kDensity = "a positive number in kg/m^3";
const std::string kYoungsModulus = "a positive number in Pa (Young's modulus)";
const std::string kPoissonRatio = "a number in [0, 0.5) (Poisson's ratio)";
const std::string kFriction = "a non-negative number (Coulomb friction coefficient)";
const std::string kRestitution = "a number in (0, 1] (coefficient of restitution)";

bool valid_friction(double mu) {
  return mu >= 0;
}
bool valid_restitution(double epsilon) {
  return epsilon > 0 && epsilon <= 1;
}

// Names are keys of maps here; the same rule as SceneNode::name.
void check_name(const std::string& name, const SceneNode& at, const std::string& what) {
  bool ok = !name.empty() && std::isalpha(static_cast<unsigned char>(name[0]));
  for (char c : name)
    ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
  if (!ok)
    at.fail("expected a " + what +
            " name of letters, digits, '_' or '-', starting with a letter, got " + quoted(name));
}

template <class Item>
std::vector<std::string> names_of(const std::vector<Item>& items) {
  std::vector<std::string> names;
  for (const Item& item : items) names.push_back(item.name);
  return names;
}

template <class Item>
int reference(const SceneNode& node, const std::vector<Item>& items, const std::string& what) {
  const std::string name = node.text("a " + what + " name");
  for (std::size_t i = 0; i < items.size(); ++i)
    if (items[i].name == name) return int(i);
  const std::vector<std::string> names = names_of(items);
  const std::optional<std::string> close = closest_option(name, names);
  node.fail("unknown " + what + " " + quoted(name) + "; defined: " + join_options(names) +
            (close ? " (did you mean '" + *close + "'?)" : ""));
}

}  // namespace

int material_reference(const SceneNode& node, const Scene& scene) {
  return reference(node, scene.materials, "material");
}

int template_reference(const SceneNode& node, const Scene& scene) {
  return reference(node, scene.templates, "template");
}

std::string resolve_path(const std::string& path, const std::string& directory) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || directory.empty()) return p.lexically_normal().string();
  return (std::filesystem::path(directory) / p).lexically_normal().string();
}

void check_mesh_file_readable(const SceneNode& node, const std::string& resolved_path) {
  const std::string problem = input_file_problem(resolved_path);
  if (!problem.empty())
    node.fail("mesh file '" + resolved_path + "' " + problem +
              " (relative paths start at the scene file's directory)");
}

void parse_materials(const SceneNode& node, Scene& scene) {
  const std::string expected = "a map from material names to their properties";
  const auto entries = node.entries(expected);
  if (entries.empty()) node.fail_expected(expected + " (at least one)");
  for (const auto& [name, body] : entries) {
    check_name(name, body, "material");
    body.keys({"density", "youngs_modulus", "poisson_ratio", "friction", "restitution"},
              "a material: a map with keys density, youngs_modulus, poisson_ratio, friction, "
              "restitution");
    Material material;
    material.name = name;
    material.density = body.at("density", kDensity).positive("kg/m^3");
    material.youngs_modulus =
        body.at("youngs_modulus", kYoungsModulus).number(kYoungsModulus, [](double v) {
          return v > 0;
        });
    material.poisson_ratio =
        body.at("poisson_ratio", kPoissonRatio).number(kPoissonRatio, [](double v) {
          return v >= 0 && v < 0.5;
        });
    material.friction = body.at("friction", kFriction).number(kFriction, valid_friction);
    material.restitution =
        body.at("restitution", kRestitution).number(kRestitution, valid_restitution);
    material.source = body.ref();
    scene.materials.push_back(material);
  }
}

void parse_material_pairs(const SceneNode& node, Scene& scene) {
  for (const SceneNode& item : node.items("a list of material pairs")) {
    item.keys({"materials", "friction", "restitution"},
              "a material pair: a map with keys materials, friction, restitution");
    const SceneNode names = item.at("materials", "two material names [a, b]");
    const std::vector<SceneNode> two = names.items("two material names [a, b]");
    if (two.size() != 2) names.fail_expected("two material names [a, b]");
    MaterialPair pair;
    pair.material_a = material_reference(two[0], scene);
    pair.material_b = material_reference(two[1], scene);
    if (pair.material_a > pair.material_b) std::swap(pair.material_a, pair.material_b);
    if (auto friction = item.find("friction"))
      pair.friction = friction->number(kFriction, valid_friction);
    if (auto restitution = item.find("restitution"))
      pair.restitution = restitution->number(kRestitution, valid_restitution);
    if (!pair.friction && !pair.restitution)
      item.fail("expected friction, restitution or both to override for this pair, got neither");
    for (const MaterialPair& other : scene.material_pairs)
      if (other.material_a == pair.material_a && other.material_b == pair.material_b)
        names.fail("this pair of materials is already given on line " +
                   std::to_string(other.source.line));
    pair.source = item.ref();
    scene.material_pairs.push_back(pair);
  }
}

namespace {

const std::string kShapeSpec =
    "a shape: a built-in spec such as 'dodecahedron:0.01' or an .obj/.stl file, optionally "
    "'file:scale'";

void parse_polyhedron(const SceneNode& shape_node, const std::optional<SceneNode>& scale_node,
                      const Scene& scene, ParticleTemplate& result) {
  result.kind = ParticleShapeKind::polyhedron;
  result.shape_spec = shape_node.text(kShapeSpec);
  const std::string& spec = result.shape_spec;
  const std::size_t colon = spec.rfind(':');
  const bool mesh_with_scale = colon != std::string::npos && is_mesh_path(spec.substr(0, colon));
  const bool mesh = is_mesh_path(spec) || mesh_with_scale;
  if (scale_node && !mesh)
    scale_node->fail("scale applies to mesh files only; a built-in shape's size is in its spec");
  if (scale_node && mesh_with_scale)
    scale_node->fail("the shape spec already gives a scale ('" + spec + "'); give it once");
  result.resolved_spec = spec;
  if (mesh) {
    const std::string path = mesh_with_scale ? spec.substr(0, colon) : spec;
    result.mesh_file = resolve_path(path, scene.directory);
    check_mesh_file_readable(shape_node, result.mesh_file);
    result.resolved_spec = result.mesh_file + (mesh_with_scale ? spec.substr(colon) : "");
  }
  // The scale is read before the loader runs: its own error names the scale key, not the shape.
  if (scale_node) {
    result.mesh_scale = scale_node->number("a positive number of metres per file unit",
                                           [](double v) { return v > 0; });
    result.resolved_spec += ":" + scale_node->text("a scale");
  }
  try {
    if (scale_node) {
      result.shape = load_shape_file(result.mesh_file, result.mesh_scale);
    } else {
      result.shape = make_shape(result.resolved_spec);  // checks the scale of "file:scale"
      if (mesh_with_scale) result.mesh_scale = std::stod(spec.substr(colon + 1));
    }
  } catch (const std::exception& e) {
    shape_node.fail(e.what());
  }
  result.volume = result.shape.volume;
  result.bounding_radius = result.shape.bounding_radius;
}

}  // namespace

void parse_templates(const SceneNode& node, Scene& scene) {
  const std::string expected = "a map from template names to particle shapes and materials";
  const auto entries = node.entries(expected);
  if (entries.empty()) node.fail_expected(expected + " (at least one)");
  for (const auto& [name, body] : entries) {
    check_name(name, body, "template");
    body.keys({"shape", "scale", "sphere", "material"},
              "a particle template: a map with keys shape (and scale) or sphere, and material");
    ParticleTemplate result;
    result.name = name;
    const std::optional<SceneNode> shape = body.find("shape"), sphere = body.find("sphere");
    if (shape.has_value() == sphere.has_value())
      body.fail("expected either 'shape' (" + kShapeSpec + ") or 'sphere' (a radius in m), got " +
                (shape ? "both" : "neither"));
    if (shape) {
      parse_polyhedron(*shape, body.find("scale"), scene, result);
    } else {
      if (auto scale = body.find("scale"))
        scale->fail("scale applies to mesh files only; a sphere's size is its radius");
      result.kind = ParticleShapeKind::sphere;
      result.sphere_radius = sphere->positive("m (the sphere's radius)");
      result.volume = 4.0 / 3.0 * M_PI * std::pow(result.sphere_radius, 3);
      result.bounding_radius = result.sphere_radius;
    }
    result.material = material_reference(body.at("material", "a material name"), scene);
    result.source = body.ref();
    scene.templates.push_back(std::move(result));
  }
}

}  // namespace talus
