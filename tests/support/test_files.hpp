// Files and directories for the tests that write outputs: a fresh directory per test under the
// build tree (left there after the test, for a look when it fails), and whole-file reads and
// writes.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace talus_test {

// <build>/<group>/<name>, removed if present and created empty.
inline std::string fresh_test_directory(const std::string& group, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(TALUS_BINARY_DIR) / group / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writes `text` to `path` and returns the path.
inline std::string write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The names of the entries of `dir`, sorted (what a writer left there).
inline std::vector<std::string> file_names(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace talus_test
