#include "solver/io/json.hpp"

#include <stdexcept>

namespace talus {

namespace {

constexpr std::size_t kLineWidth = 100;

bool is_container(const Json& value) {
  return value.is_object() || value.is_array();
}

// A number, string, boolean or null as JSON; bytes that are not UTF-8 (a path from an old file
// system, say) become U+FFFD rather than an exception.
std::string scalar_text(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// The one-line text of a value that holds no object below its top (or "" when it does): used
// for arrays and for the small records inside them.
std::string one_line(const Json& value) {
  if (!is_container(value)) return scalar_text(value);
  std::string text(1, value.is_object() ? '{' : '[');
  bool first = true;
  for (auto it = value.begin(); it != value.end(); ++it) {
    if (it->is_object()) return "";
    const std::string element = one_line(*it);
    if (element.empty()) return "";
    if (!first) text += ", ";
    first = false;
    if (value.is_object()) text += scalar_text(Json(it.key())) + ": ";
    text += element;
  }
  return text + (value.is_object() ? '}' : ']');
}

// Appends `value` whose first character goes at column `column`, its closing bracket at `indent`.
void append(const Json& value, std::size_t indent, std::size_t column, bool in_array,
            std::string& out) {
  if (!is_container(value)) {
    out += scalar_text(value);
    return;
  }
  if (value.empty()) {
    out += value.is_object() ? "{}" : "[]";
    return;
  }
  if (value.is_array() || in_array) {
    const std::string line = one_line(value);
    if (!line.empty() && column + line.size() <= kLineWidth) {
      out += line;
      return;
    }
  }
  const std::string inner(indent + 2, ' ');
  out += value.is_object() ? "{\n" : "[\n";
  bool first = true;
  for (auto it = value.begin(); it != value.end(); ++it) {
    if (!first) out += ",\n";
    first = false;
    out += inner;
    std::size_t at = inner.size();
    if (value.is_object()) {
      const std::string key = scalar_text(Json(it.key())) + ": ";
      out += key;
      at += key.size();
    }
    append(*it, indent + 2, at, value.is_array(), out);
  }
  out += '\n' + std::string(indent, ' ') + (value.is_object() ? '}' : ']');
}

}  // namespace

void to_json(Json& json, const Vec3d& v) {
  json = Json::array({v.x, v.y, v.z});
}

void to_json(Json& json, const Quatd& q) {
  json = Json::array({q.w, q.x, q.y, q.z});
}

std::string json_text(const Json& document) {
  std::string out;
  append(document, 0, 0, false, out);
  return out + '\n';
}

Json parse_json(const std::string& text, const std::string& where) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line 3, column 5: ...".
    std::string what = error.what();
    const std::size_t tag = what.find("] ");
    if (tag != std::string::npos) what = what.substr(tag + 2);
    throw std::runtime_error(where + ": not valid JSON: " + what);
  }
}

}  // namespace talus
