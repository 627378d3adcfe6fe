// The tests read talus's JSON with nlohmann's strict parser (RFC 8259: no NaN, Inf, comments or
// trailing commas), so that "the output is valid JSON" is a check that can fail. Keep the parsed
// value non-const: a missing key then reads as null and get<>() throws, which fails the test (a
// const lookup of a missing key is undefined).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include <gtest/gtest.h>

namespace talus_test {

using Json = nlohmann::json;

inline Json parse_or_fail(const std::string& text) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    ADD_FAILURE() << "not valid JSON: " << error.what() << "\n" << text;
    return Json::object();
  }
}

}  // namespace talus_test
