#ifndef EULERSPLAT_CORE_RENDER_RADIX_SORT_H_
#define EULERSPLAT_CORE_RENDER_RADIX_SORT_H_

#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace es {

// The bits of a double as an unsigned key: for doubles >= 0 (the
// rasterizer's depths, all past the near plane) the keys order as the
// values.
inline uint64_t NonNegativeDoubleKey(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  return bits;
}

// Buffers RadixSortByKey reuses from call to call.
template <typename Item>
struct RadixSortScratch {
  std::vector<Item> items;
  std::vector<size_t> count;
};

// Sorts *items by their `uint64_t key` member, ascending and stable (equal
// keys keep their order), by least-significant-digit radix sort on 11-bit
// digits; a digit all keys share is skipped (a float depth widened to
// double leaves the low 29 bits zero: 4 passes instead of 6). The items
// move with their keys, so whatever they carry is read in sorted order
// afterwards without a random lookup.
template <typename Item>
void RadixSortByKey(std::vector<Item>* items,
                    RadixSortScratch<Item>* scratch) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kDigits = 6;
  const size_t n = items->size();
  if (n < 2) return;
  // All digits' histograms in one read of the keys.
  std::vector<size_t>& count = scratch->count;
  count.assign(static_cast<size_t>(kDigits) * kBuckets, 0);
  for (const Item& it : *items)
    for (int d = 0; d < kDigits; ++d)
      ++count[d * kBuckets + ((it.key >> (kBits * d)) & (kBuckets - 1))];
  scratch->items.resize(n);
  std::vector<Item>* from = items;
  std::vector<Item>* to = &scratch->items;
  for (int d = 0; d < kDigits; ++d) {
    size_t* c = &count[static_cast<size_t>(d) * kBuckets];
    const uint64_t digit0 = ((*from)[0].key >> (kBits * d)) & (kBuckets - 1);
    if (c[digit0] == n) continue;  // every key has this digit
    size_t offset = 0;
    for (int b = 0; b < kBuckets; ++b) {
      const size_t k = c[b];
      c[b] = offset;
      offset += k;
    }
    for (const Item& it : *from)
      (*to)[c[(it.key >> (kBits * d)) & (kBuckets - 1)]++] = it;
    std::swap(from, to);
  }
  if (from != items) items->swap(*from);
}

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RADIX_SORT_H_
