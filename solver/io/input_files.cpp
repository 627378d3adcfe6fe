#include "solver/io/input_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace talus {
namespace {

// "" for a regular file, else what the file is instead.
std::string kind_problem(mode_t mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "is a directory, not a regular file";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(mode)) return "is a character device, not a regular file";
  if (S_ISBLK(mode)) return "is a block device, not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
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

}  // namespace

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
