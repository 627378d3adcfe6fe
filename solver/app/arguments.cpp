#include "solver/app/arguments.hpp"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "solver/io/input_files.hpp"
#include "solver/shape/mesh_io.hpp"

namespace talus {

namespace {

std::string describe(const std::string& argument_name, const std::string& text) {
  return argument_name + " '" + shown_input(text, kShownSpecLimit) + "'";
}

// Splits on commas, keeping empty fields so that "1,,2" and a trailing comma are caught.
std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> fields(1);
  for (const char c : text) {
    if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

}  // namespace

Posed parse_pose(const std::string& argument_name, const std::string& text) {
  const std::string expected = "expected 7 comma-separated numbers x,y,z,qw,qx,qy,qz";
  const std::vector<std::string> fields = split_commas(text);
  if (fields.size() != 7) {
    throw UsageError(describe(argument_name, text) + ": " + expected + ", got " +
                     std::to_string(fields.size()) + " field(s)");
  }
  static const char* const kFieldNames[7] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  double numbers[7];
  for (int i = 0; i < 7; ++i) {
    const std::string& field = fields[i];
    char* end = nullptr;
    errno = 0;
    const double number = std::strtod(field.c_str(), &end);
    const bool consumed = !field.empty() && end == field.c_str() + field.size();
    if (!consumed || errno == ERANGE || !std::isfinite(number)) {
      throw UsageError(describe(argument_name, text) + ": field " + kFieldNames[i] + " '" +
                       shown_input(field) + "' is not a finite number; " + expected);
    }
    numbers[i] = number;
  }
  const Quatd q(numbers[3], numbers[4], numbers[5], numbers[6]);
  const double q_norm = q.norm();
  const bool zero = numbers[3] == 0 && numbers[4] == 0 && numbers[5] == 0 && numbers[6] == 0;
  const std::string rotation = "expected a rotation quaternion, e.g. 1,0,0,0 for no rotation";
  // A quaternion whose norm under- or overflows cannot be normalised reliably either.
  if (!std::isfinite(q_norm)) {
    throw UsageError(describe(argument_name, text) +
                     ": the quaternion (qw,qx,qy,qz) is too large: its norm is not a finite "
                     "number (components up to 1e150 are taken); " +
                     rotation);
  }
  if (zero) {
    throw UsageError(describe(argument_name, text) + ": the quaternion (qw,qx,qy,qz) is zero; " +
                     rotation);
  }
  if (!(q_norm > 1e-150)) {
    throw UsageError(describe(argument_name, text) +
                     ": the quaternion (qw,qx,qy,qz) is too small to normalise: its norm is "
                     "below 1e-150; " +
                     rotation);
  }
  Posed pose;
  pose.position = Vec3d(numbers[0], numbers[1], numbers[2]);
  pose.orientation = q.normalized();
  return pose;
}

ShapeTemplate load_shape_argument(const std::string& argument_name, const std::string& spec) {
  try {
    return make_shape(spec);
  } catch (const std::exception& error) {
    std::string reason = error.what();
    for (char& c : reason) {
      if (c == '\n' || c == '\r') c = ' ';  // the error stays on one line
    }
    // A built-in spec's message starts by quoting the spec, and a mesh file's by its path (then
    // the line): the argument's name and text say the first already, "line N" the second.
    const std::string quoted = "shape spec '" + shown_input(spec, kShownSpecLimit) + "': ";
    if (reason.compare(0, quoted.size(), quoted) == 0) reason.erase(0, quoted.size());
    const std::string path = spec.substr(0, is_mesh_path(spec) ? spec.size() : spec.rfind(':'));
    if (is_mesh_path(path) && reason.compare(0, path.size() + 1, path + ":") == 0) {
      const std::size_t digits = reason.find_first_not_of("0123456789", path.size() + 1);
      if (reason.compare(path.size(), 2, ": ") == 0)
        reason.erase(0, path.size() + 2);
      else if (digits != std::string::npos && digits > path.size() + 1 &&
               reason.compare(digits, 2, ": ") == 0)
        reason = "line " + reason.substr(path.size() + 1, digits - path.size() - 1) + ": " +
                 reason.substr(digits + 2);
    }
    // The loader's message already says what it expected.
    throw UsageError(describe(argument_name, spec) + ": " + reason);
  }
}

int parse_positive_count(const std::string& option, const std::string& text, int max) {
  const std::string range = max == INT_MAX ? "of at least 1" : "from 1 to " + std::to_string(max);
  const std::string expected = option + " '" + shown(text) + "': expected a whole number " + range;
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
    throw UsageError(expected);
  }
  errno = 0;
  const long value = std::strtol(text.c_str(), nullptr, 10);
  if (errno == ERANGE || value > max) throw UsageError(expected + "; it is too large");
  if (value < 1) throw UsageError(expected);
  return static_cast<int>(value);
}

}  // namespace talus
