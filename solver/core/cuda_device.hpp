// Whether this process can use a CUDA device. Host-facing (no CUDA types); defined in
// cuda_device.cu, which exists only in CUDA builds (talus_cuda).
#pragma once

#include <cstddef>
#include <string>

namespace talus {

// True when a CUDA device can be used; otherwise `reason` (if given) says why not.
bool cuda_device_available(std::string* reason = nullptr);

// Bytes of the current device in use (total less free, cudaMemGetInfo): every allocation of
// every context on it, with the driver's own (kernels' local memory, graphs) and the allocator's
// rounding. A difference of two readings is what a piece of work holds on the device.
std::size_t cuda_device_used_bytes();

}  // namespace talus
