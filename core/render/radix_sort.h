#ifndef EULERSPLAT_CORE_RENDER_RADIX_SORT_H_
#define EULERSPLAT_CORE_RENDER_RADIX_SORT_H_

#include <omp.h>

#include <algorithm>
#include <cstddef>
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
  std::vector<size_t> count;  // per thread and bucket
};

// Sorts *items by their `uint64_t key` member, ascending and stable (equal
// keys keep their order), by least-significant-digit radix sort on 11-bit
// digits; a digit all keys share is skipped (a float depth widened to
// double leaves the low 29 bits zero: 4 passes instead of 6). The items
// move with their keys, so whatever they carry is read in sorted order
// afterwards without a random lookup. Up to `threads` threads share each
// pass: each counts and then moves one contiguous run of the items, after
// the runs in front of it in every bucket, so the result is the same for
// any thread count.
template <typename Item>
void RadixSortByKey(std::vector<Item>* items, RadixSortScratch<Item>* scratch,
                    int threads = 1) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kDigits = 6;
  const size_t n = items->size();
  if (n < 2) return;
  threads = std::max(1, threads);
  // The bits in which some key differs from the first.
  const uint64_t key0 = (*items)[0].key;
  uint64_t varying = 0;
  const Item* in = items->data();
#pragma omp parallel for num_threads(threads) reduction(| : varying)
  for (size_t i = 0; i < n; ++i) varying |= in[i].key ^ key0;
  scratch->items.resize(n);
  std::vector<size_t>& count = scratch->count;
  count.resize(static_cast<size_t>(threads) * kBuckets);
  std::vector<Item>* from = items;
  std::vector<Item>* to = &scratch->items;
  for (int d = 0; d < kDigits; ++d) {
    const int shift = kBits * d;
    if (((varying >> shift) & (kBuckets - 1)) == 0) continue;
    const Item* src = from->data();
    Item* dst = to->data();
#pragma omp parallel num_threads(threads)
    {
      const int t = omp_get_thread_num(), nt = omp_get_num_threads();
      const size_t i0 = n * t / nt, i1 = n * (t + 1) / nt;
      size_t* c = &count[static_cast<size_t>(t) * kBuckets];
      std::fill(c, c + kBuckets, size_t{0});
      for (size_t i = i0; i < i1; ++i)
        ++c[(src[i].key >> shift) & (kBuckets - 1)];
#pragma omp barrier
#pragma omp single
      {
        // Bucket by bucket, run by run: counts become start offsets.
        size_t offset = 0;
        for (int b = 0; b < kBuckets; ++b) {
          for (int r = 0; r < nt; ++r) {
            size_t& k = count[static_cast<size_t>(r) * kBuckets + b];
            const size_t run = k;
            k = offset;
            offset += run;
          }
        }
      }
      for (size_t i = i0; i < i1; ++i)
        dst[c[(src[i].key >> shift) & (kBuckets - 1)]++] = src[i];
    }
    std::swap(from, to);
  }
  if (from != items) items->swap(*from);
}

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RADIX_SORT_H_
