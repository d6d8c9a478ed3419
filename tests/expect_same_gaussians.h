#ifndef EULERSPLAT_TESTS_EXPECT_SAME_GAUSSIANS_H_
#define EULERSPLAT_TESTS_EXPECT_SAME_GAUSSIANS_H_

#include <vector>

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

// Every array of kGaussianArrays, one after the other: the whole set's
// values, to compare with a tolerance.
inline std::vector<double> AllGaussianValues(const GaussianSet& g) {
  std::vector<double> out;
  for (const GaussianArray& array : kGaussianArrays)
    out.insert(out.end(), (g.*array.values).begin(), (g.*array.values).end());
  return out;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_EXPECT_SAME_GAUSSIANS_H_
