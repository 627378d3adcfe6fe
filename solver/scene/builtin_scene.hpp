// The built-in scene that `talus run` runs when given no scene file: the packing of 63
// dodecahedra poured into the 10 cm cylinder of the method paper's §3.3. Its YAML is
// validation/dodecahedron_packing/scene.yaml, compiled in (solver/CMakeLists.txt), so the
// command needs no file from the source tree.
#pragma once

#include <string>

namespace talus {

// The scene file's text, as in the source tree.
std::string builtin_scene_text();

// The name that messages and run.json give it when it is written out: "scene.yaml".
constexpr const char* kBuiltinSceneFileName = "scene.yaml";

// Where `talus run` with no scene writes its outputs when --output is not given (relative to the
// working directory).
constexpr const char* kBuiltinSceneOutput = "talus-default";

// The final fill height the paper reports for the experiment and its simulation (§3.3), m.
constexpr double kPaperBedHeight = 0.16;

}  // namespace talus
