#ifndef EULERSPLAT_TESTS_CUDA_REQUIRE_GPU_H_
#define EULERSPLAT_TESTS_CUDA_REQUIRE_GPU_H_

#include <string>

#include <gtest/gtest.h>

#include "core/base/cuda/cuda_error.h"

// Skips the current test, saying why and what goes unchecked, when no CUDA
// device can be used (every CUDA test on a machine without a GPU).
#define ES_REQUIRE_GPU(what)                                          \
  do {                                                                \
    std::string why;                                                  \
    if (!::es::cuda::CudaDeviceAvailable(&why))                       \
      GTEST_SKIP() << "no usable CUDA device (" << why << "): the "   \
                   << (what) << " is not checked here";               \
  } while (0)

#endif  // EULERSPLAT_TESTS_CUDA_REQUIRE_GPU_H_
