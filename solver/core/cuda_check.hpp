// Checked CUDA calls: every runtime call goes through TALUS_CUDA_CHECK, which throws with the
// file, line, call and CUDA's message. TALUS_CUDA_LAUNCH_CHECK after each kernel launch checks
// the launch and, when the environment sets TALUS_CUDA_SYNC=1 (the debug switch), synchronises so
// that an asynchronous fault is reported at the launch that caused it.
#pragma once

#include <cuda_runtime.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace talus {

inline void cuda_check(cudaError_t status, const char* call, const char* file, int line) {
  if (status != cudaSuccess)
    throw std::runtime_error(std::string(file) + ":" + std::to_string(line) + ": " + call +
                             " failed: " + cudaGetErrorName(status) + ": " +
                             cudaGetErrorString(status));
}

inline bool cuda_sync_after_launch() {
  static const bool enabled = [] {
    const char* v = std::getenv("TALUS_CUDA_SYNC");
    return v != nullptr && std::string(v) == "1";
  }();
  return enabled;
}

}  // namespace talus

#define TALUS_CUDA_CHECK(call) ::talus::cuda_check((call), #call, __FILE__, __LINE__)
#define TALUS_CUDA_LAUNCH_CHECK()                                                        \
  do {                                                                                   \
    ::talus::cuda_check(cudaGetLastError(), "kernel launch", __FILE__, __LINE__);        \
    if (::talus::cuda_sync_after_launch())                                               \
      ::talus::cuda_check(cudaDeviceSynchronize(), "synchronise after launch", __FILE__, \
                          __LINE__);                                                     \
  } while (0)
