// The rasterizer's depth sort (core/render/radix_sort.h) against
// std::stable_sort.

#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/render/radix_sort.h"

namespace es {
namespace {

struct Item {
  uint64_t key;
  int index;
};

std::vector<Item> Sorted(std::vector<Item> v, int threads = 1) {
  RadixSortScratch<Item> scratch;
  RadixSortByKey(&v, &scratch, threads);
  return v;
}

std::vector<Item> Expected(std::vector<Item> v) {
  std::stable_sort(v.begin(), v.end(), [](const Item& a, const Item& b) {
    return a.key < b.key;
  });
  return v;
}

void ExpectSame(const std::vector<Item>& a, const std::vector<Item>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].key, b[i].key) << i;
    EXPECT_EQ(a[i].index, b[i].index) << i;
  }
}

TEST(RadixSortTest, DepthsSortLikeStableSortWithTiesInIndexOrder) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(0.01, 50.0);
  std::vector<Item> items;
  for (int i = 0; i < 20000; ++i) {
    // Many equal depths (float-rounded, and exact repeats), and the full
    // double range of others.
    double depth = uni(rng);
    if (i % 3 == 0) depth = static_cast<float>(depth);
    if (i % 7 == 0) depth = 4.0;
    items.push_back({NonNegativeDoubleKey(depth), i});
  }
  const std::vector<Item> expected = Expected(items);
  // Split into runs, ties across the runs' borders keep their order too.
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    ExpectSame(Sorted(items, threads), expected);
  }
}

TEST(RadixSortTest, FullKeysSharedDigitsAndTinyInputs) {
  std::mt19937_64 rng(9);
  std::vector<Item> items;
  for (int i = 0; i < 5000; ++i) items.push_back({rng(), i});
  ExpectSame(Sorted(items), Expected(items));
  ExpectSame(Sorted(items, 2), Expected(items));
  // Keys that differ only in their top digit, or only in the lowest.
  for (int i = 0; i < 5000; ++i)
    items[i].key = (i % 2 ? 1ull << 63 : 0) | (i % 5 == 0 ? 1 : 0);
  ExpectSame(Sorted(items), Expected(items));
  ExpectSame(Sorted(items, 2), Expected(items));
  ExpectSame(Sorted({}), {});
  ExpectSame(Sorted({{3, 0}}), {{3, 0}});
  ExpectSame(Sorted({{3, 0}, {1, 1}}, 4), {{1, 1}, {3, 0}});
  ExpectSame(Sorted({{3, 0}, {3, 1}, {2, 2}}), {{2, 2}, {3, 0}, {3, 1}});
}

}  // namespace
}  // namespace es
