// The top level of a scene file: reading it, its scalar settings, and the sections in order.
#include "solver/scene/scene_loader.hpp"

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "solver/contact/time_step_advisor.hpp"
#include "solver/io/input_files.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_sections.hpp"

namespace talus {
namespace {

const std::vector<std::string> kTopLevelKeys = {
    "time",    "seed",    "backend",   "precision",      "skin",      "deterministic",
    "reorder", "domain",  "materials", "material_pairs", "templates", "particles",
    "walls",   "effects", "outputs",   "decomposition"};

const std::string kTimeStep = "a positive number in s, or auto";

// `step: auto` is resolved once the whole scene is read (resolve_auto_step).
void parse_time(const SceneNode& node, Scene& scene) {
  node.keys({"step", "end"}, "time: a map with keys step, end (in s, or step: auto)");
  const SceneNode step = node.at("step", kTimeStep + " (the time step)");
  scene.time_step_source = step.ref();
  scene.time_step_auto = step.text(kTimeStep) == "auto";
  if (!scene.time_step_auto)
    scene.time_step = step.number(kTimeStep, [](double v) { return v > 0; });
  const SceneNode end = node.at("end", "a positive number in s (the end time)");
  scene.end_time = end.positive("s");
  if (!scene.time_step_auto && scene.time_step > scene.end_time)
    step.fail_expected("a time step in s no longer than the end time");
  if (!scene.time_step_auto) {
    const std::string problem = step_count_problem(scene.end_time, scene.time_step);
    if (!problem.empty()) end.fail(problem);
  }
}

// `time: {step: auto}`: a safe fraction of the critical step of the time-step advisor
// (contact/time_step_advisor.hpp), so that both solvers run the same number.
void resolve_auto_step(Scene& scene) {
  const SourceRef& at = scene.time_step_source;
  const TimeStepAdvice advice = advise_time_step(scene);
  if (!std::isfinite(advice.recommended_step))
    throw SceneError(at.file, at.line, at.column, at.key,
                     "auto needs a critical time step, and nothing limits the step here: " +
                         advice.limit + "; write the time step in s");
  scene.time_step = advice.recommended_step;
  if (scene.time_step > scene.end_time) {
    throw SceneError(
        at.file, at.line, at.column, at.key,
        fmt::format("auto gives {:.3g} s ({:.2g} of the critical step {:.3g} s), "
                    "longer than time.end {:.3g} s; write a longer end or the time "
                    "step in s",
                    scene.time_step, kAutoStepFraction, advice.critical_step, scene.end_time));
  }
  const std::string problem = step_count_problem(scene.end_time, scene.time_step);
  if (!problem.empty())
    throw SceneError(at.file, at.line, at.column, at.key, "with step: auto, " + problem);
}

// The bounding box of a region (a cylinder's: its two discs' boxes together).
Box region_bounds(const Region& r) {
  Box b;
  if (r.kind == RegionKind::box) {
    b.min = r.box_min, b.max = r.box_max;
    return b;
  }
  const Vec3d top = r.base + r.axis * r.height;
  // A disc of radius R about axis a reaches R sqrt(1 - a_k^2) along axis k.
  const Vec3d reach(r.radius * std::sqrt(std::max(0.0, 1 - r.axis.x * r.axis.x)),
                    r.radius * std::sqrt(std::max(0.0, 1 - r.axis.y * r.axis.y)),
                    r.radius * std::sqrt(std::max(0.0, 1 - r.axis.z * r.axis.z)));
  b.min = Vec3d(std::min(r.base.x, top.x), std::min(r.base.y, top.y), std::min(r.base.z, top.z)) -
          reach;
  b.max = Vec3d(std::max(r.base.x, top.x), std::max(r.base.y, top.y), std::max(r.base.z, top.z)) +
          reach;
  return b;
}

// `domain: {min: [x, y, z], max: [x, y, z]}`, read after the particles: every explicit particle
// and every lattice, fill and feed region must lie inside it, or the run would start by removing
// what the scene asked for.
void parse_domain(const SceneNode& node, Scene& scene) {
  node.keys({"min", "max"}, "domain: a map with keys min, max (corners of a box, m)");
  Box box;
  box.min = node.at("min", "[x, y, z], the lowest corner in m").vec3("[x, y, z] in m");
  const SceneNode max = node.at("max", "[x, y, z], the highest corner in m");
  box.max = max.vec3("[x, y, z] in m");
  if (!(box.min.x < box.max.x && box.min.y < box.max.y && box.min.z < box.max.z))
    max.fail_expected("a corner above min on every axis");
  if (!box.bounded()) max.fail_expected("finite corners");
  scene.domain = box;
  scene.domain_source = node.ref();
  const auto outside = [&](const SourceRef& at, const std::string& what) {
    throw SceneError(at.file, at.line, at.column, at.key,
                     what + " lies (partly) outside the domain box written at " +
                         scene.domain_source.where() + "; its particles would be removed at once");
  };
  for (const ParticleState& p : scene.particles)
    if (!box.contains(p.position)) outside(p.source, "the particle's position");
  const auto check_region = [&](const Region& r, const SourceRef& at, const char* what) {
    const Box b = region_bounds(r);
    if (!(box.contains(b.min) && b.max.x <= box.max.x && b.max.y <= box.max.y &&
          b.max.z <= box.max.z))
      outside(at, what);
  };
  for (const LatticeRequest& l : scene.lattices) check_region(l.region, l.source, "the lattice");
  for (const RandomFillRequest& f : scene.random_fills)
    check_region(f.region, f.source, "the random fill's region");
  for (const FeedRequest& f : scene.feeds) check_region(f.region, f.source, "the feed's region");
}

// The lines of `text` (without their '\n').
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// YAML is text: a NUL or another control character (a binary file, a paste gone wrong) or a byte
// that is not UTF-8 is refused at its place, before the parser turns it into a misleading syntax
// error or a value that would be echoed raw.
void check_scene_bytes(const std::string& text, const std::string& file) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < text.size(); ++column) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      ++line, column = 0, ++i;
      continue;
    }
    if (c == 0)
      throw SceneError(file, line, column, "",
                       "a NUL byte; a scene file is YAML text (is this a binary file?)");
    if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f)
      throw SceneError(file, line, column, "",
                       fmt::format("a control character (byte 0x{:02X}); a scene file is YAML "
                                   "text",
                                   c));
    std::size_t n = c < 0x80    ? 1
                    : c >= 0xf5 ? 0
                    : c >= 0xf0 ? 4
                    : c >= 0xe0 ? 3
                    : c >= 0xc2 ? 2
                                : 0;
    if (n > 1 && i + n > text.size()) n = 0;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) n = 0;
    if (n == 0)
      throw SceneError(file, line, column, "",
                       fmt::format("a byte that is not UTF-8 (0x{:02X}); a scene file is UTF-8 "
                                   "text",
                                   c));
    i += n;
  }
}

bool is_document_marker(const std::string& line, const char* marker) {
  return line.compare(0, 3, marker) == 0 &&
         (line.size() == 3 || line[3] == ' ' || line[3] == '\t' || line[3] == '\r');
}

bool is_content(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t\r");
  return first != std::string::npos && line[first] != '#' && line[0] != '%' &&
         !is_document_marker(line, "---") && !is_document_marker(line, "...");
}

// The line (from 1) where the second YAML document of `text` begins: its "---" or the "..."
// that ended the first; 0 if no such line is found.
int second_document_line(const std::vector<std::string>& lines) {
  bool content = false, started = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const bool start = is_document_marker(lines[i], "---");
    if ((start && (content || started)) || (content && is_document_marker(lines[i], "...")))
      return int(i) + 1;
    started = started || start;
    content = content || is_content(lines[i]);
  }
  return 0;
}

// The start of each YAML document in `text` (at most three are read: the first, a second that is
// an error, and one more to tell a parser that does not move on). yaml-cpp's LoadAll never ends on
// some inputs (a lone ',' or '&a&,': the parser reports document after document at one place), so
// the documents are counted with a handler that builds nothing, the calls bounded.
struct DocumentStarts : YAML::EventHandler {
  std::vector<YAML::Mark> starts;
  void OnDocumentStart(const YAML::Mark& mark) override { starts.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};
std::vector<YAML::Mark> document_starts(const std::string& text) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStarts handler;
  for (int k = 0; k < 3 && parser.HandleNextDocument(handler); ++k) {
  }
  return handler.starts;
}

// Where a flow collection or a quoted string still open at `end` (a byte offset) was opened:
// the bracket or quote and its 0-based line and column; {0, -1, -1} if none is open. Quotes and
// comments are skipped, so brackets inside them do not count.
struct Opened {
  char what = 0;
  int line = -1, column = -1;
};
// Whether a scalar may begin at text[i]: only at the start of a line or after ':', '-', '?',
// '[', '{' or ',' (and spaces) does a quote open a quoted string; elsewhere ("O'Brien", "a 'b")
// it is part of a plain one.
bool starts_scalar(const std::string& text, std::size_t i) {
  while (i > 0 && (text[i - 1] == ' ' || text[i - 1] == '\t')) --i;
  return i == 0 || std::string(":-?[{,\n").find(text[i - 1]) != std::string::npos;
}

Opened open_at(const std::string& text, std::size_t end) {
  std::vector<Opened> stack;
  Opened quote;
  int line = 0, column = 0;
  for (std::size_t i = 0; i < end && i < text.size(); ++i, ++column) {
    const char c = text[i];
    if (c == '\n') {
      ++line, column = -1;
      continue;
    }
    if (quote.what) {
      if (c == '\\' && quote.what == '"')
        ++i, ++column;
      else if (c == quote.what)
        quote.what = 0;
      continue;
    }
    if (c == '#' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '\n')) {
      while (i + 1 < end && text[i + 1] != '\n') ++i;
    } else if ((c == '"' || c == '\'') && starts_scalar(text, i)) {
      quote = {c, line, column};
    } else if (c == '{' || c == '[') {
      stack.push_back({c, line, column});
    } else if ((c == '}' || c == ']') && !stack.empty()) {
      stack.pop_back();
    }
  }
  if (quote.what) return quote;
  return stack.empty() ? Opened() : stack.back();
}

// yaml-cpp's message for a syntax error, with the likely cause where its words do not say it.
// Returns the message and sets `at` to the place to name (the parser's, or where an unclosed
// bracket or quote opened).
std::string syntax_error(const YAML::ParserException& e, const std::vector<std::string>& lines,
                         const std::string& text, YAML::Mark& at) {
  at = e.mark;
  const Opened open = open_at(text, e.mark.pos >= 0 ? std::size_t(e.mark.pos) : text.size());
  const Opened at_end = open_at(text, text.size());
  // A string open where the parser stopped and still open at the end of the file (one open only
  // at the error is a string the error lies in: a bad escape).
  if ((open.what == '"' || open.what == '\'') && at_end.what == open.what &&
      at_end.line == open.line && at_end.column == open.column) {
    at.line = open.line, at.column = open.column;
    return std::string("invalid YAML: the quoted string that starts here has no closing ") +
           open.what;
  }
  if (open.what && e.msg.find("flow not found") != std::string::npos) {
    at.line = open.line, at.column = open.column;
    return std::string("invalid YAML: this '") + open.what + "' has no matching '" +
           (open.what == '{' ? '}' : ']') + "'";
  }
  const std::string line =
      e.mark.line >= 0 && std::size_t(e.mark.line) < lines.size() ? lines[e.mark.line] : "";
  const std::string indent = line.substr(0, line.find_first_not_of(" \t"));
  if (indent.find('\t') != std::string::npos)
    return "invalid YAML: a tab in the indentation; YAML indents with spaces only";
  // YAML limits a key written without '?' to 1024 characters; yaml-cpp says "illegal map value".
  const std::size_t colon = line.find(':');
  if (colon != std::string::npos && colon > 1024 && line.find_first_of("{[\"'", 0) > colon) {
    at.column = int(line.find_first_not_of(' '));
    return "invalid YAML: a key of " + std::to_string(colon - std::size_t(at.column)) +
           " characters; YAML allows at most 1024";
  }
  // "*name" where the anchor "&name" is missing: say which name.
  if (e.msg.find("anchor is not defined") != std::string::npos && e.mark.column >= 0 &&
      std::size_t(e.mark.column) < line.size() && line[e.mark.column] == '*') {
    const std::size_t end = line.find_first_of(" ,]}\r", e.mark.column);
    const std::string name =
        line.substr(e.mark.column + 1, end == std::string::npos ? end : end - e.mark.column - 1);
    return "invalid YAML: the alias *" + shown_text(name) + " names no anchor &" +
           shown_text(name) + " written before it";
  }
  if (e.msg == "end of map not found")
    return "invalid YAML: end of map not found; the indentation of this line or the one "
           "before it does not match the keys above";
  return "invalid YAML: " + e.msg;
}

}  // namespace

Scene parse_scene(const std::string& yaml_text, const std::string& file_name,
                  const std::string& directory) {
  check_scene_bytes(yaml_text, file_name);
  const std::vector<std::string> lines = lines_of(yaml_text);
  YAML::Node document;
  std::vector<YAML::Mark> starts;
  try {
    document = YAML::Load(yaml_text);
    starts = document_starts(yaml_text);
  } catch (const YAML::ParserException& e) {
    YAML::Mark at;
    const std::string message = syntax_error(e, lines, yaml_text, at);
    throw SceneError(file_name, at.line + 1, at.column + 1, "", message);
  }
  const std::string expected_scene = "a scene: a map with keys " + join_options(kTopLevelKeys);
  // A parser that reports a second document where the first began (or before) is stuck on a
  // character it cannot read past.
  for (std::size_t k = 1; k < starts.size(); ++k) {
    if (starts[k].pos <= starts[k - 1].pos) {
      const YAML::Mark& at = starts[k];
      const std::size_t pos = static_cast<std::size_t>(std::max(at.pos, 0));
      const std::string what =
          pos < yaml_text.size() ? "'" + shown_input(yaml_text.substr(pos, 1)) + "'" : "the end";
      throw SceneError(file_name, at.line + 1, at.column + 1, "",
                       "invalid YAML: the parser cannot read past " + what +
                           " here (a ',' outside brackets, or an anchor without a node?)");
    }
  }
  // A second document would be ignored, and what the user wrote there lost without a word.
  if (starts.size() > 1) {
    int line = second_document_line(lines);
    if (line == 0 && starts[1].line >= 0) line = starts[1].line + 1;
    throw SceneError(file_name, line, 1, "",
                     "expected one YAML document, got a second one beginning here; a scene "
                     "file is one map, and talus would ignore the second document");
  }
  if (std::none_of(lines.begin(), lines.end(), is_content)) {
    const bool blank = yaml_text.find_first_not_of(" \t\r\n") == std::string::npos;
    throw SceneError(
        file_name, 1, 1, "",
        "expected " + expected_scene + ", got " + (blank ? "an empty file" : "only comments"));
  }
  // yaml-cpp takes a quoted string that is never closed to the end of the file without a word.
  const Opened open = open_at(yaml_text, yaml_text.size());
  if (open.what == '"' || open.what == '\'')
    throw SceneError(file_name, open.line + 1, open.column + 1, "",
                     std::string("invalid YAML: the quoted string that starts here has no "
                                 "closing ") +
                         open.what);
  const SceneSource source{file_name, directory};
  const YAML::Mark start = document.IsNull() ? YAML::Mark() : document.Mark();
  const SceneNode root(document, "", start, &source);
  root.keys(kTopLevelKeys, expected_scene);

  Scene scene;
  scene.file = file_name;
  scene.directory = directory;
  parse_time(root.at("time", "a map with keys step, end (in s)"), scene);
  if (auto seed = root.find("seed"))
    scene.seed = std::uint64_t(seed->integer(kSeedExpected, 0, kMaxSeed));
  if (auto backend = root.find("backend")) {
    const std::string name = backend->choice({"auto", "cpu", "cuda"}, "a backend");
    scene.backend =
        name == "auto" ? Backend::automatic : (name == "cpu" ? Backend::cpu : Backend::cuda);
  }
  if (auto precision = root.find("precision"))
    scene.precision = precision->choice({"double", "float"}, "a precision") == "float"
                          ? Precision::float32
                          : Precision::float64;
  if (auto skin = root.find("skin")) scene.skin = skin->non_negative("m");
  if (auto deterministic = root.find("deterministic"))
    scene.deterministic = deterministic->boolean();
  parse_materials(root.at("materials", "a map from material names to their properties"), scene);
  if (auto pairs = root.find("material_pairs")) parse_material_pairs(*pairs, scene);
  parse_templates(root.at("templates", "a map from template names to shapes and materials"), scene);
  const std::optional<SceneNode> walls = root.find("walls");
  if (walls) parse_walls(*walls, scene);
  const std::optional<SceneNode> effects = root.find("effects");
  parse_effects(effects ? *effects : SceneNode(YAML::Node(), "effects", start, &source), scene);
  if (!scene.walls.empty() && !scene.effects.contact)
    walls->fail(
        "walls act through contacts, and the scene has no contact model "
        "(effects.contact)");
  parse_particles(root.at("particles", "a list of particle entries"), scene);
  scene.effects.feed = !scene.feeds.empty();
  if (auto domain = root.find("domain")) parse_domain(*domain, scene);
  if (auto reorder = root.find("reorder")) scene.reorder = reorder->boolean();
  if (auto decomposition = root.find("decomposition")) {
    decomposition->keys({"rebalance"}, "decomposition: {rebalance: R}, R >= 1");
    if (auto rebalance = decomposition->find("rebalance"))
      scene.rebalance = rebalance->number(
          "a ratio >= 1 (the most particles on a rank over the "
          "mean at which the ranks' boxes are cut again)",
          [](double r) { return r >= 1; });
  }
  if (auto outputs = root.find("outputs")) parse_outputs(*outputs, scene);
  if (scene.time_step_auto) resolve_auto_step(scene);
  return scene;
}

Scene load_scene(const std::string& path) {
  std::string text;
  try {
    text = read_input_file(path);
  } catch (const InputFileError& e) {
    throw SceneError(path, 0, 0, "", "the scene file " + e.problem());
  }
  std::string directory = std::filesystem::path(path).parent_path().string();
  return parse_scene(text, path, directory.empty() ? "." : directory);
}

}  // namespace talus
