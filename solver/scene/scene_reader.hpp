// Reading YAML nodes of a scene file with error reporting (internal to solver/scene/): every
// failure throws SceneError naming the file, the node's line and column, its key path
// ("materials.glass.density", "walls[2].hopper.height") and what was expected.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "solver/core/quat.hpp"
#include "solver/scene/scene.hpp"
#include "solver/scene/scene_loader.hpp"

namespace talus {

// The scene file being read: its name for messages, its directory for relative paths.
struct SceneSource {
  std::string file;
  std::string directory;
};

class SceneNode {
 public:
  // `mark`: where the node is written (for a null value, where its key is).
  SceneNode(YAML::Node node, std::string key, YAML::Mark mark, const SceneSource* source);

  const std::string& key() const { return key_; }
  const SceneSource& source() const { return *source_; }
  SourceRef ref() const;

  [[noreturn]] void fail(const std::string& message) const;
  // "expected <expected>, got <what is there>"
  [[noreturn]] void fail_expected(const std::string& expected) const;
  // 'abc', "nothing", "a list" or "a map": what the node holds, for messages.
  std::string describe() const;

  bool is_map() const { return node_.IsMap(); }
  bool is_list() const { return node_.IsSequence(); }
  bool is_null() const { return node_.IsNull(); }

  // Maps. `keys` checks that this is a map (else "expected <expected>") whose keys are all
  // among `allowed` (else "unknown <noun>; expected one of ..." at the key), each once.
  void keys(const std::vector<std::string>& allowed, const std::string& expected,
            const std::string& noun = "key") const;
  std::optional<SceneNode> find(const std::string& name) const;
  // A required key: "<key>.<name>: missing required key; expected <expected>" at this map.
  SceneNode at(const std::string& name, const std::string& expected) const;
  // Map entries in file order: the key as written and the value (key path "<key>.<name>").
  std::vector<std::pair<std::string, SceneNode>> entries(const std::string& expected) const;
  // List items (key path "<key>[i]").
  std::vector<SceneNode> items(const std::string& expected) const;
  // A map of exactly one key, one of `kinds` ({lattice: {...}}, {drum: {...}}).
  std::pair<std::string, SceneNode> one_of(const std::vector<std::string>& kinds,
                                           const std::string& what) const;

  // Scalars. `expected` says what and in which unit, as in "a positive number in kg/m^3";
  // a value that does not parse or fails `ok` gets "expected <expected>, got '<value>'".
  double number(const std::string& expected, const std::function<bool(double)>& ok = {}) const;
  double positive(const std::string& unit) const;      // > 0
  double non_negative(const std::string& unit) const;  // >= 0
  long long integer(const std::string& expected, long long min, long long max) const;
  bool boolean() const;
  std::string text(const std::string& expected) const;  // a non-empty scalar
  // A name others refer to: letters, digits, '_', '-', starting with a letter.
  std::string name(const std::string& what) const;
  std::string choice(const std::vector<std::string>& options, const std::string& what) const;
  Vec3d vec3(const std::string& expected) const;
  Vec3d direction(const std::string& what) const;  // nonzero, returned normalised
  // [w, x, y, z] (normalised here) or {axis: [x, y, z], degrees: angle}.
  Quatd orientation() const;

 private:
  YAML::Node node_;
  std::string key_;
  YAML::Mark mark_;
  const SceneSource* source_;
};

// A scalar of the file as a message shows it: control characters and bytes that are not UTF-8
// written as \xNN, and cut to kShownLength characters with "..." and the full length (a value
// or key of 100 kB is not echoed whole).
std::string shown_text(const std::string& text);
// shown_text in quotes: 'abc'.
std::string quoted(const std::string& text);
// What is wrong with a scalar that does not read as a finite double although it is written as a
// number: "not a number" (.nan), "infinite" (.inf), "beyond the range of a double" (1e400); empty
// for anything else (a word, a finite number).
std::string number_problem(const std::string& text);

// "a, b or c"
std::string join_options(const std::vector<std::string>& options);
// The option closest to `word` by edit distance, if close enough to be a likely typo.
std::optional<std::string> closest_option(const std::string& word,
                                          const std::vector<std::string>& options);

}  // namespace talus
