#ifndef EULERSPLAT_TESTS_CUDA_HOST_ARRAYS_H_
#define EULERSPLAT_TESTS_CUDA_HOST_ARRAYS_H_

// Device and host arrays as vectors, and how far two of them differ: what
// the twin tests compare.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// `count` doubles at `device`, copied to the host.
inline std::vector<double> Fetch(const double* device, size_t count) {
  std::vector<double> host(count);
  CopyToHost(host.data(), device, count * sizeof(double));
  return host;
}

// `count` doubles at `host`.
inline std::vector<double> Copy(const double* host, size_t count) {
  return std::vector<double>(host, host + count);
}

// The largest |got - want| over the largest |want|.
inline double RelativeError(const std::vector<double>& got,
                            const std::vector<double>& want) {
  EXPECT_EQ(got.size(), want.size());
  double scale = 0, err = 0;
  for (double v : want) scale = std::max(scale, std::abs(v));
  for (size_t i = 0; i < want.size(); ++i)
    err = std::max(err, std::abs(got[i] - want[i]));
  return err / scale;
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_TESTS_CUDA_HOST_ARRAYS_H_
