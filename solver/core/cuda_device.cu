#include "solver/core/cuda_device.hpp"

#include <cuda_runtime.h>

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

}  // namespace talus
