#include "solver/scene/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "solver/scene/scene_limits.hpp"

namespace talus {
namespace {

std::string compose(const std::string& file, int line, int column, const std::string& key,
                    const std::string& message) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line) + ":" + std::to_string(column);
  return where + ": " + (key.empty() ? "" : key + ": ") + message;
}

std::string child_key(const std::string& parent, const std::string& name) {
  return parent.empty() ? shown_text(name) : parent + "." + shown_text(name);
}

// yaml-cpp marks are 0-based, -1 when unknown; messages count from 1.
int line_of(const YAML::Mark& mark) {
  return mark.line >= 0 ? mark.line + 1 : 0;
}
int column_of(const YAML::Mark& mark) {
  return mark.line >= 0 ? mark.column + 1 : 0;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A whole scalar as a finite double (strtod accepts a prefix; we do not). strtod sets ERANGE on
// underflow too: a subnormal result is still the number written (to fewer digits) and is kept,
// a 0 from a nonzero literal ("1e-400") is not the number written and is refused.
bool parse_double(const std::string& text, double& value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) return false;
  return errno != ERANGE || value != 0;
}

// Bytes in the UTF-8 sequence that starts at text[i], 0 if none does (a stray or overlong byte,
// a sequence cut short).
std::size_t utf8_length(const std::string& text, std::size_t i) {
  const unsigned char c = static_cast<unsigned char>(text[i]);
  if (c < 0x80) return 1;
  const std::size_t n = c >= 0xf5 ? 0 : c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 ? 2 : 0;
  if (n == 0 || i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return 0;
  return n;
}

// The first scalar of `node`'s items that is a number a double cannot hold, as " (x: infinite)"
// with `axes` naming the items; empty if none.
std::string component_problem(const YAML::Node& node, const char* axes) {
  for (std::size_t i = 0; node.IsSequence() && i < node.size() && axes[i]; ++i) {
    if (!node[i].IsScalar()) continue;
    const std::string problem = number_problem(node[i].Scalar());
    if (!problem.empty()) return std::string(" (") + axes[i] + ": " + problem + ")";
  }
  return "";
}

int edit_distance(const std::string& a, const std::string& b) {
  std::vector<int> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = int(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = int(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const int substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& options) {
  const std::optional<std::string> close = closest_option(word, options);
  return close ? " (did you mean '" + *close + "'?)" : "";
}

}  // namespace

SceneError::SceneError(std::string file, int line, int column, std::string key, std::string message)
    : std::runtime_error(compose(file, line, column, key, message)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      key_(std::move(key)),
      message_(std::move(message)) {}

namespace {

// `text` as shown_text shows it; `cut`: whether it was cut short.
std::string shown_prefix(const std::string& text, bool& cut) {
  // Enough for any name or number a scene needs; a longer one is shown by its start.
  constexpr std::size_t kShownLength = 60;
  std::string out;
  std::size_t characters = 0, i = 0;
  for (; i < text.size() && characters < kShownLength; ++characters) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const std::size_t n = utf8_length(text, i);
    if (c < 0x20 || c == 0x7f || n == 0) {
      out += fmt::format("\\x{:02X}", c);
      ++i;
    } else {
      out.append(text, i, n);
      i += n;
    }
  }
  cut = i < text.size();
  return cut ? out + "..." : out;
}

}  // namespace

std::string shown_text(const std::string& text) {
  bool cut = false;
  return shown_prefix(text, cut);
}

std::string quoted(const std::string& text) {
  bool cut = false;
  const std::string shown = "'" + shown_prefix(text, cut) + "'";
  return cut ? shown + " (" + std::to_string(text.size()) + " bytes)" : shown;
}

std::string number_problem(const std::string& text) {
  const std::string word = lower(text);
  // YAML's own spellings, which strtod does not read.
  if (word == ".nan") return "not a number";
  if (word == ".inf" || word == "+.inf" || word == "-.inf") return "infinite";
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return "";
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return "";
  if (std::isnan(value)) return "not a number";
  if (std::isinf(value))
    return errno == ERANGE ? "beyond the range of a double, about 1.8e308" : "infinite";
  if (errno == ERANGE && value == 0) return "below the smallest double, so it would read as 0";
  return "";
}

std::string join_options(const std::vector<std::string>& options) {
  std::string joined;
  for (std::size_t i = 0; i < options.size(); ++i) joined += (i ? ", " : "") + options[i];
  return joined;
}

std::optional<std::string> closest_option(const std::string& word,
                                          const std::vector<std::string>& options) {
  std::optional<std::string> best;
  int best_distance = 0;
  for (const std::string& option : options) {
    const int d = edit_distance(lower(word), lower(option));
    if (!best || d < best_distance) best = option, best_distance = d;
  }
  // Up to two edits, and fewer than half the word: "densty" -> "density", not "x" -> "y".
  if (best && best_distance <= 2 && 2 * best_distance < int(word.size())) return best;
  return std::nullopt;
}

SceneNode::SceneNode(YAML::Node node, std::string key, YAML::Mark mark, const SceneSource* source)
    : node_(std::move(node)), key_(std::move(key)), mark_(mark), source_(source) {}

SourceRef SceneNode::ref() const {
  return {source_->file, line_of(mark_), column_of(mark_), key_};
}

void SceneNode::fail(const std::string& message) const {
  throw SceneError(source_->file, line_of(mark_), column_of(mark_), key_, message);
}

void SceneNode::fail_expected(const std::string& expected) const {
  fail("expected " + expected + ", got " + describe());
}

std::string SceneNode::describe() const {
  if (node_.IsNull()) return "nothing";
  if (node_.IsScalar()) return quoted(node_.Scalar());
  if (node_.IsMap()) return node_.size() == 0 ? "an empty map {}" : "a map";
  // A short list of scalars is shown as written, anything else by its kind.
  std::string shown = "[";
  for (std::size_t i = 0; i < node_.size(); ++i) {
    if (!node_[i].IsScalar() || node_.size() > 8) return "a list";
    shown += (i ? ", " : "") + shown_text(node_[i].Scalar());
  }
  return shown + "]";
}

void SceneNode::keys(const std::vector<std::string>& allowed, const std::string& expected,
                     const std::string& noun) const {
  if (!node_.IsMap()) fail_expected(expected);
  std::vector<std::pair<std::string, int>> seen;  // key, line
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const YAML::Mark mark = it->first.Mark();
    if (!it->first.IsScalar())
      throw SceneError(source_->file, line_of(mark), column_of(mark), key_,
                       "expected a plain key, one of " + join_options(allowed) +
                           ", got a key that is a " + (it->first.IsMap() ? "map" : "list"));
    const std::string name = it->first.Scalar();
    const std::string path = child_key(key_, name);
    // yaml-cpp does not expand YAML 1.1's merge key; an alias of a whole map (key: *name) works.
    if (name == "<<")
      throw SceneError(source_->file, line_of(mark), column_of(mark), key_,
                       "expected keys among " + join_options(allowed) +
                           ", got a merge key '<<', which talus does not expand; write the "
                           "keys out, or use an alias of the whole map");
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw SceneError(source_->file, line_of(mark), column_of(mark), path,
                       "unknown " + noun + "; expected one of " + join_options(allowed) +
                           did_you_mean(name, allowed));
    for (const auto& [other, line] : seen)
      if (other == name)
        throw SceneError(source_->file, line_of(mark), column_of(mark), path,
                         "duplicate key; first given on line " + std::to_string(line));
    seen.emplace_back(name, line_of(mark));
  }
}

std::optional<SceneNode> SceneNode::find(const std::string& name) const {
  if (!node_.IsMap()) fail_expected("a map");
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar() || it->first.Scalar() != name) continue;
    const YAML::Mark mark = it->second.IsNull() ? it->first.Mark() : it->second.Mark();
    return SceneNode(it->second, child_key(key_, name), mark, source_);
  }
  return std::nullopt;
}

SceneNode SceneNode::at(const std::string& name, const std::string& expected) const {
  std::optional<SceneNode> found = find(name);
  if (!found)
    throw SceneError(source_->file, line_of(mark_), column_of(mark_), child_key(key_, name),
                     "missing required key; expected " + expected);
  return *found;
}

std::vector<std::pair<std::string, SceneNode>> SceneNode::entries(
    const std::string& expected) const {
  if (!node_.IsMap()) fail_expected(expected);
  std::vector<std::pair<std::string, SceneNode>> result;
  std::vector<int> key_lines;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const YAML::Mark key_mark = it->first.Mark();
    if (!it->first.IsScalar())
      throw SceneError(source_->file, line_of(key_mark), column_of(key_mark), key_,
                       "expected a name as the key, got a map or list");
    const std::string name = it->first.Scalar();
    for (std::size_t i = 0; i < result.size(); ++i)
      if (result[i].first == name)
        throw SceneError(source_->file, line_of(key_mark), column_of(key_mark),
                         child_key(key_, name),
                         "duplicate name; first given on line " + std::to_string(key_lines[i]));
    key_lines.push_back(line_of(key_mark));
    result.emplace_back(name,
                        SceneNode(it->second, child_key(key_, name),
                                  it->second.IsNull() ? key_mark : it->second.Mark(), source_));
  }
  return result;
}

std::vector<SceneNode> SceneNode::items(const std::string& expected) const {
  if (!node_.IsSequence()) fail_expected(expected);
  std::vector<SceneNode> result;
  for (std::size_t i = 0; i < node_.size(); ++i) {
    const YAML::Node item = node_[i];
    result.emplace_back(item, key_ + "[" + std::to_string(i) + "]",
                        item.IsNull() ? mark_ : item.Mark(), source_);
  }
  return result;
}

std::pair<std::string, SceneNode> SceneNode::one_of(const std::vector<std::string>& kinds,
                                                    const std::string& what) const {
  const std::string expected = what + ": a map of one key, one of " + join_options(kinds);
  if (node_.IsMap() && node_.size() > 1) {
    std::vector<std::string> given;
    for (auto it = node_.begin(); it != node_.end(); ++it)
      given.push_back(it->first.IsScalar() ? shown_text(it->first.Scalar()) : "?");
    fail("expected " + expected + ", got a map of " + std::to_string(node_.size()) + " keys (" +
         join_options(given) + ")");
  }
  if (!node_.IsMap() || node_.size() != 1) fail_expected(expected);
  keys(kinds, what, what + " kind");
  const std::string kind = node_.begin()->first.Scalar();
  return {kind, *find(kind)};
}

double SceneNode::number(const std::string& expected, const std::function<bool(double)>& ok) const {
  double value = 0;
  if (!node_.IsScalar() || !parse_double(node_.Scalar(), value) || (ok && !ok(value))) {
    const std::string problem = node_.IsScalar() ? number_problem(node_.Scalar()) : "";
    fail("expected " + expected + ", got " + describe() +
         (problem.empty() ? "" : " (" + problem + ")"));
  }
  return value;
}

double SceneNode::positive(const std::string& unit) const {
  return number("a positive number in " + unit, [](double v) { return v > 0; });
}

double SceneNode::non_negative(const std::string& unit) const {
  return number("a non-negative number in " + unit, [](double v) { return v >= 0; });
}

long long SceneNode::integer(const std::string& expected, long long min, long long max) const {
  if (!node_.IsScalar()) fail_expected(expected);
  const std::string& text = node_.Scalar();
  // An integer beyond the limit gets a message naming the limit, whether or not it fits a long
  // long ("1e30", "99999999999999999999" alike).
  const auto above_limit = [&] {
    fail("expected " + expected + ", at most " + describe_limit(max) + ", got " + quoted(text));
  };
  char* end = nullptr;
  errno = 0;
  long long value = std::strtoll(text.c_str(), &end, 10);
  const bool whole = !text.empty() && end == text.c_str() + text.size();
  if (whole && errno == ERANGE && value > 0) above_limit();
  if (!whole || errno != 0) {
    // Also "1e5": an integral double below 2^53, where doubles hold integers exactly.
    double as_double = 0;
    if (!parse_double(text, as_double) || as_double != std::floor(as_double))
      fail_expected(expected);
    if (as_double > double(max)) above_limit();
    if (std::fabs(as_double) > 9007199254740992.0) fail_expected(expected);
    value = static_cast<long long>(as_double);
  }
  if (value > max) above_limit();
  if (value < min) fail_expected(expected);
  return value;
}

bool SceneNode::boolean() const {
  if (node_.IsScalar()) {
    const std::string word = lower(node_.Scalar());
    if (word == "true" || word == "yes" || word == "on") return true;
    if (word == "false" || word == "no" || word == "off") return false;
  }
  fail_expected("true or false");
}

std::string SceneNode::text(const std::string& expected) const {
  if (!node_.IsScalar() || node_.Scalar().empty()) fail_expected(expected);
  return node_.Scalar();
}

std::string SceneNode::name(const std::string& what) const {
  const std::string expected =
      what + ": a name of letters, digits, '_' or '-', starting with a letter";
  const std::string value = text(expected);
  bool ok = std::isalpha(static_cast<unsigned char>(value[0])) != 0;
  for (char c : value)
    ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
  if (!ok) fail_expected(expected);
  return value;
}

std::string SceneNode::choice(const std::vector<std::string>& options,
                              const std::string& what) const {
  const std::string expected = what + ", one of " + join_options(options);
  const std::string value = text(expected);
  if (std::find(options.begin(), options.end(), value) == options.end())
    fail("expected " + expected + ", got " + quoted(value) + did_you_mean(value, options));
  return value;
}

Vec3d SceneNode::vec3(const std::string& expected) const {
  Vec3d v;
  double component = 0;
  bool ok = node_.IsSequence() && node_.size() == 3;
  for (std::size_t i = 0; ok && i < 3; ++i) {
    ok = node_[i].IsScalar() && parse_double(node_[i].Scalar(), component);
    v[int(i)] = component;
  }
  if (!ok) fail("expected " + expected + ", got " + describe() + component_problem(node_, "xyz"));
  return v;
}

Vec3d SceneNode::direction(const std::string& what) const {
  const std::string expected = what + ", a nonzero vector [x, y, z]";
  const Vec3d v = vec3(expected);
  // Scaled by its largest component first, so that a huge vector ([1e300, 1e300, 0]) does not
  // overflow its norm and a tiny one does not underflow it.
  const double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(largest > 0)) fail_expected(expected);
  const Vec3d scaled = v / largest;
  return scaled / norm(scaled);
}

Quatd SceneNode::orientation() const {
  const std::string expected =
      "an orientation: a quaternion [w, x, y, z] or {axis: [x, y, z], degrees: angle}";
  if (node_.IsMap()) {
    keys({"axis", "degrees"}, expected);
    const Vec3d axis = at("axis", "a rotation axis [x, y, z]").direction("a rotation axis");
    const double degrees = at("degrees", "an angle in degrees").number("an angle in degrees");
    return Quatd::from_axis_angle(axis, degrees * M_PI / 180);
  }
  double q[4] = {0, 0, 0, 0};
  bool ok = node_.IsSequence() && node_.size() == 4;
  for (std::size_t i = 0; ok && i < 4; ++i)
    ok = node_[i].IsScalar() && parse_double(node_[i].Scalar(), q[i]);
  if (!ok) fail("expected " + expected + ", got " + describe() + component_problem(node_, "wxyz"));
  const Quatd quaternion(q[0], q[1], q[2], q[3]);
  const double length = quaternion.norm();
  // The components are finite; their squares may still overflow or underflow, and then there is
  // no finite nonzero norm to normalise by.
  if (!std::isfinite(length))
    fail("expected " + expected + ", got " + describe() +
         " (its norm overflows a double, too large to normalise; write it with smaller "
         "components)");
  if (!(length > 0)) {
    if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0)
      fail("expected " + expected + ", got " + describe() + " (a zero quaternion is no rotation)");
    fail("expected " + expected + ", got " + describe() +
         " (its norm underflows to 0 in a double, too small to normalise; write it with larger "
         "components)");
  }
  return quaternion.normalized();
}

}  // namespace talus
