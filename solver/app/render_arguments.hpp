// `talus render`'s options, as the command line (command_line.hpp) gives them to render_json,
// whether or not OpenCV is built in.
#pragma once

#include <string>

#include "solver/render/render_run.hpp"

namespace talus {

struct RenderArguments {
  RenderSettings settings;  // run_directory: the one operand
  bool quiet = false;       // --quiet: no line per picture on stderr
};

}  // namespace talus
