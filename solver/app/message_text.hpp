// What an error message may show of the user's own text (an argument, a path): printable UTF-8 on
// one line and of a bounded length, however long the text or whatever bytes it holds. The command
// line quotes its arguments through shown(); main passes every message through
// printable_message() before it prints it, for the paths that other layers put in theirs.
#pragma once

#include <cstddef>
#include <string>

namespace talus {

// `text` as a message quotes it: a tab, newline or carriage return written \t, \n, \r; any other
// control byte, and each byte that is not part of valid UTF-8, written \xNN; a text that shows in
// more than `max` bytes cut in the middle between whole characters: "aaa[... 100000 bytes in all
// ...]aaa".
std::string shown(const std::string& text, std::size_t max = 160);

// A whole message made printable (as shown() escapes) with each word (a run without spaces) over
// 160 characters cut as shown() cuts it, and a message still over 900 bytes cut in its middle,
// keeping its beginning (the place) and its end (the cause).
std::string printable_message(const std::string& message);

}  // namespace talus
