// JSON as talus writes and reads it (solver/io/json.hpp): the layout, escaping, finite-only
// numbers that read back exactly, and parse errors that name the file.
#include "solver/io/json.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(Json, LayoutIsExact) {
  Json json;
  json["n"] = 3;
  json["v"] = Vec3d(1, -2.5, 0);
  json["q"] = Quatd(1, 0, 0, 0);
  json["list"] = Json::array({Json{{"ok", true}, {"empty", Json::array()}}});
  json["nested"] = {{"a", "x"}};
  EXPECT_EQ(json_text(json),
            "{\n"
            "  \"n\": 3,\n"
            "  \"v\": [1.0, -2.5, 0.0],\n"
            "  \"q\": [1.0, 0.0, 0.0, 0.0],\n"
            "  \"list\": [\n"
            "    {\"ok\": true, \"empty\": []}\n"
            "  ],\n"
            "  \"nested\": {\n"
            "    \"a\": \"x\"\n"
            "  }\n"
            "}\n");
}

// An array or a record in an array that would pass 100 columns takes a line per element; an
// array holding an object is never put on one line.
TEST(Json, LongArraysTakeALineAnElement) {
  Json json;
  json["paths"] = Json::array();
  for (int i = 0; i < 5; ++i) json["paths"].push_back(std::string(30, 'a' + i));
  json["records"] = Json::array({Json{{"k", Json::array({1, 2})}}});
  const std::string text = json_text(json);
  EXPECT_NE(text.find("  \"paths\": [\n    \"aaaa"), std::string::npos) << text;
  EXPECT_NE(text.find("\n    \"eeee"), std::string::npos) << text;
  EXPECT_NE(text.find("  \"records\": [\n    {\"k\": [1, 2]}\n  ]"), std::string::npos) << text;
  EXPECT_EQ(parse_json(text, "test"), json);
}

TEST(Json, StringsAreEscapedAndUtf8PassesThrough) {
  const Json json = std::string("a\"b\\c\nd\te\x01/") + "\xc3\xa9";
  EXPECT_EQ(json_text(json), "\"a\\\"b\\\\c\\nd\\te\\u0001/\xc3\xa9\"\n");
  // Bytes that are not UTF-8 (a Latin-1 file name) are replaced, not thrown on.
  EXPECT_EQ(json_text(Json("caf\xe9")), "\"caf\xef\xbf\xbd\"\n");
}

TEST(Json, NonFiniteNumbersBecomeNull) {
  const Json json = Json::array({std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity()});
  EXPECT_EQ(json_text(json), "[null, null, null]\n");
}

// Every double reads back to the same bits, which the command-line tests' 1e-12 tolerances rely
// on; a \u escape beyond one byte reads back as its UTF-8 (the hand-written run.json reader kept
// only its low byte).
TEST(Json, NumbersAndEscapesRoundTripExactly) {
  for (const double x :
       {0.1, 1.0 / 3.0, -2.220446049250313e-16, 1e-300, 6.02214076e23, std::nextafter(1.0, 2.0),
        std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max()}) {
    const std::string text = json_text(Json(x));
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), x) << text;
    EXPECT_EQ(parse_json(text, "test").get<double>(), x) << text;
  }
  EXPECT_EQ(parse_json("\"\\u00e9\\u4e2d\"", "test").get<std::string>(), "\xc3\xa9\xe4\xb8\xad");
}

TEST(Json, ParseErrorsNameTheFileAndPlace) {
  for (const char* text : {"{\"a\": 1,}", "{\"a\": NaN}", "[1, 2", "{} {}", "// c\n{}"}) {
    try {
      parse_json(text, "dir/run.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("dir/run.json: not valid JSON: ", 0), 0u) << what;
      EXPECT_NE(what.find("line 1"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace talus
