// Running the built `talus` binary as a separate process, for the command-line tests: no shell
// (arguments pass verbatim), stdout and stderr captured, the exit status decoded.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace talus_test {

struct ProcessResult {
  int exit_code = -1;
  std::string out, err;
};

// A fresh, empty directory <build>/<group>/<name> for one test's files.
inline std::string fresh_directory(const std::string& group, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(TALUS_BINARY_DIR) / group / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// `text` written to <dir>/scene.yaml; returns that path.
inline std::string write_scene(const std::string& dir, const std::string& text) {
  const std::string path = dir + "/scene.yaml";
  std::ofstream(path) << text;
  return path;
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs <build>/talus with `args` (no shell: arguments pass verbatim), stdout and stderr captured in
// temporary files so that neither can fill a pipe and stall the child. `address_space_bytes`
// (0: none) caps the child's virtual memory (RLIMIT_AS), so that an allocation fails there.
inline ProcessResult run_talus(const std::vector<std::string>& args,
                               rlim_t address_space_bytes = 0) {
  char out_path[] = "/tmp/talus_cli_out_XXXXXX";
  char err_path[] = "/tmp/talus_cli_err_XXXXXX";
  const int out_fd = mkstemp(out_path);
  const int err_fd = mkstemp(err_path);
  ProcessResult run;
  if (out_fd < 0 || err_fd < 0) {
    ADD_FAILURE() << "cannot create temporary files";
    return run;
  }
  const std::string binary = TALUS_BINARY_DIR "/talus";
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(binary.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (address_space_bytes > 0) {
      const rlimit limit{address_space_bytes, address_space_bytes};
      if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(126);
    }
    dup2(out_fd, STDOUT_FILENO);
    dup2(err_fd, STDERR_FILENO);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  close(out_fd);
  close(err_fd);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.out = read_file(out_path);
  run.err = read_file(err_path);
  unlink(out_path);
  unlink(err_path);
  return run;
}

}  // namespace talus_test
