#ifndef EULERSPLAT_TESTS_EXPECT_SAME_GAUSSIANS_H_
#define EULERSPLAT_TESTS_EXPECT_SAME_GAUSSIANS_H_

#include <gtest/gtest.h>

#include "core/model/gaussians.h"

namespace es {

// Expects a and b to hold the same SH degree and, bit for bit, the same
// values in every array of kGaussianArrays.
inline void ExpectSameGaussians(const GaussianSet& a, const GaussianSet& b) {
  ASSERT_EQ(a.sh_degree, b.sh_degree);
  ASSERT_EQ(a.size(), b.size());
  for (const GaussianArray& array : kGaussianArrays)
    EXPECT_EQ(a.*array.values, b.*array.values) << array.name;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_EXPECT_SAME_GAUSSIANS_H_
