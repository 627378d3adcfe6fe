// Whether this process can use a CUDA device. Host-facing (no CUDA types); defined in
// cuda_device.cu, which exists only in CUDA builds (talus_cuda).
#pragma once

#include <string>

namespace talus {

// True when a CUDA device can be used; otherwise `reason` (if given) says why not.
bool cuda_device_available(std::string* reason = nullptr);

}  // namespace talus
