// The names each output writes into its directory (trajectory.hpp, vtk_output.hpp,
// checkpoint.hpp), so that the scene loader can refuse an output path that would collide with
// another output's files and a new run can find an earlier run's files (run_directory.hpp).
// A name with the ".tmp" of a write in progress (output_files.hpp) counts as its final name.
#pragma once

#include <string>

namespace talus {

// The run lock's file name inside the output root (run_directory.hpp).
inline constexpr const char* kRunLockFile = ".talus.lock";

inline bool name_starts_with(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}
inline bool name_ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

inline std::string final_output_name(const std::string& name) {
  return name_ends_with(name, ".tmp") ? name.substr(0, name.size() - 4) : name;
}

// run.json and trajectory_<step>.csv or .h5.
inline bool trajectory_output_name(const std::string& name) {
  const std::string n = final_output_name(name);
  return n == "run.json" || (name_starts_with(n, "trajectory_") &&
                             (name_ends_with(n, ".csv") || name_ends_with(n, ".h5")));
}
// particles_<step>.vtp, walls_<step>.vtp, particles.pvd, walls.pvd.
inline bool vtk_output_name(const std::string& name) {
  const std::string n = final_output_name(name);
  return (name_starts_with(n, "particles") || name_starts_with(n, "walls")) &&
         (name_ends_with(n, ".vtp") || name_ends_with(n, ".pvd"));
}
// checkpoint_<step>.bin.
inline bool checkpoint_output_name(const std::string& name) {
  const std::string n = final_output_name(name);
  return name_starts_with(n, "checkpoint_") && name_ends_with(n, ".bin");
}

}  // namespace talus
