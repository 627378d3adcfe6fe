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
