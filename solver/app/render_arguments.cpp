#include "solver/app/render_arguments.hpp"

#include <cmath>

#include "solver/app/arguments.hpp"

namespace talus {

RenderArguments parse_render_arguments(const std::vector<std::string>& operands) {
  static const std::pair<const char*, ColorMode> kColors[] = {
      {"normal", ColorMode::normal}, {"velocity", ColorMode::velocity}, {"id", ColorMode::id}};
  static const std::pair<const char*, std::string> kViews[] = {
      {"x", "x"}, {"-x", "-x"}, {"y", "y"}, {"-y", "-y"}, {"z", "z"}, {"-z", "-z"}};
  static const std::pair<const char*, bool> kFits[] = {{"all", true}, {"particles", false}};
  static const char* const kValued[] = {"--view",   "--color", "--width", "--height",   "--every",
                                        "--output", "--scene", "--fit",   "--max-speed"};
  RenderArguments parsed;
  RenderSettings& s = parsed.settings;
  bool have_directory = false;
  for (std::size_t i = 0; i < operands.size(); ++i) {
    const std::string& word = operands[i];
    if (word == "--quiet" || word == "--last" || word == "--no-label") {
      if (word == "--quiet") parsed.quiet = true;
      if (word == "--last") s.last_only = true;
      if (word == "--no-label") s.label = false;
      continue;
    }
    if (word.rfind("--", 0) != 0) {
      if (have_directory)
        throw UsageError("render expects one run directory, got '" + s.run_directory + "' and '" +
                         word + "'");
      s.run_directory = word;
      have_directory = true;
      continue;
    }
    std::string name = word, value;
    const std::size_t equals = word.find('=');
    bool valued = false;
    for (const char* v : kValued) valued = valued || name == v;
    if (equals != std::string::npos) {
      name = word.substr(0, equals);
      value = word.substr(equals + 1);
    } else if (valued) {
      if (i + 1 >= operands.size()) throw UsageError(name + " expects a value");
      value = operands[++i];
    }
    if (name == "--view") {
      s.view = choose(name, value, kViews);
    } else if (name == "--color") {
      s.color = choose(name, value, kColors);
    } else if (name == "--width") {
      s.width = parse_positive_count(name, value);
    } else if (name == "--height") {
      s.height = parse_positive_count(name, value);
    } else if (name == "--every") {
      s.every = parse_positive_count(name, value);
    } else if (name == "--fit") {
      s.fit_walls = choose(name, value, kFits);
    } else if (name == "--output" || name == "--scene") {
      if (value.empty()) throw UsageError(name + " expects a path");
      (name == "--output" ? s.output_directory : s.scene_file) = value;
    } else if (name == "--max-speed") {
      char* end = nullptr;
      s.max_speed = std::strtod(value.c_str(), &end);
      if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(s.max_speed) ||
          s.max_speed <= 0)
        throw UsageError("--max-speed '" + value + "': expected a positive speed in m/s");
    } else {
      throw UsageError("unknown option '" + name +
                       "' for render; expected --view, --color, --width, --height, --every, "
                       "--last, --output, --scene, --fit, --max-speed, --no-label, --quiet");
    }
  }
  if (!have_directory)
    throw UsageError("render expects a run directory (the trajectory directory talus run wrote)");
  constexpr int kMaxSide = 16384;  // px: 16384^2 RGB is 800 MB, beyond what a frame needs
  if (s.width > kMaxSide || s.height > kMaxSide)
    throw UsageError("--width and --height: expected at most " + std::to_string(kMaxSide) + " px");
  if (s.width <= 2 * s.margin || s.height <= 2 * s.margin)
    throw UsageError("--width and --height: expected more than " + std::to_string(2 * s.margin) +
                     " px (twice the margin)");
  return parsed;
}

}  // namespace talus
