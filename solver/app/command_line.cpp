#include "solver/app/command_line.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "solver/app/arguments.hpp"

namespace talus {

namespace {

const char* const kDescription =
    "talus: discrete element simulation of convex polyhedral and spherical particles on the GPU "
    "or the host, with a serial reference solver beside it.";

const char* const kShapes =
    "A, B     a built-in shape 'name:size' or an .obj/.stl file ('path' or 'path:scale')\n"
    "         name: tetrahedron, cube, octahedron, dodecahedron, icosahedron, corn, mineral\n"
    "               (size = circumscribed-sphere diameter, m); cuboid:a,b,c (sides, m);\n"
    "               cylinder:D,L[,N] (diameter, length, N sides; m)\n";

const char* const kPoses =
    "POSE     x,y,z,qw,qx,qy,qz: centroid position (m) and orientation quaternion\n"
    "         (body -> world, normalised by talus), e.g. 0,0,0,1,0,0,0\n";

const char* const kOverlapPrints =
    "overlap prints: status, volume (m^3), normal (S/|S|, from A to B), area (|S|, m^2),\n"
    "vector_area (S), point (overlap centroid), chebyshev_depth (inradius of the overlap),\n"
    "thin_slab (touching because the overlap is a slab too thin to measure: no force),\n"
    "depth, simple_normal, simple_point (BLAZE-DEM simple contact), gjk_intersecting.\n";

// The synopsis of each command, for the top-level help and the usage line of an error.
const std::pair<const char*, const char*> kSynopses[] = {
    {"run", "talus run [options] [SCENE.yaml]"},
    {"resume", "talus run --resume DIR [options]"},
    {"render", "talus render [options] DIR"},
    {"validate", "talus validate [options] [CASE...]"},
    {"accuracy", "talus accuracy [options]"},
    {"overlap", "talus overlap A POSE_A B POSE_B"},
    {"shape", "talus shape A"},
    {"help", "talus help | --help | -h | COMMAND --help"}};

// The values of --backend (run, validate, accuracy).
const std::pair<const char*, Backend> kBackends[] = {
    {"auto", Backend::automatic}, {"cpu", Backend::cpu}, {"cuda", Backend::cuda}};

// The most host threads --threads takes: beyond any machine's cores, below what makes starting
// them fail (a billion threads' stacks are more than any memory).
constexpr int kMaxThreads = 1024;

// Every option is read as text and checked here, so that one message style covers them all:
// "--threads '0': expected a whole number of at least 1".
struct RunText {
  std::vector<std::string> scenes;
  std::string solver, backend, precision, output, threads, end, resume, stop_after;
  bool quiet = false, allow_unstable_step = false, overwrite = false;
};

struct ValidateText {
  std::vector<std::string> cases;
  std::string output, cases_directory, backend;
  bool full = false, quiet = false;
};

struct AccuracyText {
  std::string scenes, knobs, output, backend;
  bool quick = false, quiet = false;
};

struct RenderText {
  std::vector<std::string> directories;
  std::string view, color, width, height, every, output, scene, fit, max_speed;
  bool last = false, no_label = false, outline = false, quiet = false;
};

// Adds a text option whose value is checked after parsing.
CLI::Option* text_option(CLI::App* app, const char* name, std::string& value, const char* what,
                         const char* help) {
  return app->add_option(name, value, help)->type_name(what);
}

double positive_number(const std::string& option, const std::string& text, const char* unit) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  // A decimal number only: strtod would also take leading spaces, hexadecimal and "infinity".
  const bool decimal = text.find_first_not_of("0123456789+-.eE") == std::string::npos;
  if (!decimal || text.empty() || end != text.c_str() + text.size() || !std::isfinite(value) ||
      value <= 0)
    throw UsageError(option + " '" + shown(text) + "': expected a positive " + unit);
  return value;
}

// Options given on the command line that are not the command's: CLI11 leaves them in
// remaining() when extras are allowed, and the message is ours.
void refuse_extras(const CLI::App* app, const std::string& command, const char* expected) {
  const std::vector<std::string> extras = app->remaining();
  if (!extras.empty())
    throw UsageError("unknown option '" + shown(extras.front()) + "' for " + command +
                     "; expected " + expected);
}

RunArguments run_arguments(const CLI::App* app, const RunText& t) {
  static const std::pair<const char*, SolverKind> kSolvers[] = {
      {"production", SolverKind::production}, {"reference", SolverKind::reference}};
  static const std::pair<const char*, Precision> kPrecisions[] = {{"double", Precision::float64},
                                                                  {"float", Precision::float32}};
  refuse_extras(app, "run",
                "--solver, --backend, --precision, --output, --threads, --end, --resume, "
                "--stop-after, --quiet, --allow-unstable-step, --overwrite");
  const auto given = [&](const char* name) { return app->count(name) > 0; };
  RunArguments parsed;
  if (t.scenes.size() > 1)
    throw UsageError("run expects one scene file, got '" + shown(t.scenes[0]) + "' and '" +
                     shown(t.scenes[1]) + "'");
  if (!t.scenes.empty()) {
    // An empty path must not stand for "no scene": that runs the built-in one.
    if (t.scenes[0].empty()) throw UsageError("run expects a scene file, got an empty path ''");
    parsed.scene_path = t.scenes[0];
  }
  if (given("--solver")) parsed.solver = choose("--solver", t.solver, kSolvers);
  if (given("--backend")) parsed.backend = choose("--backend", t.backend, kBackends);
  if (given("--precision")) parsed.precision = choose("--precision", t.precision, kPrecisions);
  if (given("--output")) {
    if (t.output.empty()) throw UsageError("--output expects a directory");
    parsed.output_root = t.output;
  }
  if (given("--threads"))
    parsed.threads = parse_positive_count("--threads", t.threads, kMaxThreads);
  if (given("--end")) parsed.end_time = positive_number("--end", t.end, "time in s");
  if (given("--stop-after"))
    parsed.stop_after_seconds = positive_number("--stop-after", t.stop_after, "number of seconds");
  if (given("--resume")) {
    if (t.resume.empty())
      throw UsageError("--resume expects a checkpoint directory or a checkpoint file");
    parsed.resume_directory = t.resume;
  }
  if (parsed.stop_after_seconds && parsed.solver == SolverKind::reference)
    throw UsageError(
        "--stop-after stops the production solver with a checkpoint; the reference solver "
        "writes none: drop --stop-after or --solver reference");
  parsed.quiet = t.quiet;
  parsed.allow_unstable_step = t.allow_unstable_step;
  parsed.overwrite = t.overwrite;
  if (!parsed.resume_directory.empty()) {
    if (parsed.overwrite)
      throw UsageError("--resume continues the run's own outputs; drop --overwrite");
    if (!t.scenes.empty())
      throw UsageError("--resume continues the run its checkpoint names; drop the scene file '" +
                       shown(parsed.scene_path) + "'");
    for (const char* fixed : {"--solver", "--precision", "--output"}) {
      if (given(fixed))
        throw UsageError(std::string("--resume continues the run as it was set up; drop ") + fixed +
                         " (the checkpoint fixes the solver, precision and output " + "directory)");
    }
  }
  return parsed;
}

RenderArguments render_arguments(const CLI::App* app, const RenderText& t) {
  static const std::pair<const char*, ColorMode> kColors[] = {
      {"normal", ColorMode::normal}, {"velocity", ColorMode::velocity}, {"id", ColorMode::id}};
  static const std::pair<const char*, std::string> kViews[] = {
      {"x", "x"}, {"-x", "-x"}, {"y", "y"}, {"-y", "-y"}, {"z", "z"}, {"-z", "-z"}};
  static const std::pair<const char*, bool> kFits[] = {{"all", true}, {"particles", false}};
  refuse_extras(app, "render",
                "--view, --color, --width, --height, --every, --last, --output, --scene, --fit, "
                "--max-speed, --outline, --no-label, --quiet");
  const auto given = [&](const char* name) { return app->count(name) > 0; };
  RenderArguments parsed;
  RenderSettings& s = parsed.settings;
  if (t.directories.empty())
    throw UsageError("render expects a run directory (the trajectory directory talus run wrote)");
  if (t.directories.size() > 1)
    throw UsageError("render expects one run directory, got '" + shown(t.directories[0]) +
                     "' and '" + shown(t.directories[1]) + "'");
  if (t.directories[0].empty())
    throw UsageError("render expects a run directory, got an empty path ''");
  s.run_directory = t.directories[0];
  if (given("--view")) s.view = choose("--view", t.view, kViews);
  if (given("--color")) s.color = choose("--color", t.color, kColors);
  constexpr int kMaxSide = 16384;  // px: 16384^2 RGB is 800 MB, beyond what a frame needs
  if (given("--width")) s.width = parse_positive_count("--width", t.width, kMaxSide);
  if (given("--height")) s.height = parse_positive_count("--height", t.height, kMaxSide);
  if (given("--every")) s.every = parse_positive_count("--every", t.every);
  if (given("--fit")) s.fit_walls = choose("--fit", t.fit, kFits);
  if (given("--output")) {
    if (t.output.empty()) throw UsageError("--output expects a path");
    s.output_directory = t.output;
  }
  if (given("--scene")) {
    if (t.scene.empty()) throw UsageError("--scene expects a path");
    s.scene_file = t.scene;
  }
  if (given("--max-speed"))
    s.max_speed = positive_number("--max-speed", t.max_speed, "speed in m/s");
  s.last_only = t.last;
  s.label = !t.no_label;
  s.outline = t.outline;
  parsed.quiet = t.quiet;
  if (s.width <= 2 * s.margin || s.height <= 2 * s.margin)
    throw UsageError("--width and --height: expected more than " + std::to_string(2 * s.margin) +
                     " px (twice the margin)");
  return parsed;
}

ValidateArguments validate_arguments(const CLI::App* app, const ValidateText& t) {
  refuse_extras(app, "validate", "--full, --output, --backend, --cases, --quiet");
  const auto given = [&](const char* name) { return app->count(name) > 0; };
  ValidateArguments parsed;
  for (const std::string& name : t.cases) {
    if (name.empty()) throw UsageError("validate expects case names, got an empty one ''");
  }
  parsed.cases = t.cases;
  parsed.full = t.full;
  parsed.quiet = t.quiet;
  if (given("--output")) {
    if (t.output.empty()) throw UsageError("--output expects a directory");
    parsed.output = t.output;
  }
  if (given("--cases")) {
    if (t.cases_directory.empty()) throw UsageError("--cases expects a directory");
    parsed.cases_directory = t.cases_directory;
  }
  if (given("--backend")) parsed.backend = choose("--backend", t.backend, kBackends);
  return parsed;
}

// "a,b" as its words; an empty word is refused.
std::vector<std::string> comma_list(const char* option, const std::string& text) {
  std::vector<std::string> words;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string word = text.substr(start, comma - start);
    if (word.empty())
      throw UsageError(std::string(option) + " '" + shown(text) +
                       "': expected names separated by commas, got an empty one");
    words.push_back(word);
    if (comma == std::string::npos) return words;
    start = comma + 1;
  }
}

AccuracyArguments accuracy_arguments(const CLI::App* app, const AccuracyText& t) {
  refuse_extras(app, "accuracy", "--scenes, --knobs, --quick, --output, --backend, --quiet");
  const auto given = [&](const char* name) { return app->count(name) > 0; };
  AccuracyArguments parsed;
  if (given("--scenes")) parsed.scenes = comma_list("--scenes", t.scenes);
  if (given("--knobs")) parsed.knobs = comma_list("--knobs", t.knobs);
  parsed.quick = t.quick;
  parsed.quiet = t.quiet;
  if (given("--output")) {
    if (t.output.empty()) throw UsageError("--output expects a directory");
    parsed.output = t.output;
  }
  if (given("--backend")) parsed.backend = choose("--backend", t.backend, kBackends);
  return parsed;
}

// The operands of overlap and shape, which may begin with '-' (a negative coordinate): CLI11
// leaves every word it does not know in remaining(), in order.
std::vector<std::string> operands(const CLI::App* app, const std::string& command,
                                  std::size_t count, const char* names) {
  std::vector<std::string> words = app->remaining();
  if (words.size() != count)
    throw UsageError(command + " expects " + std::to_string(count) + " argument" +
                     (count > 1 ? "s " : " ") + names + ", got " + std::to_string(words.size()));
  return words;
}

// The synopses, one a line under "usage:".
std::string synopses() {
  std::string text = "usage:\n";
  for (const auto& [name, synopsis] : kSynopses) {
    (void)name;
    text += std::string("  ") + synopsis + "\n";
  }
  return text;
}

std::string top_footer() {
  return synopses() +
         "With no command, talus runs the built-in scene: 63 dodecahedra poured into a 10 cm\n"
         "cylinder (the method paper's section 3.3), outputs in talus-default/.\n"
         "'talus COMMAND --help' describes a command's options. Scenes: docs/scenes.md.\n\n" +
         kShapes + kPoses;
}

}  // namespace

ParsedCommand parse_command_line(const std::vector<std::string>& arguments) {
  ParsedCommand command;
  if (arguments.empty()) {
    command.bare = true;
    return command;
  }
  CLI::App app(kDescription, "talus");
  app.require_subcommand(0, 1);
  app.allow_extras();

  CLI::App* help = app.add_subcommand("help", "this text; 'talus help COMMAND': a command's");
  help->allow_extras();

  RunText r;
  CLI::App* run = app.add_subcommand("run", "run a scene; its summary as JSON");
  run->footer(
      "Runs SCENE.yaml (docs/scenes.md) and prints its summary as JSON, progress on stderr.\n"
      "Without SCENE.yaml: the built-in scene, 63 dodecahedra poured into a 10 cm cylinder\n"
      "(paper section 3.3), outputs in talus-default/, its final bed height and a picture.");
  run->allow_extras();
  run->add_option("SCENE.yaml", r.scenes, "the scene file (none: the built-in scene)")
      ->type_name("");
  text_option(run, "--solver", r.solver, "production|reference",
              "which solver steps the scene (default production; reference: the serial "
              "CGAL/Eigen oracle)");
  text_option(run, "--backend", r.backend, "auto|cpu|cuda", "overrides the scene's backend");
  text_option(run, "--precision", r.precision, "double|float", "overrides the scene's precision");
  text_option(run, "--output", r.output, "DIR", "relative output paths of the scene go inside DIR");
  text_option(
      run, "--threads", r.threads, "N",
      "the host backend's threads (1 <= N <= 1024; default: all cores, or OMP_NUM_THREADS)");
  text_option(run, "--end", r.end, "T", "stop at T seconds instead of the scene's end time");
  text_option(run, "--resume", r.resume, "DIR|FILE",
              "continue the run from the newest checkpoint in DIR (outputs.checkpoint), or from "
              "the checkpoint FILE, instead of a scene file; takes --backend, --threads, --end, "
              "--stop-after, --quiet and --allow-unstable-step only");
  text_option(run, "--stop-after", r.stop_after, "S",
              "stop after S seconds of wall-clock time, at a step boundary, with a checkpoint "
              "(as Ctrl-C does; exit status 75): runs longer than a sitting");
  run->add_flag("--quiet", r.quiet, "no progress lines on stderr");
  run->add_flag("--overwrite", r.overwrite,
                "remove an earlier run's outputs from the output directory first (a new run "
                "into a directory that holds them is refused otherwise)");
  run->add_flag("--allow-unstable-step", r.allow_unstable_step,
                "run a time step above the critical step that talus estimates (refused "
                "otherwise; docs/contact.md)");

  RenderText d;
  CLI::App* render = app.add_subcommand("render", "draw a run's frames to PNG");
  render->footer(
      "DIR: the run's trajectory directory, with run.json. The pictures, their projection and\n"
      "each particle's pixel position go to DIR/render/ unless --output says otherwise\n"
      "(docs/scenes.md, \"Pictures\").");
  render->allow_extras();
  render->add_option("DIR", d.directories, "the run's trajectory directory")->type_name("");
  text_option(render, "--view", d.view, "x|-x|y|-y|z|-z",
              "the direction the camera looks along (default y)");
  text_option(render, "--color", d.color, "normal|velocity|id",
              "faces shaded by normal, speed colours, or one flat colour per particle id "
              "(default normal)");
  text_option(render, "--width", d.width, "N", "image width in pixels (default 800)");
  text_option(render, "--height", d.height, "N", "image height in pixels (default 800)");
  text_option(render, "--every", d.every, "K", "every K-th frame (the last always)");
  render->add_flag("--last", d.last, "only the last frame");
  text_option(render, "--fit", d.fit, "all|particles",
              "scale to fit particles and walls (default) or particles only");
  text_option(render, "--max-speed", d.max_speed, "V",
              "m/s drawn red with --color velocity (default: the fastest particle of the "
              "frames)");
  text_option(render, "--scene", d.scene, "FILE",
              "the scene, when run.json's path does not lead to it");
  text_option(render, "--output", d.output, "DIR", "where the pictures go");
  render->add_flag(
      "--outline", d.outline,
      "each particle's silhouette as a dark line (occluding contours, as in a photograph)");
  render->add_flag("--no-label", d.no_label, "no time label on the pictures");
  render->add_flag("--quiet", d.quiet, "no line per picture on stderr");

  ValidateText v;
  CLI::App* validate =
      app.add_subcommand("validate", "run the validation cases; their results as JSON");
  validate->footer(
      "Runs the published cases of validation/ (validation/README.md) on the production\n"
      "solver: each case's quantities against its expected.yaml. Writes\n"
      "validation-results.json, validation-summary.md and each case's files into the output\n"
      "directory; prints the results' JSON. Exit status 1 when a case fails.");
  validate->allow_extras();
  validate->add_option("CASE", v.cases, "the cases to run (none: all)")->type_name("");
  validate->add_flag("--full", v.full,
                     "the full versions (finer sweeps, more steps: for the GPU) instead of the "
                     "small ones CI runs");
  text_option(validate, "--output", v.output, "DIR",
              "where the results go (default talus-validation)");
  text_option(validate, "--backend", v.backend, "auto|cpu|cuda",
              "the production solver's backend (default auto: the GPU where one is usable)");
  text_option(validate, "--cases", v.cases_directory, "DIR",
              "the folder that holds the case folders (default: this source tree's validation/)");
  validate->add_flag("--quiet", v.quiet, "no line per case on stderr");

  AccuracyText a;
  CLI::App* accuracy = app.add_subcommand(
      "accuracy", "the accuracy-against-time study: each fidelity knob's error and cost");
  accuracy->footer(
      "Sets each fidelity knob (contact law, shape and wall-mesh resolution, precision, time\n"
      "step, neighbour-list skin) in turn on the same scenes (the section 3.1 impact, the\n"
      "section 3.3 packing, a quasi-2D drum) and writes each setting's error against its\n"
      "reference and its wall time per simulated second to accuracy.csv in the output\n"
      "directory (experiments/accuracy/README.md); prints a summary as JSON.");
  accuracy->allow_extras();
  text_option(accuracy, "--scenes", a.scenes, "impact,packing,drum",
              "the scenes to run (default all)");
  text_option(accuracy, "--knobs", a.knobs, "LIST",
              "the knobs to set, of contact_law, shape_resolution, wall_mesh, precision, "
              "time_step, skin (default all)");
  accuracy->add_flag("--quick", a.quick,
                     "CI's size: fewer particles, shorter runs, fewer settings");
  text_option(accuracy, "--output", a.output, "DIR",
              "where accuracy.csv and the scenes go (default talus-accuracy)");
  text_option(accuracy, "--backend", a.backend, "auto|cpu|cuda",
              "the production solver's backend (default auto: the GPU where one is usable)");
  accuracy->add_flag("--quiet", a.quiet, "no line per run on stderr");

  CLI::App* overlap = app.add_subcommand("overlap", "the overlap of two posed polyhedra, as JSON");
  overlap->allow_extras();
  overlap->footer(
      "talus overlap A POSE_A B POSE_B: the exact overlap (paper section 2.3), the BLAZE-DEM\n"
      "simple contact and the GJK verdict (paper Algorithm I) side by side.\n\n" +
      std::string(kShapes) + kPoses + "\n" + kOverlapPrints);
  CLI::App* shape = app.add_subcommand("shape", "a shape template in its body frame, as JSON");
  shape->allow_extras();
  shape->footer("talus shape A: the template (paper section 2.1) built from A.\n\n" +
                std::string(kShapes));
  // Set last: a subcommand takes its parent's footer when it is added.
  app.footer(top_footer());

  // "--threads=" with nothing after '=': CLI11 would take the next argument as its value.
  for (const std::string& word : arguments) {
    if (word == "--") break;
    if (word.size() > 3 && word.rfind("--", 0) == 0 && word.back() == '=')
      throw UsageError(shown(word.substr(0, word.size() - 1)) + " expects a value, got '" +
                       shown(word) + "' with nothing after '='");
  }
  std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    command.kind = ParsedCommand::help;
    command.help_text = app.help();
    return command;
  } catch (const CLI::ArgumentMismatch& error) {
    // An option without its value: CLI11 says "--output: 1 required DIR missing".
    const std::string what = error.what();
    const std::size_t colon = what.find(": ");
    if (colon != std::string::npos && what.find(" required ", colon) != std::string::npos &&
        what.size() >= 8 && what.compare(what.size() - 8, 8, " missing") == 0)
      throw UsageError(what.substr(0, colon) + " expects a value");
    // An option given twice: "--output: At Most 1 required but received 2".
    const std::size_t received = what.find(" but received ");
    if (colon != std::string::npos && what.find(": At Most 1 required", colon) == colon &&
        received != std::string::npos)
      throw UsageError(what.substr(0, colon) + " is given " + what.substr(received + 14) +
                       " times; give it once");
    throw UsageError(what);
  } catch (const CLI::ConversionError& error) {
    // A flag given a value it does not take: "Could not convert: --quiet = maybe".
    const std::string what = error.what();
    const std::string prefix = "Could not convert: ";
    const std::size_t equals = what.find(" = ");
    if (what.rfind(prefix, 0) == 0 && equals != std::string::npos)
      throw UsageError(what.substr(prefix.size(), equals - prefix.size()) + " '" +
                       shown(what.substr(equals + 3)) +
                       "': a flag takes no value (or one of true, false, yes, no, 1, 0)");
    throw UsageError(what);
  } catch (const CLI::ParseError& error) {
    throw UsageError(error.what());  // CLI11's words, which name the argument
  }
  // A word before the command (CLI11 leaves it with talus itself): "talus -x run" must not run.
  const std::vector<std::string> before = app.remaining();
  if (!before.empty() && (*run || *render || *validate || *accuracy || *overlap || *shape))
    throw UsageError("unknown option '" + shown(before.front()) +
                     "' before the command; talus takes a command first and its options after "
                     "it (e.g. 'talus run --quiet SCENE.yaml')");
  if (*help) {
    command.kind = ParsedCommand::help;
    const std::vector<std::string> topic = help->remaining();
    CLI::App* about = nullptr;
    if (!topic.empty() && topic.front() != "help") {
      try {
        about = app.get_subcommand(topic.front());
      } catch (const CLI::OptionNotFound&) {
        throw UsageError("help '" + shown(topic.front()) +
                         "': expected one of run, render, validate, accuracy, overlap, shape");
      }
    }
    // app.help() would describe the `help` command itself, the one parsed.
    command.help_text =
        about ? about->help("talus")
              : app.get_formatter()->make_help(&app, "talus", CLI::AppFormatMode::Normal);
  } else if (*run) {
    command.kind = ParsedCommand::run;
    command.run_arguments = run_arguments(run, r);
  } else if (*render) {
    command.kind = ParsedCommand::render;
    command.render_arguments = render_arguments(render, d);
  } else if (*validate) {
    command.kind = ParsedCommand::validate;
    command.validate_arguments = validate_arguments(validate, v);
  } else if (*accuracy) {
    command.kind = ParsedCommand::accuracy;
    command.accuracy_arguments = accuracy_arguments(accuracy, a);
  } else if (*overlap) {
    command.kind = ParsedCommand::overlap;
    command.operands = operands(overlap, "overlap", 4, "A POSE_A B POSE_B");
  } else if (*shape) {
    command.kind = ParsedCommand::shape;
    command.operands = operands(shape, "shape", 1, "A");
  } else {
    const std::vector<std::string> words = app.remaining();
    const std::string word = words.empty() ? arguments.front() : words.front();
    // An option before any command: talus itself takes none but --help.
    if (word.size() > 1 && word[0] == '-')
      throw UsageError("unknown option '" + shown(word) +
                       "'; expected a command first (run, render, validate, accuracy, overlap, "
                       "shape or help), or "
                       "--help");
    throw UsageError("unknown command '" + shown(word) +
                     "'; expected run, render, validate, accuracy, overlap, shape or help");
  }
  return command;
}

std::string usage_line(const std::vector<std::string>& arguments) {
  const std::string first = arguments.empty() ? "" : arguments.front();
  for (const auto& [name, synopsis] : kSynopses) {
    if (first == name && first != "help")
      return std::string("usage: ") + synopsis + " ('talus " + first +
             " --help' lists the options)\n";
  }
  // "usage: " begins the first line, as for a command ("usage:" alone would read as a title).
  std::string text = synopses();
  return "usage: talus COMMAND ...: one of\n" + text.substr(text.find('\n') + 1);
}

}  // namespace talus
