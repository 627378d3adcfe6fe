// Opening the files talus reads (scenes, meshes, checkpoints, trajectories, probes) by a path the
// user gave: anything but a regular file is refused as what it is, and nothing blocks. A FIFO
// would block open(2) until a writer appears, /dev/zero would be read forever, and a directory
// "opens" fine with std::ifstream and then reads as empty.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include <sys/types.h>

namespace talus {

// Why `path` cannot be read as an input file, or "" when it is a regular file (symbolic links
// followed): "does not exist", "is a directory, not a regular file", "is a FIFO (named pipe), not
// a regular file", "is a character device, not a regular file", "is a block device, not a
// regular file", "is a socket, not a regular file", "cannot be reached: '<dir>' on its path is
// not a directory" (a file where a directory must be), or "cannot be accessed: <reason>".
std::string input_file_problem(const std::string& path);

// What a file of this mode (stat's st_mode) is: "a regular file", "a directory", "a FIFO (named
// pipe)", "a character device", "a block device", "a socket" or "a special file".
std::string file_kind(mode_t mode);

// Thrown by read_input_file: what() is "<path>: <problem>"; problem() is the part after the path.
class InputFileError : public std::runtime_error {
 public:
  InputFileError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem), problem_(problem) {}
  const std::string& problem() const { return problem_; }

 private:
  std::string problem_;
};

// The whole content of the regular file `path`. The file is opened without blocking and checked
// with fstat(2) on the open descriptor (so a path swapped after input_file_problem is still
// refused) before a single byte is read. Throws InputFileError.
std::string read_input_file(const std::string& path);

// `text` (a line or token of an input file, a spec the user wrote) as a message may show it: a
// control byte or a byte that is not part of valid UTF-8 as \xNN, and a text longer than
// `limit` characters cut there with "... (N bytes)" after it, so that a binary file or a
// 100 kB line never reaches the terminal raw or whole.
std::string shown_input(const std::string& text, std::size_t limit = 60);
// The limit for a spec or a path, which may be long and still be what the user meant.
constexpr std::size_t kShownSpecLimit = 200;

}  // namespace talus
