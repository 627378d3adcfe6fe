// Reading the command line's positional arguments: poses and shape specs. Every failure is a
// UsageError whose message names the argument and says what was expected.
#pragma once

#include <climits>
#include <stdexcept>
#include <string>
#include <utility>

#include "solver/app/message_text.hpp"
#include "solver/core/quat.hpp"
#include "solver/shape/shape.hpp"

namespace talus {

// A bad command line. main prints the message and the usage on stderr and exits with status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "x,y,z,qw,qx,qy,qz": position in metres and an orientation quaternion (body -> world), which is
// normalised here; a zero or non-finite quaternion is an error. `argument_name` (e.g. "POSE_A")
// goes into the error message.
Posed parse_pose(const std::string& argument_name, const std::string& text);

// A built-in shape spec or a mesh file (solver/shape/mesh_io.hpp: make_shape); the loader's own
// message is kept and prefixed with the argument's name and text.
ShapeTemplate load_shape_argument(const std::string& argument_name, const std::string& spec);

// A whole number from 1 to `max` written in decimal (nothing else around it), or a UsageError
// naming the option: "--threads '0': expected a whole number from 1 to 1024".
int parse_positive_count(const std::string& option, const std::string& text, int max = INT_MAX);

// One of `choices` (as written), or a UsageError naming the option and listing them.
template <class Value, std::size_t N>
Value choose(const std::string& option, const std::string& text,
             const std::pair<const char*, Value> (&choices)[N]) {
  std::string listed;
  for (const auto& [name, value] : choices) {
    if (text == name) return value;
    listed += (listed.empty() ? "" : ", ") + std::string(name);
  }
  throw UsageError(option + " '" + shown(text) + "': expected one of " + listed);
}

}  // namespace talus
