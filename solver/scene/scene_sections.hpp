// The parsers of the scene file's sections (internal to solver/scene/), in the order
// scene_loader.cpp calls them: each may rely on the sections before it.
#pragma once

#include <string>

#include "solver/scene/scene.hpp"
#include "solver/scene/scene_reader.hpp"

namespace talus {

// A seed (the scene's, an entry's): SceneNode::integer names the limit, kMaxSeed.
inline const std::string kSeedExpected = "a non-negative integer";

void parse_materials(const SceneNode& node, Scene& scene);
void parse_material_pairs(const SceneNode& node, Scene& scene);
void parse_templates(const SceneNode& node, Scene& scene);
void parse_walls(const SceneNode& node, Scene& scene);
void parse_effects(const SceneNode& node, Scene& scene);
void parse_particles(const SceneNode& node, Scene& scene);
void parse_outputs(const SceneNode& node, Scene& scene);

// A reference by name: the index, or "unknown material 'x'; defined: ..." at the node.
int material_reference(const SceneNode& node, const Scene& scene);
int template_reference(const SceneNode& node, const Scene& scene);

// `path` as given when absolute, else relative to `directory`.
std::string resolve_path(const std::string& path, const std::string& directory);
// A mesh file that is a regular file, or "mesh file '<resolved>' does not exist" (or "is a
// directory, not a regular file", "is a FIFO ...", see input_file_problem) at the node.
void check_mesh_file_readable(const SceneNode& node, const std::string& resolved_path);

}  // namespace talus
