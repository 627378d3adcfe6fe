// A small JSON writer for the command line's output. It builds the whole document in a string so
// that an error half-way leaves nothing printed. Numbers carry 17 significant digits (a double
// round-trips exactly); a non-finite number is written as null, since JSON has no NaN or Inf.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "solver/core/quat.hpp"

namespace talus {

class JsonWriter {
 public:
  // A container laid out on one line (arrays of numbers, small records) or one element per line.
  enum class Layout { one_line, multi_line };

  void begin_object(Layout layout = Layout::multi_line) { open('{', layout); }
  void end_object() { close('}'); }
  void begin_array(Layout layout = Layout::one_line) { open('[', layout); }
  void end_array() { close(']'); }

  // The key of the next member of the current object.
  void key(const std::string& name) {
    separate();
    append_string(name);
    text_ += ": ";
    after_key_ = true;
  }

  void value(double number) {
    separate();
    if (!std::isfinite(number)) {
      text_ += "null";
      return;
    }
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", number);
    text_ += buffer;
  }
  void value(int number) {
    separate();
    text_ += std::to_string(number);
  }
  void value(bool flag) {
    separate();
    text_ += flag ? "true" : "false";
  }
  void value(const std::string& text) {
    separate();
    append_string(text);
  }
  void value(const char* text) { value(std::string(text)); }
  void value(const Vec3d& v) {
    begin_array();
    value(v.x);
    value(v.y);
    value(v.z);
    end_array();
  }
  // A quaternion as [w, x, y, z].
  void value(const Quatd& q) {
    begin_array();
    value(q.w);
    value(q.x);
    value(q.y);
    value(q.z);
    end_array();
  }

  template <class T>
  void member(const std::string& name, const T& v) {
    key(name);
    value(v);
  }

  // The finished document, newline-terminated; valid once every container is closed.
  std::string str() const { return text_ + "\n"; }
  bool complete() const { return stack_.empty() && !text_.empty(); }

 private:
  struct Level {
    Layout layout;
    bool empty;
  };

  void open(char bracket, Layout layout) {
    separate();
    text_ += bracket;
    // A container inside a one-line container stays on that line.
    if (!stack_.empty() && stack_.back().layout == Layout::one_line) layout = Layout::one_line;
    stack_.push_back({layout, true});
  }

  void close(char bracket) {
    const Level level = stack_.back();
    stack_.pop_back();
    if (level.layout == Layout::multi_line && !level.empty) newline();
    text_ += bracket;
  }

  // Comma and line break before a new element; nothing after a key.
  void separate() {
    if (after_key_) {
      after_key_ = false;
      return;
    }
    if (stack_.empty()) return;
    Level& level = stack_.back();
    if (!level.empty) text_ += level.layout == Layout::one_line ? ", " : ",";
    if (level.layout == Layout::multi_line) newline();
    level.empty = false;
  }

  void newline() {
    text_ += '\n';
    text_.append(2 * stack_.size(), ' ');
  }

  void append_string(const std::string& s) {
    text_ += '"';
    for (const char c : s) {
      switch (c) {
        case '"':
          text_ += "\\\"";
          break;
        case '\\':
          text_ += "\\\\";
          break;
        case '\n':
          text_ += "\\n";
          break;
        case '\r':
          text_ += "\\r";
          break;
        case '\t':
          text_ += "\\t";
          break;
        case '\b':
          text_ += "\\b";
          break;
        case '\f':
          text_ += "\\f";
          break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned char>(c));
            text_ += buffer;
          } else {
            text_ += c;  // UTF-8 bytes pass through unchanged
          }
      }
    }
    text_ += '"';
  }

  std::string text_;
  std::vector<Level> stack_;
  bool after_key_ = false;
};

}  // namespace talus
