#ifndef EULERSPLAT_TESTS_MAX_ABS_DIFF_H_
#define EULERSPLAT_TESTS_MAX_ABS_DIFF_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace es {

// The largest |a - b| (`diff`) and the largest |b| (`scale`) over two arrays
// of equal size, from which each test forms its relative difference.
struct AbsDiff {
  double diff = 0;
  double scale = 0;
};

inline AbsDiff MaxAbsDiff(const std::vector<double>& a,
                          const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  AbsDiff d;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    d.diff = std::max(d.diff, std::abs(a[i] - b[i]));
    d.scale = std::max(d.scale, std::abs(b[i]));
  }
  return d;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_MAX_ABS_DIFF_H_
