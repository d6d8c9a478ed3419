#ifndef EULERSPLAT_CORE_METRICS_SORTED_ORDER_H_
#define EULERSPLAT_CORE_METRICS_SORTED_ORDER_H_

#include <cstdint>
#include <vector>

namespace es {

// Scratch for SortedOrder, reused between calls.
struct SortedOrderScratch {
  struct Entry {
    uint32_t top;  // the top half of the value's bits, mapped so that
                   // they sort as values do
    int32_t index;
  };
  std::vector<Entry> entries, spare;
  std::vector<uint64_t> keys, spare_keys;
  std::vector<int> counts;  // per digit, its values' counts
};

// The indices 0 .. n - 1 of values[0], values[stride], ... in ascending
// order of value, equal values in index order (-0 equals +0): the order
// that std::sort gives on (value, index) pairs, by a least-significant-
// digit radix sort of the top half of the values' bits in O(n), then a
// comparison sort of each run that shares them (rare unless values tie),
// for the sliced Wasserstein distances' many sorts of thousands of values
// each. The values must not be NaN.
void SortedOrder(const double* values, int n, int stride,
                 SortedOrderScratch* scratch, std::vector<int>* order);

// values[0 .. n - 1] in ascending order, by the same sort on the values
// alone (half the data to move): for the side of a distance whose indices
// are not needed. A -0 comes out as +0.
void SortedValues(const double* values, int n, SortedOrderScratch* scratch,
                  std::vector<double>* sorted);

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_SORTED_ORDER_H_
