#include "solver/app/message_text.hpp"

#include <cstdio>
#include <vector>

namespace talus {

namespace {

// The bytes of a UTF-8 sequence that starts with `lead` (1 to 4), or 0 for a byte that cannot
// start one.
int sequence_length(unsigned char lead) {
  if (lead < 0x80) return 1;
  if (lead >= 0xc2 && lead <= 0xdf) return 2;
  if (lead >= 0xe0 && lead <= 0xef) return 3;
  if (lead >= 0xf0 && lead <= 0xf4) return 4;
  return 0;
}

// `text` as printable pieces, one per character: a valid UTF-8 sequence as it is, anything else
// as its escape.
std::vector<std::string> printable_pieces(const std::string& text) {
  std::vector<std::string> pieces;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    int length = sequence_length(c);
    if (length > 1) {
      if (i + length > text.size()) length = 0;
      for (int k = 1; k < length; ++k)
        if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) length = 0;
    }
    if (length == 1 && c >= 0x20 && c != 0x7f) {
      pieces.emplace_back(1, text[i]);
    } else if (length > 1) {
      pieces.push_back(text.substr(i, length));
    } else {
      char escape[8];
      if (c == '\t' || c == '\n' || c == '\r')
        std::snprintf(escape, sizeof escape, "\\%c", c == '\t' ? 't' : c == '\n' ? 'n' : 'r');
      else
        std::snprintf(escape, sizeof escape, "\\x%02x", c);
      pieces.emplace_back(escape);
      length = 1;
    }
    i += length;
  }
  return pieces;
}

}  // namespace

std::string shown(const std::string& text, std::size_t max) {
  const std::vector<std::string> pieces = printable_pieces(text);
  std::string whole;
  for (const std::string& piece : pieces) whole += piece;
  if (whole.size() <= max) return whole;
  // Whole pieces (an escape, a UTF-8 character) from each end, within max counted in bytes
  // shown: two thirds at the beginning, a third at the end.
  std::string head, tail;
  for (std::size_t k = 0; k < pieces.size() && head.size() + pieces[k].size() <= max * 2 / 3; ++k)
    head += pieces[k];
  for (std::size_t k = pieces.size(); k > 0 && tail.size() + pieces[k - 1].size() <= max / 3; --k)
    tail.insert(0, pieces[k - 1]);
  return head + "[... " + std::to_string(text.size()) + " bytes in all ...]" + tail;
}

std::string printable_message(const std::string& message) {
  constexpr std::size_t kLongestWord = 160, kLongestMessage = 900;
  std::string out;
  for (std::size_t begin = 0; begin < message.size();) {
    std::size_t end = message.find(' ', begin);
    if (end == std::string::npos) end = message.size();
    out += shown(message.substr(begin, end - begin), kLongestWord);
    if (end < message.size()) out += ' ';
    begin = end + 1;
  }
  if (out.size() <= kLongestMessage) return out;
  // Cut between whole characters: never inside a UTF-8 sequence.
  std::size_t head = kLongestMessage / 2, tail = out.size() - kLongestMessage / 3;
  while (head > 0 && (static_cast<unsigned char>(out[head]) & 0xc0) == 0x80) --head;
  while (tail < out.size() && (static_cast<unsigned char>(out[tail]) & 0xc0) == 0x80) ++tail;
  return out.substr(0, head) + " ... (" + std::to_string(tail - head) + " bytes left out) ... " +
         out.substr(tail);
}

}  // namespace talus
