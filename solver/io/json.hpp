// JSON for everything talus writes or reads as JSON (the commands' summaries, run.json,
// render.json): nlohmann's json, its members kept in the order they were set, and one layout for
// people to read. Host only.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "solver/core/quat.hpp"
#include "solver/core/vec3.hpp"

namespace talus {

using Json = nlohmann::ordered_json;

// A vector as [x, y, z]; a quaternion as [w, x, y, z] (found by nlohmann through ADL).
void to_json(Json& json, const Vec3d& v);
void to_json(Json& json, const Quatd& q);

// The document as text, newline-terminated: an object one member a line (two spaces a level), an
// array on one line when it holds no object and fits in 100 columns, else one element a line; an
// object inside an array on one line when it holds only numbers, strings, booleans and such
// arrays and fits. Numbers are nlohmann's shortest text that reads back to the same double; a
// NaN or an infinity is written as null (JSON has neither). Strings are escaped as RFC 8259 asks,
// UTF-8 passed through.
std::string json_text(const Json& document);

// The JSON document that makes up all of `text`, or a std::runtime_error
// "<where>: not valid JSON: <what and the byte where it failed>".
Json parse_json(const std::string& text, const std::string& where);

}  // namespace talus
