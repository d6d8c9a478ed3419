#include "core/metrics/sorted_order.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace {

// What SortedOrder must equal: std::sort of (value, index) pairs.
std::vector<int> ReferenceOrder(const std::vector<double>& values) {
  std::vector<std::pair<double, int>> pairs;
  for (size_t i = 0; i < values.size(); ++i)
    pairs.push_back({values[i], static_cast<int>(i)});
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> order;
  for (const auto& p : pairs) order.push_back(p.second);
  return order;
}

std::vector<int> Order(const std::vector<double>& values) {
  SortedOrderScratch scratch;
  std::vector<int> order;
  SortedOrder(values.data(), static_cast<int>(values.size()), 1, &scratch,
              &order);
  return order;
}

TEST(SortedOrderTest, MatchesSortedPairsOnMixedValues) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> pick(0, 5);
  for (int n : {0, 1, 2, 17, 1000, 8191}) {
    std::vector<double> values(n);
    for (double& v : values) {
      switch (pick(rng)) {
        case 0: v = normal(rng) * 1e-12; break;  // tiny, both signs
        case 1: v = normal(rng) * 1e9; break;    // large
        case 2: v = std::round(normal(rng) * 3); break;  // many ties
        case 3: v = -0.0; break;
        case 4: v = 0.0; break;
        default: v = normal(rng);
      }
    }
    if (n > 3) {
      values[1] = std::numeric_limits<double>::infinity();
      values[2] = -std::numeric_limits<double>::infinity();
      values[3] = std::numeric_limits<double>::denorm_min();
    }
    EXPECT_EQ(Order(values), ReferenceOrder(values)) << "n = " << n;
    // The values alone, sorted: the same values in std::sort's order,
    // -0 as +0.
    std::vector<double> want = values, sorted;
    std::sort(want.begin(), want.end());
    for (double& v : want) v = v == 0 ? 0.0 : v;
    SortedOrderScratch scratch;
    SortedValues(values.data(), n, &scratch, &sorted);
    ASSERT_EQ(sorted.size(), want.size());
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(sorted[i], want[i]) << i;
      EXPECT_FALSE(std::signbit(sorted[i]) && sorted[i] == 0) << i;
    }
  }
}

// A strided column (as a column of a row-major matrix) and reused scratch
// give the same order as a packed copy.
TEST(SortedOrderTest, StridedValuesAndReusedScratch) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  const int rows = 500, cols = 3;
  std::vector<double> matrix(rows * cols);
  for (double& v : matrix) v = normal(rng);
  SortedOrderScratch scratch;
  std::vector<int> order;
  for (int c = 0; c < cols; ++c) {
    std::vector<double> column(rows);
    for (int r = 0; r < rows; ++r) column[r] = matrix[r * cols + c];
    SortedOrder(matrix.data() + c, rows, cols, &scratch, &order);
    EXPECT_EQ(order, ReferenceOrder(column)) << "column " << c;
  }
}

// Values that all share their top bytes (one exponent and sign) skip
// those passes and still sort.
TEST(SortedOrderTest, SharedHighBytes) {
  std::vector<double> values;
  for (int i = 0; i < 300; ++i) values.push_back(1.0 + ((i * 37) % 300) * 1e-15);
  EXPECT_EQ(Order(values), ReferenceOrder(values));
}

}  // namespace
}  // namespace es
