#include "solver/io/checkpoint.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>

#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"

namespace talus {

namespace {

constexpr char kMagic[8] = {'T', 'A', 'L', 'U', 'S', 'C', 'K', 'P'};
constexpr std::uint32_t kByteOrderMark = 0x01020304;
// Magic, version, mark, file size, section count.
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;

template <class T>
void append(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// Reads the file's bytes in order; every read past the end is a truncated file.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::size_t end, const std::string& path)
      : bytes_(bytes), end_(end), path_(path) {}
  template <class T>
  T value() {
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }
  std::string text(std::uint64_t size) {
    const char* p = take(size);
    return std::string(p, size);
  }

 private:
  const char* take(std::uint64_t size) {
    if (size > end_ - at_)
      throw CheckpointError(path_ +
                            ": truncated checkpoint (a section ends "
                            "past the end of the file)");
    const char* p = bytes_.data() + at_;
    at_ += size;
    return p;
  }
  const std::string& bytes_;
  std::size_t end_, at_ = kHeaderBytes;
  const std::string& path_;
};

}  // namespace

void throw_checkpoint_error(const std::string& path, const std::string& section,
                            const std::string& what) {
  throw CheckpointError((path.empty() ? std::string("checkpoint") : path) + ": section '" +
                        section + "': " + what);
}

void Checkpoint::fail(const std::string& name, const std::string& what) const {
  throw_checkpoint_error(path_, name, what);
}

CheckpointSection& Checkpoint::section(const std::string& name) {
  for (CheckpointSection& s : sections_)
    if (s.name == name) return s;
  sections_.push_back({name, 1, {}});
  return sections_.back();
}

const CheckpointSection* Checkpoint::find(const std::string& name) const {
  for (const CheckpointSection& s : sections_)
    if (s.name == name) return &s;
  return nullptr;
}

const CheckpointSection& Checkpoint::required(const std::string& name,
                                              std::uint32_t element_size) const {
  const CheckpointSection* s = find(name);
  if (!s) fail(name, "missing");
  if (s->element_size != element_size)
    fail(name, "expected elements of " + std::to_string(element_size) + " bytes, got " +
                   std::to_string(s->element_size));
  return *s;
}

std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t hash) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < size; ++k) {
    hash ^= bytes[k];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::uint64_t file_hash(const std::string& path) {
  std::string bytes;
  try {
    bytes = read_input_file(path);
  } catch (const InputFileError& e) {
    throw CheckpointError(e.what());
  }
  return fnv1a64(bytes.data(), bytes.size());
}

std::string checkpoint_bytes(const Checkpoint& checkpoint) {
  std::string out(kMagic, sizeof kMagic);
  append(out, kCheckpointVersion);
  append(out, kByteOrderMark);
  append(out, std::uint64_t(0));  // the file size, filled in below
  append(out, std::uint64_t(checkpoint.sections().size()));
  for (const CheckpointSection& s : checkpoint.sections()) {
    append(out, std::uint32_t(s.name.size()));
    out += s.name;
    append(out, s.element_size);
    append(out, s.count());
    out += s.bytes;
  }
  const std::uint64_t size = out.size() + sizeof(std::uint64_t);
  std::memcpy(&out[16], &size, sizeof size);
  append(out, fnv1a64(out.data(), out.size()));
  return out;
}

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint) {
  write_file_atomically(path, checkpoint_bytes(checkpoint));
}

Checkpoint read_checkpoint(const std::string& path) {
  std::string bytes;
  try {
    bytes = read_input_file(path);
  } catch (const InputFileError& e) {
    throw CheckpointError(path + ": cannot read the checkpoint: it " + e.problem());
  }
  if (bytes.empty()) throw CheckpointError(path + ": an empty file (0 bytes), not a checkpoint");
  if (bytes.size() < sizeof kMagic && std::memcmp(bytes.data(), kMagic, bytes.size()) == 0)
    throw CheckpointError(path + ": truncated checkpoint (" + std::to_string(bytes.size()) +
                          " bytes, shorter than its header)");
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw CheckpointError(path + ": not a talus checkpoint (no TALUSCKP header)");
  if (bytes.size() < kHeaderBytes + sizeof(std::uint64_t))
    throw CheckpointError(path + ": truncated checkpoint (" + std::to_string(bytes.size()) +
                          " bytes, shorter than its header)");
  std::uint32_t version = 0, mark = 0;
  std::uint64_t size = 0, sections = 0;
  std::memcpy(&version, bytes.data() + 8, 4);
  std::memcpy(&mark, bytes.data() + 12, 4);
  std::memcpy(&size, bytes.data() + 16, 8);
  std::memcpy(&sections, bytes.data() + 24, 8);
  // Whether the first `length` bytes are a whole checkpoint: their last 8 the checksum of the
  // rest, with `size_field` in place of the file-size field.
  const auto whole = [&](std::size_t length, std::uint64_t size_field) {
    if (length < kHeaderBytes + sizeof(std::uint64_t) || length > bytes.size()) return false;
    std::uint64_t hash = fnv1a64(bytes.data(), 16);
    hash = fnv1a64(&size_field, sizeof size_field, hash);
    hash = fnv1a64(bytes.data() + 24, length - 24 - sizeof(std::uint64_t), hash);
    std::uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + length - sizeof stored, sizeof stored);
    return hash == stored;
  };
  const std::string corrupt = path + ": corrupt checkpoint (the checksum does not match its bytes";
  // A header field that no intact file of ours holds is a damaged byte when the checksum fails
  // too, and another talus's file only when it holds.
  if (version != kCheckpointVersion) {
    if (!whole(bytes.size(), size))
      throw CheckpointError(corrupt + "; its version field reads " + std::to_string(version) + ")");
    throw CheckpointError(path + ": checkpoint format version " + std::to_string(version) +
                          "; this talus reads version " + std::to_string(kCheckpointVersion));
  }
  if (mark != kByteOrderMark) {
    if (!whole(bytes.size(), size))
      throw CheckpointError(corrupt + "; its byte-order mark is damaged)");
    throw CheckpointError(path + ": written on a machine of another byte order");
  }
  if (bytes.size() != size) {
    const std::string sizes =
        std::to_string(bytes.size()) + " bytes, its header says " + std::to_string(size);
    if (whole(bytes.size(), bytes.size()))
      throw CheckpointError(path + ": corrupt checkpoint (a damaged file-size field: " + sizes +
                            ", and its checksum matches the " + std::to_string(bytes.size()) + ")");
    if (bytes.size() < size)
      throw CheckpointError(path + ": truncated checkpoint (" + std::to_string(bytes.size()) +
                            " bytes of " + std::to_string(size) + ")");
    if (whole(size, size))
      throw CheckpointError(path + ": " + std::to_string(bytes.size() - size) +
                            (bytes.size() - size == 1 ? " byte was" : " bytes were") +
                            " appended to the checkpoint (" + sizes + ")");
    throw CheckpointError(corrupt + "; " + sizes + ")");
  }
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  if (!whole(bytes.size(), size)) throw CheckpointError(corrupt + ")");
  Checkpoint checkpoint;
  checkpoint.set_path(path);
  ByteReader reader(bytes, body, path);
  for (std::uint64_t k = 0; k < sections; ++k) {
    const std::string name = reader.text(reader.value<std::uint32_t>());
    const auto element_size = reader.value<std::uint32_t>();
    const auto count = reader.value<std::uint64_t>();
    if (element_size == 0 || count > body / element_size)
      throw CheckpointError(path + ": section '" + name + "' is larger than the file");
    checkpoint.put_bytes(name, element_size, reader.text(count * element_size));
  }
  return checkpoint;
}

std::string checkpoint_file_name(long long step) {
  return numbered_file_name("checkpoint_", step, ".bin");
}

std::vector<std::string> list_checkpoints(const std::string& directory) {
  // At most 18 digits: every such step fits a long long (a longer name is not one of ours).
  static const std::regex pattern("checkpoint_([0-9]{9,18})\\.bin");
  std::vector<std::pair<long long, std::string>> found;
  std::error_code error;
  for (std::filesystem::directory_iterator it(directory, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    std::smatch match;
    if (it->is_regular_file(error) && std::regex_match(name, match, pattern))
      found.emplace_back(std::stoll(match[1].str()), it->path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> paths;
  for (const auto& entry : found) paths.push_back(entry.second);
  return paths;
}

std::string checkpoint_run_id(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[kHeaderBytes];
  if (!in.read(header, sizeof header) || std::memcmp(header, kMagic, sizeof kMagic) != 0) return {};
  std::uint64_t sections = 0;
  std::memcpy(&sections, header + 24, 8);
  // The run's sections come first (the runner puts them before the step's): a few are read, the
  // rest of the file never is.
  for (std::uint64_t k = 0; k < sections && k < 64; ++k) {
    std::uint32_t name_size = 0, element_size = 0;
    std::uint64_t count = 0;
    if (!in.read(reinterpret_cast<char*>(&name_size), 4) || name_size > 256) return {};
    std::string name(name_size, '\0');
    if (!in.read(name.data(), name_size) || !in.read(reinterpret_cast<char*>(&element_size), 4) ||
        !in.read(reinterpret_cast<char*>(&count), 8))
      return {};
    if (name == "run.id") {
      if (element_size != 1 || count > 64) return {};
      std::string id(count, '\0');
      return in.read(id.data(), static_cast<std::streamsize>(count)) ? id : std::string();
    }
    if (element_size == 0 || count > (std::uint64_t(1) << 40) / element_size) return {};
    in.seekg(static_cast<std::streamoff>(count * element_size), std::ios::cur);
  }
  return {};
}

}  // namespace talus
