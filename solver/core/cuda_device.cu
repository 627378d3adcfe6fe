#include "solver/core/cuda_device.hpp"

#include <cuda_runtime.h>

#include "solver/core/cuda_check.hpp"

namespace talus {

bool cuda_device_available(std::string* reason) {
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess || count == 0) {
    if (reason)
      *reason = status != cudaSuccess
                    ? std::string("no usable CUDA device: ") + cudaGetErrorString(status)
                    : std::string("no CUDA device present");
    cudaGetLastError();  // clear the sticky error of a failed query
    return false;
  }
  return true;
}

std::size_t cuda_device_used_bytes() {
  std::size_t free = 0, total = 0;
  TALUS_CUDA_CHECK(cudaMemGetInfo(&free, &total));
  return total - free;
}

}  // namespace talus
