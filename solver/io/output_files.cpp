#include "solver/io/output_files.hpp"

#include "solver/io/input_files.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace talus {

void create_output_directory(const std::string& directory, const std::string& role) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (!error && std::filesystem::is_directory(directory, error)) return;
  const std::string what = "cannot create " + role + " '" + directory + "': ";
  // What stands in the way: the path itself, or the nearest of its parents that exists and is
  // not a directory.
  for (std::filesystem::path p = directory; !p.empty(); p = p.parent_path()) {
    struct stat status;
    if (::stat(p.c_str(), &status) == 0) {
      if (S_ISDIR(status.st_mode)) break;
      const std::string kind = file_kind(status.st_mode);
      if (p.string() == directory)
        throw OutputPathError(what + "it is " + kind + ", not a directory");
      throw OutputPathError(what + "'" + p.string() + "' is " + kind + ", not a directory");
    }
    if (p == p.parent_path()) break;
  }
  throw OutputPathError(what + (error ? error.message() : "a file of that name is in the way"));
}

void sync_directory_of(const std::string& path) {
  std::string directory = std::filesystem::path(path).parent_path().string();
  if (directory.empty()) directory = ".";
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0)
    throw std::runtime_error("cannot sync directory '" + directory + "': " + std::strerror(errno));
  const int code = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  // Some file systems cannot sync a directory (EINVAL): nothing more can be done there.
  if (code != 0 && code != EINVAL)
    throw std::runtime_error("cannot sync directory '" + directory + "': " + std::strerror(code));
}

void sync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot sync '" + path + "': " + std::strerror(errno));
  const int code = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  if (code != 0) throw std::runtime_error("cannot sync '" + path + "': " + std::strerror(code));
}

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  auto fail = [&](int code) {
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write '" + path + "': " + std::strerror(code));
  };
  std::FILE* file = std::fopen(temporary.c_str(), "wb");
  if (!file) fail(errno);
  const std::size_t written = std::fwrite(text.data(), 1, text.size(), file);
  int code = (written != text.size() || std::fflush(file) != 0) ? errno : 0;
  // On the disk before the rename: a power loss leaves the old file or the whole new one, never
  // a new name on an empty file.
  if (code == 0 && ::fsync(fileno(file)) != 0) code = errno;
  if (std::fclose(file) != 0 && code == 0) code = errno;
  if (written != text.size() && code == 0) code = EIO;
  if (code != 0) fail(code);
  if (std::rename(temporary.c_str(), path.c_str()) != 0) fail(errno);
  sync_directory_of(path);  // the rename itself, on the disk
}

std::string numbered_file_name(const std::string& prefix, long long step,
                               const std::string& extension) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%09lld", step);
  return prefix + digits + extension;
}

std::string joined_path(const std::string& root, const std::string& path) {
  if (root.empty() || path.empty() || path.front() == '/') return path;
  return root + (root.back() == '/' ? "" : "/") + path;
}

std::string exact_decimal(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(line.substr(begin, comma - begin));
    if (comma == std::string::npos) return fields;
    begin = comma + 1;
  }
}

bool parse_double(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  // ERANGE on underflow still gives the nearest value (a subnormal): accept it, as printed.
  return end == text.c_str() + text.size();
}

}  // namespace talus
