// The `effects` and `outputs` sections.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "solver/io/output_names.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_sections.hpp"

namespace talus {
namespace {

const std::string kTangentialDamping =
    "a non-negative number in N s/m (gamma of BLAZE-DEM Eq. 3, the friction force's cap per "
    "unit tangential speed)";

// Returns whether the linear model's tangential_damping was given.
bool parse_contact(const SceneNode& node, Effects& effects) {
  const std::vector<std::string> models = {"volume", "volume_paper", "linear"};
  const std::string what = "a contact model";
  if (!node.is_map()) {
    const std::string model = node.choice(models, what);
    if (model == "linear")
      node.fail(
          "the linear model needs its parameters: write {model: linear, stiffness: K_N, "
          "damping: eta, tangential_damping: gamma}");
    effects.contact = model == "volume" ? ContactModel::volume : ContactModel::volume_paper;
    return false;
  }
  node.keys({"model", "stiffness", "damping", "tangential_damping"},
            "a contact model: volume, volume_paper, or {model: linear, stiffness, damping, "
            "tangential_damping}");
  const SceneNode model = node.at("model", what + ", one of volume, volume_paper, linear");
  const std::string name = model.choice(models, what);
  if (name != "linear") {
    effects.contact = name == "volume" ? ContactModel::volume : ContactModel::volume_paper;
    for (const char* key : {"stiffness", "damping", "tangential_damping"})
      if (auto extra = node.find(key))
        extra->fail(
            "the volume model takes its stiffness and damping from the materials "
            "(paper Eqs. 13, 15, 19, 20); only the linear model has this key");
    return false;
  }
  // BLAZE-DEM Eqs. 2-3.
  effects.contact = ContactModel::linear;
  effects.linear.stiffness =
      node.at("stiffness", "a positive number in N/m (K_N of BLAZE-DEM Eq. 2)").positive("N/m");
  effects.linear.damping =
      node.at("damping", "a non-negative number in N s/m (eta of BLAZE-DEM Eq. 2)")
          .non_negative("N s/m");
  const std::optional<SceneNode> gamma = node.find("tangential_damping");
  if (gamma)
    effects.linear.tangential_damping =
        gamma->number(kTangentialDamping, [](double v) { return v >= 0; });
  return gamma.has_value();
}

}  // namespace

void parse_effects(const SceneNode& node, Scene& scene) {
  Effects& effects = scene.effects;
  effects.walls = !scene.walls.empty();
  for (const WallSpec& wall : scene.walls)
    effects.moving_walls = effects.moving_walls || wall.motion.kind != WallMotion::Kind::none;
  if (node.is_null()) return;  // `effects:` with nothing: none
  if (node.is_map())
    if (auto walls = node.find("walls"))
      walls->fail("the walls effect follows from the walls list; leave it out of effects");
  node.keys({"gravity", "contact", "friction", "rotation", "drag"},
            "a map of effects (gravity, contact, friction, rotation, drag)", "effect");
  if (auto gravity = node.find("gravity"))
    effects.gravity = gravity->vec3("a gravitational acceleration [x, y, z] in m/s^2");
  const std::optional<SceneNode> contact = node.find("contact");
  const bool has_tangential_damping = contact && parse_contact(*contact, effects);
  if (contact) scene.contact_source = contact->ref();
  if (auto rotation = node.find("rotation")) effects.rotation = rotation->boolean();
  if (auto drag = node.find("drag")) {
    drag->keys({"alpha"}, "a quadratic drag: {alpha: a positive number in kg/m}");
    effects.drag_alpha =
        drag->at("alpha", "a positive number in kg/m (F = -alpha |v| v)").positive("kg/m");
  }
  if (auto friction = node.find("friction")) {
    effects.friction = friction->boolean();
    if (effects.friction && !effects.contact)
      friction->fail(
          "friction acts at contacts: the scene needs a contact model "
          "(effects.contact)");
    if (effects.friction && effects.contact == ContactModel::linear && !has_tangential_damping)
      contact->fail("the linear model with friction needs tangential_damping: " +
                    kTangentialDamping);
  }
}

namespace {

// Steps between outputs; a run has at most kMaxSteps steps, so a larger `every` means nothing.
const std::string kEvery = "a positive integer number of steps";

TrajectoryOutput parse_trajectories(const SceneNode& node) {
  node.keys({"every", "directory", "format"},
            "trajectories: a map with keys every, directory, format");
  TrajectoryOutput output;
  output.every = node.at("every", kEvery).integer(kEvery, 1, kMaxSteps);
  output.directory = "trajectories";
  if (auto directory = node.find("directory"))
    output.directory = directory->text("a directory path");
  if (auto format = node.find("format")) {
    // The value that once chose VTK here: ParaView files are an output of their own now.
    if (format->text("a trajectory format") == "vtk")
      format->fail(
          "trajectories are CSV or HDF5 files; for ParaView's VTK files write "
          "outputs.vtk");
    output.format = format->choice({"csv", "hdf5"}, "a trajectory format") == "csv"
                        ? TrajectoryFormat::csv
                        : TrajectoryFormat::hdf5;
  }
  return output;
}

VtkOutput parse_vtk(const SceneNode& node) {
  node.keys({"every", "directory", "particles"},
            "vtk: a map with keys every, directory, particles");
  VtkOutput output;
  output.every = node.at("every", kEvery).integer(kEvery, 1, kMaxSteps);
  output.directory = "vtk";
  if (auto directory = node.find("directory"))
    output.directory = directory->text("a directory path");
  if (auto particles = node.find("particles"))
    output.particles = particles->choice({"surfaces", "points"}, "a particle form") == "surfaces"
                           ? VtkParticles::surfaces
                           : VtkParticles::points;
  return output;
}

CheckpointOutput parse_checkpoint(const SceneNode& node) {
  node.keys({"every", "directory", "keep"}, "checkpoint: a map with keys every, directory, keep");
  CheckpointOutput output;
  output.every = node.at("every", kEvery).integer(kEvery, 1, kMaxSteps);
  output.directory = "checkpoints";
  if (auto directory = node.find("directory"))
    output.directory = directory->text("a directory path");
  const std::string keep = "a positive integer number of checkpoint files";
  if (auto count = node.find("keep")) output.keep = static_cast<int>(count->integer(keep, 1, 1000));
  return output;
}

ProbeOutput parse_probes(const SceneNode& node, const Scene& scene) {
  node.keys({"every", "file", "quantities"}, "probes: a map with keys every, file, quantities");
  ProbeOutput output;
  output.every = node.at("every", kEvery).integer(kEvery, 1, kMaxSteps);
  output.file = "probes.csv";
  if (auto file = node.find("file")) output.file = file->text("a file path");
  const std::vector<Probe> all = {Probe::kinetic_energy, Probe::wall_forces, Probe::contact_count,
                                  Probe::bed_height, Probe::energy};
  std::vector<std::string> names;
  for (Probe p : all) names.push_back(to_string(p));
  const SceneNode quantities = node.at("quantities", "a list of probes");
  const std::vector<SceneNode> items =
      quantities.items("a list of probes, from " + join_options(names));
  if (items.empty()) quantities.fail_expected("a list of probes (at least one)");
  for (const SceneNode& item : items) {
    const std::string name = item.choice(names, "a probe");
    const Probe probe = all[std::find(names.begin(), names.end(), name) - names.begin()];
    if (std::find(output.quantities.begin(), output.quantities.end(), probe) !=
        output.quantities.end())
      item.fail("probe '" + name + "' is listed twice");
    if (probe == Probe::wall_forces && scene.walls.empty())
      item.fail("wall_forces needs walls; the scene has none");
    if (probe == Probe::contact_count && !scene.effects.contact)
      item.fail("contact_count needs a contact model (effects.contact)");
    if (probe == Probe::bed_height && !scene.effects.gravity)
      item.fail("bed_height is measured against gravity; the scene has no effects.gravity");
    output.quantities.push_back(probe);
  }
  return output;
}

// Refuses outputs that would write over each other (relative paths are compared as written:
// they share the run's output root): two outputs on one path, a probe file named like a file that
// the output directory it lies in writes, or like the run lock.
void check_output_paths(const SceneNode& node, const Outputs& o) {
  struct Placed {
    const char* key;
    std::string path;
    bool (*writes)(const std::string&);  // the names the output writes in its directory
  };
  std::vector<Placed> placed;
  if (o.trajectories)
    placed.push_back({"trajectories", o.trajectories->directory, trajectory_output_name});
  if (o.probes) placed.push_back({"probes", o.probes->file, nullptr});
  if (o.vtk) placed.push_back({"vtk", o.vtk->directory, vtk_output_name});
  if (o.checkpoint)
    placed.push_back({"checkpoint", o.checkpoint->directory, checkpoint_output_name});
  const auto normal = [](const std::string& path) {
    std::string text = std::filesystem::path(path).lexically_normal().generic_string();
    while (text.size() > 1 && text.back() == '/') text.pop_back();
    return text.empty() ? std::string(".") : text;
  };
  const auto fail_at = [&](const Placed& p, const std::string& message) {
    const SceneNode item = node.at(p.key, "");
    if (auto where = item.find(p.writes ? "directory" : "file")) where->fail(message);
    item.fail(message);
  };
  for (std::size_t a = 0; a < placed.size(); ++a)
    for (std::size_t b = a + 1; b < placed.size(); ++b)
      if (normal(placed[a].path) == normal(placed[b].path))
        fail_at(placed[b], std::string("'") + placed[b].path + "' is also the path of outputs." +
                               placed[a].key + "; give each output a path of its own");
  if (!o.probes) return;
  const Placed& probes = placed[o.trajectories ? 1 : 0];
  const std::filesystem::path probe(normal(o.probes->file));
  const std::string name = probe.filename().string();
  const std::string parent = probe.has_parent_path() ? normal(probe.parent_path().string()) : ".";
  if (parent == "." && name == kRunLockFile)
    fail_at(probes,
            "'" + o.probes->file + "' is the run lock's file; name the probe file another way");
  for (const Placed& p : placed)
    if (p.writes && normal(p.path) == parent && p.writes(name))
      fail_at(probes, "'" + o.probes->file + "' lies in the directory of outputs." + p.key +
                          " under a name that output writes; name the probe file another way");
}

}  // namespace

void parse_outputs(const SceneNode& node, Scene& scene) {
  node.keys({"trajectories", "probes", "vtk", "checkpoint"},
            "a map of outputs (trajectories, probes, vtk, checkpoint)");
  if (auto trajectories = node.find("trajectories"))
    scene.outputs.trajectories = parse_trajectories(*trajectories);
  if (auto probes = node.find("probes")) scene.outputs.probes = parse_probes(*probes, scene);
  if (auto vtk = node.find("vtk")) scene.outputs.vtk = parse_vtk(*vtk);
  if (auto checkpoint = node.find("checkpoint"))
    scene.outputs.checkpoint = parse_checkpoint(*checkpoint);
  check_output_paths(node, scene.outputs);
}

}  // namespace talus
