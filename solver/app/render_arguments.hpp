// `talus render`'s options, parsed apart from rendering so that every bad option is a
// UsageError naming it and what was expected, whether or not OpenCV is built in.
#pragma once

#include <string>
#include <vector>

#include "solver/render/render_run.hpp"

namespace talus {

struct RenderArguments {
  RenderSettings settings;  // run_directory: the one operand
  bool quiet = false;       // --quiet: no line per picture on stderr
};

// The operands after `render`: DIR and options in any order (`--name value` or `--name=value`):
// --view x|-x|y|-y|z|-z, --color normal|velocity|id, --width N, --height N, --every K, --last,
// --output DIR, --scene FILE, --fit all|particles, --max-speed V, --no-label, --quiet.
RenderArguments parse_render_arguments(const std::vector<std::string>& operands);

}  // namespace talus
