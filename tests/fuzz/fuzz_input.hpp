// What the three fuzz targets share: the readers under test take file paths, so each input is
// written to a file of this process's own (in /dev/shm when there is one: no disk traffic per
// input), and a fixed name so that a crash's file is easy to find.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace talus_fuzz {

// This process's scratch directory, made on first use.
inline const std::string& scratch_directory() {
  static const std::string directory = [] {
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm")
                                           ? "/dev/shm"
                                           : std::filesystem::temp_directory_path();
    const std::filesystem::path d = base / ("talus-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return directory;
}

// The bytes written to `name` in the scratch directory; returns the file's path.
inline std::string write_input(const std::uint8_t* data, std::size_t size,
                               const std::string& name) {
  const std::string path = scratch_directory() + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace talus_fuzz
