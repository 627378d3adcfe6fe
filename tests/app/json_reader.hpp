// A strict JSON reader for the tests (RFC 8259 grammar: no NaN, Inf, comments or trailing commas),
// so that "the output is valid JSON" is a check that can fail.
#pragma once

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace talus_test {

struct Json {
  enum Kind { null, boolean, number, string, array, object } kind = null;
  bool flag = false;
  double value = 0;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> members;

  const Json& operator[](const std::string& key) const {
    static const Json missing;
    const auto it = members.find(key);
    if (it == members.end()) ADD_FAILURE() << "missing key '" << key << "'";
    return it == members.end() ? missing : it->second;
  }
  double x(int i) const { return kind == array && i < int(items.size()) ? items[i].value : NAN; }
};

class JsonReader {
 public:
  explicit JsonReader(const std::string& text) : s_(text) {}

  // The single value that makes up the whole text; false on any syntax error.
  bool parse(Json& out) {
    skip_space();
    if (!read_value(out, 0)) return false;
    skip_space();
    return pos_ == s_.size();
  }

 private:
  void skip_space() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\n' || s_[pos_] == '\t' || s_[pos_] == '\r')) {
      ++pos_;
    }
  }
  bool literal(const char* word) {
    const std::string w(word);
    if (s_.compare(pos_, w.size(), w) != 0) return false;
    pos_ += w.size();
    return true;
  }
  bool read_string(std::string& out) {
    if (s_[pos_] != '"') return false;
    for (++pos_; pos_ < s_.size(); ++pos_) {
      const char c = s_[pos_];
      if (c == '"') {
        ++pos_;
        return true;
      }
      if (static_cast<unsigned char>(c) < 0x20) return false;
      if (c == '\\') {
        if (++pos_ >= s_.size()) return false;
        const char e = s_[pos_];
        const std::string simple = "\"\\/bfnrt";
        if (e == 'u') {
          if (pos_ + 4 >= s_.size()) return false;
          out += static_cast<char>(std::strtol(s_.substr(pos_ + 1, 4).c_str(), nullptr, 16));
          pos_ += 4;
        } else if (simple.find(e) != std::string::npos) {
          out += e == 'n' ? '\n' : (e == 't' ? '\t' : (e == 'r' ? '\r' : e));
        } else {
          return false;
        }
      } else {
        out += c;
      }
    }
    return false;
  }
  bool read_number(double& out) {
    const size_t start = pos_;
    if (s_[pos_] == '-') ++pos_;
    auto digits = [&] {
      const size_t from = pos_;
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      return pos_ > from;
    };
    if (!digits()) return false;
    if (pos_ < s_.size() && s_[pos_] == '.') {
      ++pos_;
      if (!digits()) return false;
    }
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
      if (!digits()) return false;
    }
    out = std::strtod(s_.substr(start, pos_ - start).c_str(), nullptr);
    return true;
  }
  bool read_value(Json& out, int depth) {
    if (pos_ >= s_.size() || depth > 32) return false;
    const char c = s_[pos_];
    if (c == '{' || c == '[') {
      const bool is_object = c == '{';
      out.kind = is_object ? Json::object : Json::array;
      ++pos_;
      skip_space();
      if (pos_ < s_.size() && s_[pos_] == (is_object ? '}' : ']')) {
        ++pos_;
        return true;
      }
      while (true) {
        skip_space();
        Json item;
        std::string key;
        if (is_object) {
          if (pos_ >= s_.size() || !read_string(key)) return false;
          skip_space();
          if (pos_ >= s_.size() || s_[pos_++] != ':') return false;
          skip_space();
        }
        if (!read_value(item, depth + 1)) return false;
        if (is_object) {
          if (out.members.count(key)) return false;  // duplicate key
          out.members[key] = item;
        } else {
          out.items.push_back(item);
        }
        skip_space();
        if (pos_ >= s_.size()) return false;
        const char next = s_[pos_++];
        if (next == (is_object ? '}' : ']')) return true;
        if (next != ',') return false;
      }
    }
    if (c == '"') {
      out.kind = Json::string;
      return read_string(out.text);
    }
    if (literal("true") || literal("false")) {
      out.kind = Json::boolean;
      out.flag = c == 't';
      return true;
    }
    if (literal("null")) return true;
    out.kind = Json::number;
    return read_number(out.value);
  }

  const std::string& s_;
  size_t pos_ = 0;
};

inline Json parse_or_fail(const std::string& text) {
  Json json;
  EXPECT_TRUE(JsonReader(text).parse(json)) << "not valid JSON:\n" << text;
  return json;
}

}  // namespace talus_test
