// Host/device annotation: one source for the CPU and the GPU backends.
#pragma once

#if defined(__CUDACC__)
#define TALUS_HD __host__ __device__
#define TALUS_DEVICE_CODE 1
#else
#define TALUS_HD
#endif

#if defined(__CUDA_ARCH__)
#define TALUS_ON_DEVICE 1
#endif

// Full unrolling of a loop with a compile-time trip count (nvcc's pragma in the device pass,
// GCC's on the host), so that arrays indexed by its counter stay in registers. nvcc's host pass
// gets neither: its front end rejects GCC's pragma and passes nvcc's on to g++, which warns.
#if defined(__CUDA_ARCH__)
#define TALUS_UNROLL _Pragma("unroll")
#elif defined(__CUDACC__)
#define TALUS_UNROLL
#elif defined(__GNUC__) && !defined(__clang__)
#define TALUS_UNROLL _Pragma("GCC unroll 64")
#else
#define TALUS_UNROLL
#endif
