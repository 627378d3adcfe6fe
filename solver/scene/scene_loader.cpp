// The top level of a scene file: reading it, its scalar settings, and the sections in order.
#include "solver/scene/scene_loader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "solver/contact/time_step_advisor.hpp"
#include "solver/io/input_files.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_sections.hpp"

namespace talus {
namespace {

const std::vector<std::string> kTopLevelKeys = {
    "time",          "seed",      "backend", "precision", "skin",
    "deterministic", "reorder",   "domain",  "materials", "material_pairs",
    "templates",     "particles", "walls",   "effects",   "outputs"};

const std::string kTimeStep = "a positive number in s, or auto";

// `step: auto` is resolved once the whole scene is read (resolve_auto_step).
void parse_time(const SceneNode& node, Scene& scene) {
  node.keys({"step", "end"}, "time: a map with keys step, end (in s, or step: auto)");
  const SceneNode step = node.at("step", kTimeStep + " (the time step)");
  scene.time_step_source = step.ref();
  scene.time_step_auto = step.text(kTimeStep) == "auto";
  if (!scene.time_step_auto)
    scene.time_step = step.number(kTimeStep, [](double v) { return v > 0; });
  const SceneNode end = node.at("end", "a positive number in s (the end time)");
  scene.end_time = end.positive("s");
  if (!scene.time_step_auto && scene.time_step > scene.end_time)
    step.fail_expected("a time step in s no longer than the end time");
  if (!scene.time_step_auto) {
    const std::string problem = step_count_problem(scene.end_time, scene.time_step);
    if (!problem.empty()) end.fail(problem);
  }
}

// `time: {step: auto}`: a safe fraction of the critical step of the time-step advisor
// (contact/time_step_advisor.hpp), so that both solvers run the same number.
void resolve_auto_step(Scene& scene) {
  const SourceRef& at = scene.time_step_source;
  const TimeStepAdvice advice = advise_time_step(scene);
  if (!std::isfinite(advice.recommended_step))
    throw SceneError(at.file, at.line, at.column, at.key,
                     "auto needs a critical time step, and nothing limits the step here: " +
                         advice.limit + "; write the time step in s");
  scene.time_step = advice.recommended_step;
  if (scene.time_step > scene.end_time) {
    throw SceneError(
        at.file, at.line, at.column, at.key,
        fmt::format("auto gives {:.3g} s ({:.2g} of the critical step {:.3g} s), "
                    "longer than time.end {:.3g} s; write a longer end or the time "
                    "step in s",
                    scene.time_step, kAutoStepFraction, advice.critical_step, scene.end_time));
  }
  const std::string problem = step_count_problem(scene.end_time, scene.time_step);
  if (!problem.empty())
    throw SceneError(at.file, at.line, at.column, at.key, "with step: auto, " + problem);
}

// The bounding box of a region (a cylinder's: its two discs' boxes together).
Box region_bounds(const Region& r) {
  Box b;
  if (r.kind == RegionKind::box) {
    b.min = r.box_min, b.max = r.box_max;
    return b;
  }
  const Vec3d top = r.base + r.axis * r.height;
  // A disc of radius R about axis a reaches R sqrt(1 - a_k^2) along axis k.
  const Vec3d reach(r.radius * std::sqrt(std::max(0.0, 1 - r.axis.x * r.axis.x)),
                    r.radius * std::sqrt(std::max(0.0, 1 - r.axis.y * r.axis.y)),
                    r.radius * std::sqrt(std::max(0.0, 1 - r.axis.z * r.axis.z)));
  b.min = Vec3d(std::min(r.base.x, top.x), std::min(r.base.y, top.y), std::min(r.base.z, top.z)) -
          reach;
  b.max = Vec3d(std::max(r.base.x, top.x), std::max(r.base.y, top.y), std::max(r.base.z, top.z)) +
          reach;
  return b;
}

// `domain: {min: [x, y, z], max: [x, y, z]}`, read after the particles: every explicit particle
// and every lattice, fill and feed region must lie inside it, or the run would start by removing
// what the scene asked for.
void parse_domain(const SceneNode& node, Scene& scene) {
  node.keys({"min", "max"}, "domain: a map with keys min, max (corners of a box, m)");
  Box box;
  box.min = node.at("min", "[x, y, z], the lowest corner in m").vec3("[x, y, z] in m");
  const SceneNode max = node.at("max", "[x, y, z], the highest corner in m");
  box.max = max.vec3("[x, y, z] in m");
  if (!(box.min.x < box.max.x && box.min.y < box.max.y && box.min.z < box.max.z))
    max.fail_expected("a corner above min on every axis");
  if (!box.bounded()) max.fail_expected("finite corners");
  scene.domain = box;
  scene.domain_source = node.ref();
  const auto outside = [&](const SourceRef& at, const std::string& what) {
    throw SceneError(at.file, at.line, at.column, at.key,
                     what + " lies (partly) outside the domain box written at " +
                         scene.domain_source.where() + "; its particles would be removed at once");
  };
  for (const ParticleState& p : scene.particles)
    if (!box.contains(p.position)) outside(p.source, "the particle's position");
  const auto check_region = [&](const Region& r, const SourceRef& at, const char* what) {
    const Box b = region_bounds(r);
    if (!(box.contains(b.min) && b.max.x <= box.max.x && b.max.y <= box.max.y &&
          b.max.z <= box.max.z))
      outside(at, what);
  };
  for (const LatticeRequest& l : scene.lattices) check_region(l.region, l.source, "the lattice");
  for (const RandomFillRequest& f : scene.random_fills)
    check_region(f.region, f.source, "the random fill's region");
  for (const FeedRequest& f : scene.feeds) check_region(f.region, f.source, "the feed's region");
}

}  // namespace

Scene parse_scene(const std::string& yaml_text, const std::string& file_name,
                  const std::string& directory) {
  YAML::Node document;
  try {
    document = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw SceneError(file_name, e.mark.line + 1, e.mark.column + 1, "",
                     "YAML syntax error: " + e.msg);
  }
  const SceneSource source{file_name, directory};
  const YAML::Mark start = document.IsNull() ? YAML::Mark() : document.Mark();
  const SceneNode root(document, "", start, &source);
  root.keys(kTopLevelKeys, "a scene: a map with keys " + join_options(kTopLevelKeys));

  Scene scene;
  scene.file = file_name;
  scene.directory = directory;
  parse_time(root.at("time", "a map with keys step, end (in s)"), scene);
  if (auto seed = root.find("seed"))
    scene.seed = std::uint64_t(seed->integer(kSeedExpected, 0, kMaxSeed));
  if (auto backend = root.find("backend")) {
    const std::string name = backend->choice({"auto", "cpu", "cuda"}, "a backend");
    scene.backend =
        name == "auto" ? Backend::automatic : (name == "cpu" ? Backend::cpu : Backend::cuda);
  }
  if (auto precision = root.find("precision"))
    scene.precision = precision->choice({"double", "float"}, "a precision") == "float"
                          ? Precision::float32
                          : Precision::float64;
  if (auto skin = root.find("skin")) scene.skin = skin->non_negative("m");
  if (auto deterministic = root.find("deterministic"))
    scene.deterministic = deterministic->boolean();
  parse_materials(root.at("materials", "a map from material names to their properties"), scene);
  if (auto pairs = root.find("material_pairs")) parse_material_pairs(*pairs, scene);
  parse_templates(root.at("templates", "a map from template names to shapes and materials"), scene);
  const std::optional<SceneNode> walls = root.find("walls");
  if (walls) parse_walls(*walls, scene);
  const std::optional<SceneNode> effects = root.find("effects");
  parse_effects(effects ? *effects : SceneNode(YAML::Node(), "effects", start, &source), scene);
  if (!scene.walls.empty() && !scene.effects.contact)
    walls->fail(
        "walls act through contacts, and the scene has no contact model "
        "(effects.contact)");
  parse_particles(root.at("particles", "a list of particle entries"), scene);
  scene.effects.feed = !scene.feeds.empty();
  if (auto domain = root.find("domain")) parse_domain(*domain, scene);
  if (auto reorder = root.find("reorder")) scene.reorder = reorder->boolean();
  if (auto outputs = root.find("outputs")) parse_outputs(*outputs, scene);
  if (scene.time_step_auto) resolve_auto_step(scene);
  return scene;
}

Scene load_scene(const std::string& path) {
  std::string text;
  try {
    text = read_input_file(path);
  } catch (const InputFileError& e) {
    throw SceneError(path, 0, 0, "", "the scene file " + e.problem());
  }
  std::string directory = std::filesystem::path(path).parent_path().string();
  return parse_scene(text, path, directory.empty() ? "." : directory);
}

}  // namespace talus
