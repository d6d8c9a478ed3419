#ifndef EULERSPLAT_TESTS_CUDA_EXPECT_FRAMES_CLOSE_H_
#define EULERSPLAT_TESTS_CUDA_EXPECT_FRAMES_CLOSE_H_

// A frame the device rendered against the CPU's, for the float
// rasterizers that draw the same splats with their own kernels: at most
// 0.5% of the values off by more than 2e-5 of the largest |want|, none by
// more than 0.05 of it (a NaN counts as off).

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace cuda {

inline void ExpectFramesClose(const std::vector<double>& got,
                              const std::vector<double>& want) {
  ASSERT_EQ(got.size(), want.size());
  double scale = 0;
  for (double v : want) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0);
  size_t off = 0;
  double largest = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    const double d = std::abs(got[i] - want[i]) / scale;
    if (!(d <= 2e-5)) ++off;  // NaN counts
    if (!(d <= largest)) largest = d;
  }
  EXPECT_LE(off, 0.005 * want.size())
      << off << " of " << want.size() << " values off (largest " << largest
      << ")";
  EXPECT_LE(largest, 0.05);
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_TESTS_CUDA_EXPECT_FRAMES_CLOSE_H_
