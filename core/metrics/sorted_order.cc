#include "core/metrics/sorted_order.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace es {
namespace {

// Unsigned keys in the values' order: positive doubles' bits already sort
// as their values, negative ones in reverse, below every positive one.
uint64_t OrderKey(double v) {
  if (v == 0) v = 0;  // -0 sorts as +0
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  return (bits >> 63) ? ~bits : bits | (uint64_t{1} << 63);
}

double ValueOf(uint64_t key) {
  const uint64_t bits = (key >> 63) ? key & ~(uint64_t{1} << 63) : ~key;
  double v;
  std::memcpy(&v, &bits, sizeof(v));
  return v;
}

// The radix passes sort by a key's top 32 bits (sign, exponent and 20
// bits of mantissa: values a millionth apart already differ there), in
// three passes of 11, 11 and 10 bits; the runs that share those bits are
// then put in full order.
uint32_t TopBits(uint64_t key) { return static_cast<uint32_t>(key >> 32); }
uint32_t TopBits(const SortedOrderScratch::Entry& e) { return e.top; }

// A stable least-significant-digit radix sort of `in` by TopBits; all
// digits counted in one read, and a digit that every key shares (the
// exponent's, often) skipped. The result is left in *in.
template <typename T>
void RadixSort(std::vector<T>* in, std::vector<T>* out,
               std::vector<int>* counts) {
  constexpr int kBits = 11, kDigits = 3;
  constexpr uint32_t kMask = (1u << kBits) - 1;
  constexpr size_t kSlots = kMask + 2;
  const size_t n = in->size();
  out->resize(n);
  counts->assign(kDigits * kSlots, 0);
  int* start = counts->data();
  for (const T& e : *in) {
    const uint32_t top = TopBits(e);
    for (int d = 0; d < kDigits; ++d)
      ++start[d * kSlots + ((top >> (kBits * d)) & kMask) + 1];
  }
  for (int d = 0; d < kDigits; ++d) {
    const int shift = kBits * d;
    int* s = start + d * kSlots;
    if (s[((TopBits((*in)[0]) >> shift) & kMask) + 1] == static_cast<int>(n))
      continue;
    for (uint32_t v = 0; v <= kMask; ++v) s[v + 1] += s[v];
    for (const T& e : *in) (*out)[s[(TopBits(e) >> shift) & kMask]++] = e;
    std::swap(*in, *out);
  }
}

// Sorts each run of elements with equal TopBits by `less`.
template <typename T, typename Less>
void OrderRuns(std::vector<T>* v, Less less) {
  const size_t n = v->size();
  for (size_t begin = 0; begin < n;) {
    size_t end = begin + 1;
    const uint32_t top = TopBits((*v)[begin]);
    while (end < n && TopBits((*v)[end]) == top) ++end;
    if (end - begin > 1) std::sort(v->begin() + begin, v->begin() + end, less);
    begin = end;
  }
}

}  // namespace

void SortedOrder(const double* values, int n, int stride,
                 SortedOrderScratch* scratch, std::vector<int>* order) {
  order->resize(n);
  if (n == 0) return;
  std::vector<SortedOrderScratch::Entry>& in = scratch->entries;
  in.resize(n);
  const auto key = [&](int i) {
    return OrderKey(values[static_cast<size_t>(i) * stride]);
  };
  for (int i = 0; i < n; ++i) in[i] = {TopBits(key(i)), i};
  RadixSort(&in, &scratch->spare, &scratch->counts);
  // Equal values keep their index order, as the whole sort is stable.
  using Entry = SortedOrderScratch::Entry;
  OrderRuns(&in, [&](const Entry& a, const Entry& b) {
    const uint64_t ka = key(a.index), kb = key(b.index);
    return ka < kb || (ka == kb && a.index < b.index);
  });
  for (int i = 0; i < n; ++i) (*order)[i] = in[i].index;
}

void SortedValues(const double* values, int n, SortedOrderScratch* scratch,
                  std::vector<double>* sorted) {
  sorted->resize(n);
  if (n == 0) return;
  std::vector<uint64_t>& keys = scratch->keys;
  keys.resize(n);
  for (int i = 0; i < n; ++i) keys[i] = OrderKey(values[i]);
  RadixSort(&keys, &scratch->spare_keys, &scratch->counts);
  OrderRuns(&keys, std::less<uint64_t>());
  for (int i = 0; i < n; ++i) (*sorted)[i] = ValueOf(keys[i]);
}

}  // namespace es
