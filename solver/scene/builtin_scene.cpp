#include "solver/scene/builtin_scene.hpp"

#include "talus/builtin_scene_text.hpp"

namespace talus {

std::string builtin_scene_text() {
  return kBuiltinSceneText;
}

}  // namespace talus
