// Loading and checking YAML scene files (format: docs/scenes.md).
#pragma once

#include <stdexcept>
#include <string>

#include "solver/scene/scene.hpp"

namespace talus {

// A scene that cannot be loaded. what() is "<file>:<line>:<column>: <key>: <message>", e.g.
// "scene.yaml:12:5: materials.glass.density: expected a positive number in kg/m^3, got 'abc'";
// the line and column are left out when unknown (a file that cannot be opened), the key when
// the error is not about one key (a YAML syntax error).
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, int line, int column, std::string key, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 1-based; 0 when unknown
  int column() const { return column_; }
  const std::string& key() const { return key_; }          // e.g. "materials.glass.density"
  const std::string& message() const { return message_; }  // what was wrong or expected

 private:
  std::string file_;
  int line_, column_;
  std::string key_, message_;
};

// Reads and checks the scene file at `path`; relative mesh paths in it are resolved against
// the file's directory. Builds the particle templates (make_shape) and reads wall meshes.
// Throws SceneError.
Scene load_scene(const std::string& path);

// The same from YAML text: `file_name` names it in messages, `directory` resolves relative paths.
Scene parse_scene(const std::string& yaml_text, const std::string& file_name,
                  const std::string& directory);

}  // namespace talus
