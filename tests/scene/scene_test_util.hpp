// Helpers shared by the scene tests: the data folder, file reading, and catching SceneError.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "solver/scene/scene_loader.hpp"

namespace talus {

inline std::string scene_data_dir() {
  return std::string(TALUS_SOURCE_DIR) + "/tests/scene/data";
}

inline std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// `text` with its one occurrence of `from` replaced by `to` (the test fails if `from` is not
// found exactly once, so that a mutated scene cannot silently stay valid).
inline std::string replaced(const std::string& text, const std::string& from,
                            const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the scene";
  if (at == std::string::npos) return text;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "'" << from << "' found twice";
  return text.substr(0, at) + to + text.substr(at + from.size());
}

// The SceneError that parsing `text` (named errors.yaml, paths relative to the data folder)
// throws; a test failure and an empty error when it throws none.
inline SceneError scene_error(const std::string& text) {
  try {
    parse_scene(text, "errors.yaml", scene_data_dir());
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "no SceneError for:\n" << text;
  return SceneError("", 0, 0, "", "<no error>");
}

// A small valid scene that the error tests edit. Positions in messages are 1-based lines and
// columns of this text.
inline const std::string kValidScene = R"(time: {step: 1.0e-5, end: 0.1}
seed: 3
materials:
  glass:
    density: 2500
    youngs_modulus: 6.0e7
    poisson_ratio: 0.23
    friction: 0.4
    restitution: 0.8
templates:
  grain:
    shape: dodecahedron:0.01
    material: glass
particles:
  - explicit:
      - {template: grain, position: [0, 0, 0.05]}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
)";

// The error of kValidScene with `from` replaced by `to`.
inline SceneError error_with(const std::string& from, const std::string& to) {
  return scene_error(replaced(kValidScene, from, to));
}

}  // namespace talus
