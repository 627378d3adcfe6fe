// The GPU tests' first line: skips the test, with the reason, where no CUDA device is usable
// (cuda_device_available), so that a machine without one reports them skipped, not failed.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "solver/core/cuda_device.hpp"

#define SKIP_WITHOUT_GPU()                                          \
  do {                                                              \
    std::string why;                                                \
    if (!::talus::cuda_device_available(&why)) GTEST_SKIP() << why; \
  } while (0)
