// The command line's JSON writer: layout, escaping, and finite-only numbers.
#include "solver/app/json_writer.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(JsonWriter, NestedLayoutIsExact) {
  JsonWriter json;
  json.begin_object();
  json.member("n", 3);
  json.member("v", Vec3d(1, -2.5, 0));
  json.key("list");
  json.begin_array(JsonWriter::Layout::multi_line);
  json.begin_object(JsonWriter::Layout::one_line);
  json.member("ok", true);
  json.key("empty");
  json.begin_array();
  json.end_array();
  json.end_object();
  json.end_array();
  json.end_object();
  EXPECT_TRUE(json.complete());
  EXPECT_EQ(json.str(),
            "{\n"
            "  \"n\": 3,\n"
            "  \"v\": [1, -2.5, 0],\n"
            "  \"list\": [\n"
            "    {\"ok\": true, \"empty\": []}\n"
            "  ]\n"
            "}\n");
}

TEST(JsonWriter, StringsAreEscaped) {
  JsonWriter json;
  json.value(std::string("a\"b\\c\nd\te\x01/") + "\xc3\xa9");
  EXPECT_EQ(json.str(), "\"a\\\"b\\\\c\\nd\\te\\u0001/\xc3\xa9\"\n");
}

TEST(JsonWriter, NonFiniteNumbersBecomeNull) {
  JsonWriter json;
  json.begin_array();
  json.value(std::numeric_limits<double>::quiet_NaN());
  json.value(std::numeric_limits<double>::infinity());
  json.value(-std::numeric_limits<double>::infinity());
  json.end_array();
  EXPECT_EQ(json.str(), "[null, null, null]\n");
}

// 17 significant digits make every double round-trip exactly, which the CLI tests' 1e-12
// tolerances rely on.
TEST(JsonWriter, NumbersRoundTripExactly) {
  for (const double x :
       {0.1, 1.0 / 3.0, -2.220446049250313e-16, 1e-300, 6.02214076e23, std::nextafter(1.0, 2.0)}) {
    JsonWriter json;
    json.value(x);
    EXPECT_EQ(std::strtod(json.str().c_str(), nullptr), x) << json.str();
  }
}

}  // namespace
}  // namespace talus
