// Writing output files so that an interrupted run never leaves a half-written file under its
// final name: the text goes to a temporary file in the same directory, which is then renamed
// (rename(2) replaces the target in one step within a file system).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace talus {

// An output path that cannot be used as the run asks: a file where a directory must go (or above
// one), a directory where a file must go, a name too long, no permission. The user's setting, not
// an internal failure: talus exits with status 2 for it.
class OutputPathError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Creates `directory` and its parents when missing. Throws OutputPathError "cannot create <role>
// '<dir>': <reason>", the reason naming what is in the way ("'out' is a regular file, not a
// directory") where something is. `role` says which directory it is, e.g. "checkpoint directory
// (outputs.checkpoint.directory)".
void create_output_directory(const std::string& directory,
                             const std::string& role = "output directory");

// `path` under the run's output root: unchanged when it is absolute or the root is empty.
std::string joined_path(const std::string& root, const std::string& path);

// Writes `text` to `path` through "<path>.tmp" and a rename, the file synced to the disk before
// the rename and its directory after it (fsync). Throws std::runtime_error "cannot write
// '<path>': <reason>" (and removes the temporary file) on any failure.
void write_file_atomically(const std::string& path, const std::string& text);

// fsync of a written file, and of the directory that holds `path` (after a rename or a new file
// in it). Throw std::runtime_error naming the path on failure.
void sync_file(const std::string& path);
void sync_directory_of(const std::string& path);

// prefix + the step in at least 9 digits + extension: ("particles_", 1200, ".vtp") gives
// "particles_000001200.vtp", so that the files of a run sort by step.
std::string numbered_file_name(const std::string& prefix, long long step,
                               const std::string& extension);

// printf("%.17g"): 17 significant digits, enough for every double to read back to the same bits
// (and every float, converted to double, too).
std::string exact_decimal(double value);

// The fields of one CSV line (no quoting: our files hold names and numbers only).
std::vector<std::string> split_csv_line(const std::string& line);

// strtod of the whole of `text`; false when it is not one number.
bool parse_double(const std::string& text, double& value);

}  // namespace talus
