// Checkpoint files (outputs.checkpoint; format in docs/scenes.md, "Checkpoints"): the whole state
// a run needs to go on exactly, as named sections of raw bytes in one binary file:
//
//   "TALUSCKP"                 8 bytes, the magic
//   version                    uint32 (kCheckpointVersion)
//   byte-order mark            uint32 0x01020304 as the writing machine stores it
//   file size                  uint64, every byte of the file (a truncated file is told apart)
//   section count              uint64
//   per section:               name length uint32, name, element size uint32, element count
//                              uint64, count * size bytes
//   checksum                   uint64, FNV-1a of every byte before it
//
// Numbers are in the writing machine's byte order (the mark refuses another); values are stored
// with their bits, so a double or float reads back exactly. The file is written to "<path>.tmp"
// and renamed (output_files.hpp), so an interrupted write leaves the last complete checkpoint.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace talus {

constexpr std::uint32_t kCheckpointVersion = 1;

// A checkpoint that cannot be read: what() names the file and says what is wrong (missing,
// truncated, a checksum that does not match, another format version, a missing section).
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws the CheckpointError "<path>: section '<section>': <what>" ("checkpoint" for an empty
// path): what every refusal of a section's contents says, whoever finds it.
[[noreturn]] void throw_checkpoint_error(const std::string& path, const std::string& section,
                                         const std::string& what);

struct CheckpointSection {
  std::string name;
  std::uint32_t element_size = 1;
  std::string bytes;  // element_size * count bytes
  std::uint64_t count() const { return element_size ? bytes.size() / element_size : 0; }
};

class Checkpoint {
 public:
  // Adds (or replaces) a section of trivially copyable values.
  template <class T>
  void put(const std::string& name, const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>, "checkpoint values are stored as bytes");
    CheckpointSection& s = section(name);
    s.element_size = sizeof(T);
    s.bytes.assign(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  template <class T>
  void put_value(const std::string& name, const T& value) {
    put(name, std::vector<T>{value});
  }
  void put_text(const std::string& name, const std::string& text) { put_bytes(name, 1, text); }
  // A section as stored: `bytes` holds whole elements of `element_size` bytes.
  void put_bytes(const std::string& name, std::uint32_t element_size, std::string bytes) {
    CheckpointSection& s = section(name);
    s.element_size = element_size;
    s.bytes = std::move(bytes);
  }

  bool has(const std::string& name) const { return find(name) != nullptr; }
  // The section's values; CheckpointError naming the file and section when it is missing or its
  // element size is not sizeof(T).
  template <class T>
  std::vector<T> get(const std::string& name) const {
    const CheckpointSection& s = required(name, sizeof(T));
    std::vector<T> values(s.bytes.size() / sizeof(T));
    if (!values.empty()) std::memcpy(values.data(), s.bytes.data(), s.bytes.size());
    return values;
  }
  // A section of exactly one value.
  template <class T>
  T get_value(const std::string& name) const {
    const std::vector<T> values = get<T>(name);
    if (values.size() != 1) fail(name, "expected one value, got " + std::to_string(values.size()));
    return values[0];
  }
  std::string text(const std::string& name) const { return required(name, 1).bytes; }

  const std::vector<CheckpointSection>& sections() const { return sections_; }
  // The file this was read from (for messages); empty when made in memory.
  const std::string& path() const { return path_; }
  void set_path(const std::string& path) { path_ = path; }
  [[noreturn]] void fail(const std::string& name, const std::string& what) const;

 private:
  CheckpointSection& section(const std::string& name);
  const CheckpointSection* find(const std::string& name) const;
  const CheckpointSection& required(const std::string& name, std::uint32_t element_size) const;

  std::vector<CheckpointSection> sections_;
  std::string path_;
};

// FNV-1a, 64 bits, of `size` bytes (continuing from `hash`).
std::uint64_t fnv1a64(const void* data, std::size_t size,
                      std::uint64_t hash = 0xcbf29ce484222325ULL);
// The FNV-1a of a file's bytes; CheckpointError "<path>: cannot read ..." when it cannot be read.
std::uint64_t file_hash(const std::string& path);

// The file's bytes (header, sections, checksum), and the file written through a temporary name
// and a rename. Throws std::runtime_error naming the path when writing fails.
std::string checkpoint_bytes(const Checkpoint& checkpoint);
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Reads and checks a checkpoint file. Throws CheckpointError naming the path: not a checkpoint,
// another version, truncated, a checksum mismatch.
Checkpoint read_checkpoint(const std::string& path);

// "checkpoint_000001200.bin" for step 1200.
std::string checkpoint_file_name(long long step);
// The checkpoint files (checkpoint_<digits>.bin) of a directory by increasing step; empty when
// there are none or the directory does not exist.
std::vector<std::string> list_checkpoints(const std::string& directory);
// The run id (section `run.id`) of a checkpoint file, read from its first sections without
// checking the whole file; empty when it has none or cannot be read.
std::string checkpoint_run_id(const std::string& path);

}  // namespace talus
