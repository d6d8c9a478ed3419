#include "core/metrics/sorted_order.h"

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

uint64_t KeyOf(uint64_t key) { return key; }
uint64_t KeyOf(const SortedOrderScratch::Entry& e) { return e.key; }

double ValueOf(uint64_t key) {
  const uint64_t bits = (key >> 63) ? key & ~(uint64_t{1} << 63) : ~key;
  double v;
  std::memcpy(&v, &bits, sizeof(v));
  return v;
}

// A stable least-significant-digit radix sort of `in` by KeyOf, 11 bits a
// pass (six passes, not eight of a byte); all digits counted in one
// read, and a digit that every key shares (the exponent's, often)
// skipped. The result is left in *in.
template <typename T>
void RadixSort(std::vector<T>* in, std::vector<T>* out,
               std::vector<int>* counts) {
  constexpr int kBits = 11, kDigits = (64 + kBits - 1) / kBits;
  constexpr uint64_t kMask = (uint64_t{1} << kBits) - 1;
  constexpr size_t kSlots = kMask + 2;
  const size_t n = in->size();
  out->resize(n);
  counts->assign(kDigits * kSlots, 0);
  int* start = counts->data();
  for (const T& e : *in) {
    const uint64_t key = KeyOf(e);
    for (int d = 0; d < kDigits; ++d)
      ++start[d * kSlots + ((key >> (kBits * d)) & kMask) + 1];
  }
  for (int d = 0; d < kDigits; ++d) {
    const int shift = kBits * d;
    int* s = start + d * kSlots;
    if (s[((KeyOf((*in)[0]) >> shift) & kMask) + 1] == static_cast<int>(n))
      continue;
    for (uint64_t v = 0; v <= kMask; ++v) s[v + 1] += s[v];
    for (const T& e : *in) (*out)[s[(KeyOf(e) >> shift) & kMask]++] = e;
    std::swap(*in, *out);
  }
}

}  // namespace

void SortedOrder(const double* values, int n, int stride,
                 SortedOrderScratch* scratch, std::vector<int>* order) {
  order->resize(n);
  if (n == 0) return;
  std::vector<SortedOrderScratch::Entry>& in = scratch->entries;
  in.resize(n);
  for (int i = 0; i < n; ++i)
    in[i] = {OrderKey(values[static_cast<size_t>(i) * stride]), i};
  RadixSort(&in, &scratch->spare, &scratch->counts);
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
  for (int i = 0; i < n; ++i) (*sorted)[i] = ValueOf(keys[i]);
}

}  // namespace es
