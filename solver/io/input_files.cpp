#include "solver/io/input_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace talus {
namespace {

// "" for a regular file, else what the file is instead.
std::string kind_problem(mode_t mode) {
  if (S_ISREG(mode)) return "";
  const std::string kind = file_kind(mode);
  return kind == "a special file" ? "is not a regular file" : "is " + kind + ", not a regular file";
}

std::string errno_problem(int error, const std::string& path) {
  if (error == ENOENT) return "does not exist";
  if (error == ENOTDIR) {
    // A file where the path needs a directory: name it (strerror says only "Not a directory").
    // The path without its trailing slashes first ("scene.yaml/"), then each directory above.
    std::string above = path;
    while (above.size() > 1 && above.back() == '/') above.pop_back();
    if (above == path) above.resize(above.rfind('/') == std::string::npos ? 0 : above.rfind('/'));
    while (!above.empty()) {
      struct stat status;
      if (::stat(above.c_str(), &status) == 0 && !S_ISDIR(status.st_mode))
        return "cannot be reached: '" + above + "' on its path is not a directory";
      while (above.size() > 1 && above.back() == '/') above.pop_back();
      const std::size_t slash = above.rfind('/');
      above.resize(slash == std::string::npos ? 0 : slash);
    }
  }
  return std::string("cannot be accessed: ") + std::strerror(error);
}

// Closes the descriptor on every way out of read_input_file.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// The length of the valid UTF-8 sequence (no overlong form, no surrogate, no C1 control)
// starting at s[i], or 0.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = byte(i);
  std::size_t n = 0;
  unsigned char low = 0x80, high = 0xBF;  // the allowed range of the second byte
  if (b >= 0xC2 && b <= 0xDF) n = 2, low = b == 0xC2 ? 0xA0 : 0x80;  // no C1 control
  if (b >= 0xE0 && b <= 0xEF) n = 3, low = b == 0xE0 ? 0xA0 : 0x80, high = b == 0xED ? 0x9F : 0xBF;
  if (b >= 0xF0 && b <= 0xF4) n = 4, low = b == 0xF0 ? 0x90 : 0x80, high = b == 0xF4 ? 0x8F : 0xBF;
  if (n == 0 || i + n > s.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return n;
}

}  // namespace

std::string file_kind(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "a special file";
}

std::string shown_input(const std::string& text, std::size_t limit) {
  std::string shown;
  std::size_t characters = 0, i = 0;
  for (; i < text.size() && characters < limit; ++characters) {
    const unsigned char b = static_cast<unsigned char>(text[i]);
    if (b >= 0x20 && b < 0x7F) {
      shown += text[i++];
      continue;
    }
    const std::size_t n = b >= 0x80 ? utf8_length(text, i) : 0;
    if (n > 0) {
      shown += text.substr(i, n);
      i += n;
      continue;
    }
    char escaped[8];
    std::snprintf(escaped, sizeof escaped, "\\x%02X", unsigned(b));
    shown += escaped;
    ++i;
  }
  if (i < text.size()) shown += "... (" + std::to_string(text.size()) + " bytes)";
  return shown;
}

std::string input_file_problem(const std::string& path) {
  struct stat status;
  if (::stat(path.c_str(), &status) != 0) return errno_problem(errno, path);
  return kind_problem(status.st_mode);
}

std::string read_input_file(const std::string& path) {
  // The kind is checked first, without opening: opening a FIFO (even non-blocking) can disturb
  // the process at its other end.
  const std::string problem = input_file_problem(path);
  if (!problem.empty()) throw InputFileError(path, problem);
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) throw InputFileError(path, errno_problem(errno, path));
  struct stat status;
  if (::fstat(file.fd, &status) != 0) throw InputFileError(path, errno_problem(errno, path));
  const std::string kind = kind_problem(status.st_mode);
  if (!kind.empty()) throw InputFileError(path, kind);
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(file.fd, buffer, sizeof buffer);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      throw InputFileError(path, std::string("cannot be read: ") + std::strerror(errno));
    }
    bytes.append(buffer, std::size_t(n));
  }
  return bytes;
}

}  // namespace talus
