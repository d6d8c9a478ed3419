#ifndef EULERSPLAT_TESTS_CUDA_EXPECT_TWINS_NEAR_H_
#define EULERSPLAT_TESTS_CUDA_EXPECT_TWINS_NEAR_H_

// Device result against its CPU twin's, value by value, for the double
// device code that sums in another order than the CPU (fields, Euler
// chain): |got - want| <= tolerance * max(1, |want|); a NaN or an infinity
// must be matched by the same on the other side.

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace cuda {

inline void ExpectTwinsNear(const std::vector<double>& got,
                            const std::vector<double>& want, double tolerance,
                            const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  int reported = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    const bool same_kind = std::isnan(got[i]) == std::isnan(want[i]) &&
                           std::isinf(got[i]) == std::isinf(want[i]);
    const bool near =
        std::isfinite(want[i])
            ? std::abs(got[i] - want[i]) <=
                  tolerance * std::max(1.0, std::abs(want[i]))
            : !std::isfinite(got[i]) &&
                  (std::isnan(want[i]) || got[i] == want[i]);
    if ((same_kind && near) || reported >= 10) continue;
    ++reported;
    ADD_FAILURE() << what << "[" << i << "]: device " << got[i] << ", CPU "
                  << want[i];
  }
}

// Fails when every value is (near) zero: a check that compared zeros with
// zeros would pass whatever the device computed.
inline void ExpectSomeNonZero(const std::vector<double>& v,
                              const char* what) {
  double largest = 0;
  for (double x : v) {
    if (std::isfinite(x)) largest = std::max(largest, std::abs(x));
  }
  EXPECT_GT(largest, 1e-6) << what << " is all zero: nothing was checked";
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_TESTS_CUDA_EXPECT_TWINS_NEAR_H_
