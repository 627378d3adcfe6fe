#include "solver/io/run_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <random>

#include "solver/io/output_files.hpp"
#include "solver/io/output_names.hpp"

namespace talus {

namespace fs = std::filesystem;

namespace {

std::string root_or_here(const std::string& root) {
  return root.empty() ? "." : root;
}

void add_matching(const std::string& directory, const std::function<bool(const std::string&)>& ours,
                  std::vector<std::string>& found) {
  std::error_code error;
  if (!fs::is_directory(directory, error)) return;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, error)) {
    if (entry.is_directory(error)) continue;
    if (ours(entry.path().filename().string())) found.push_back(entry.path().string());
  }
}

void add_if_present(const std::string& file, std::vector<std::string>& found) {
  std::error_code error;
  for (const std::string& path : {file, file + ".tmp"})
    if (fs::exists(fs::symlink_status(path, error))) found.push_back(path);
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace

OutputLock::OutputLock(const std::string& root, const std::string& holder) {
  const std::string directory = root_or_here(root);
  create_output_directory(directory);
  const std::string path = directory + "/" + kRunLockFile;
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw std::runtime_error("cannot create the run lock '" + path + "': " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int code = errno;
    std::string other(512, '\0');
    const ssize_t got = ::pread(fd_, other.data(), other.size(), 0);
    other.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
    while (!other.empty() && (other.back() == '\n' || other.back() == '\0')) other.pop_back();
    ::close(fd_);
    fd_ = -1;
    if (code != EWOULDBLOCK)
      throw std::runtime_error("cannot lock '" + path + "': " + std::strerror(code));
    throw OutputConflict(
        directory + " is in use by another talus run (" +
        (other.empty() ? std::string("its holder has not said who it is yet") : other) +
        "); wait for it to end, or give this run another output directory");
  }
  // Who holds it, for the message of the next one that tries; failing to say so is no reason to
  // stop the run.
  const std::string text = holder + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(fd_, text.data(), text.size(), 0);
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

OutputLock::OutputLock(OutputLock&& other) noexcept : fd_(other.fd_) {
  other.fd_ = -1;
}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

std::string new_run_id() {
  std::random_device device;
  const auto ticks =
      static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
  std::uint64_t id = ticks ^ (static_cast<std::uint64_t>(::getpid()) << 40);
  id ^= (static_cast<std::uint64_t>(device()) << 32) | device();
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(id));
  return text;
}

std::string run_holder_description(const std::string& run_id, const std::string& scene_file) {
  char host[256] = "an unknown host";
  if (::gethostname(host, sizeof host - 1) != 0) std::strcpy(host, "an unknown host");
  host[sizeof host - 1] = '\0';
  return "pid " + std::to_string(::getpid()) + " on " + host + ", started " + utc_now() + ", run " +
         run_id + ", scene " + scene_file;
}

std::vector<std::string> existing_outputs(const Scene& scene, const std::string& root) {
  std::vector<std::string> found;
  const Outputs& o = scene.outputs;
  if (o.trajectories)
    add_matching(joined_path(root, o.trajectories->directory), trajectory_output_name, found);
  if (o.probes) add_if_present(joined_path(root, o.probes->file), found);
  if (o.vtk) add_matching(joined_path(root, o.vtk->directory), vtk_output_name, found);
  if (o.checkpoint)
    add_matching(joined_path(root, o.checkpoint->directory), checkpoint_output_name, found);
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  return found;
}

OutputLock claim_output_root(const Scene& scene, const std::string& root, const std::string& run_id,
                             bool resume, bool overwrite) {
  const Outputs& o = scene.outputs;
  if (!o.trajectories && !o.probes && !o.vtk && !o.checkpoint) return {};  // writes nothing
  OutputLock lock(root, run_holder_description(run_id, scene.file));
  // A directory where the probe file goes is no earlier run's output: nothing may remove it.
  std::error_code error;
  if (o.probes && fs::is_directory(joined_path(root, o.probes->file), error))
    throw OutputPathError("the probe file (outputs.probes.file) '" +
                          joined_path(root, o.probes->file) +
                          "' is a directory; remove it or give the probe file another name");
  if (resume) return lock;
  const std::vector<std::string> earlier = existing_outputs(scene, root);
  if (earlier.empty()) return lock;
  if (!overwrite) {
    std::string some;
    // Named inside the root, which the message names first.
    const std::string inside = root.empty() || root.back() == '/' ? root : root + "/";
    for (std::size_t k = 0; k < earlier.size() && k < 3; ++k) {
      const std::string& path = earlier[k];
      some += (k ? ", " : "") +
              (!inside.empty() && path.rfind(inside, 0) == 0 ? path.substr(inside.size()) : path);
    }
    if (earlier.size() > 3) some += ", ...";
    throw OutputConflict(
        root_or_here(root) + " holds " + std::to_string(earlier.size()) + " output file" +
        (earlier.size() == 1 ? "" : "s") + " of an earlier run (" + some +
        "); a new run would mix its outputs with them. Give it another output directory "
        "(--output), continue the earlier run with 'talus run --resume' if it was interrupted, "
        "or pass --overwrite to remove those files first");
  }
  for (const std::string& path : earlier) {
    std::error_code error;
    fs::remove(path, error);
    if (error)
      throw std::runtime_error("--overwrite: cannot remove '" + path + "': " + error.message());
  }
  return lock;
}

}  // namespace talus
