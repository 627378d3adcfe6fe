// `talus validate`'s and `talus accuracy`'s options, as the command line (command_line.hpp)
// gives them to validate_command and accuracy_command (commands.hpp).
#pragma once

#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

// Where `talus validate` writes when --output is not given.
inline constexpr const char* kValidationOutput = "talus-validation";

struct ValidateArguments {
  std::vector<std::string> cases;          // the operands; none: every case
  bool full = false;                       // --full: the full versions (the GPU's)
  bool quiet = false;                      // --quiet: no line per case on stderr
  std::string output = kValidationOutput;  // --output DIR
  std::string cases_directory;             // --cases DIR; empty: the source tree's validation/
  Backend backend = Backend::automatic;    // --backend
};

// Where `talus accuracy` writes when --output is not given.
inline constexpr const char* kAccuracyOutput = "talus-accuracy";

// `talus accuracy`'s options (experiments/accuracy/README.md).
struct AccuracyArguments {
  std::vector<std::string> scenes;       // --scenes a,b; empty: every scene
  std::vector<std::string> knobs;        // --knobs a,b; empty: every knob
  bool quick = false;                    // --quick: CI's size
  bool quiet = false;                    // --quiet: no line per run on stderr
  std::string output = kAccuracyOutput;  // --output DIR
  Backend backend = Backend::automatic;  // --backend
};

}  // namespace talus
