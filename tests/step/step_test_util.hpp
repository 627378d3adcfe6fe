// Helpers of the production-step tests: scenes from YAML text and a temporary directory.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "solver/scene/scene_loader.hpp"

namespace talus_test {

// A fresh directory under the system's temporary directory, removed at the end of the test.
class StepTempDir {
 public:
  StepTempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "talus_step_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "mkdtemp failed";
    path_ = pattern;
  }
  ~StepTempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline talus::Scene scene_from(const std::string& yaml) {
  return talus::parse_scene(yaml, "test.yaml", ".");
}

}  // namespace talus_test
