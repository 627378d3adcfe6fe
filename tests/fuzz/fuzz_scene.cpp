// libFuzzer target: the scene loader (solver/scene/scene_loader.hpp) on arbitrary YAML text.
// parse_scene is the loader's in-memory entry point (load_scene reads the file and calls it);
// relative mesh paths resolve against tests/scene/data, so the seeds' meshes are found. A
// SceneError (or another std::runtime_error the loader throws on purpose) is a correct answer;
// anything else — a crash, a sanitizer report, std::bad_alloc, std::out_of_range, a hang — is a
// bug.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "solver/scene/scene_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    talus::parse_scene(text, "fuzz.yaml", TALUS_SOURCE_DIR "/tests/scene/data");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
