#include "core/metrics/sorted_order.h"

#include <array>
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

}  // namespace

void SortedOrder(const double* values, int n, int stride,
                 SortedOrderScratch* scratch, std::vector<int>* order) {
  using Entry = SortedOrderScratch::Entry;
  order->resize(n);
  if (n == 0) return;
  std::vector<Entry>& in = scratch->entries;
  std::vector<Entry>& out = scratch->spare;
  in.resize(n);
  out.resize(n);
  for (int i = 0; i < n; ++i)
    in[i] = {OrderKey(values[static_cast<size_t>(i) * stride]), i};
  // Every byte's counts in one read, then one stable scatter per byte,
  // lowest first; a byte that every key shares (the exponent's, often) is
  // skipped.
  std::array<std::array<int, 257>, 8> start{};
  for (const Entry& e : in)
    for (int b = 0; b < 8; ++b) ++start[b][((e.key >> (8 * b)) & 255) + 1];
  for (int b = 0; b < 8; ++b) {
    const int shift = 8 * b;
    std::array<int, 257>& s = start[b];
    if (s[((in[0].key >> shift) & 255) + 1] == n) continue;
    for (int d = 0; d < 256; ++d) s[d + 1] += s[d];
    for (const Entry& e : in) out[s[(e.key >> shift) & 255]++] = e;
    std::swap(in, out);
  }
  for (int i = 0; i < n; ++i) (*order)[i] = in[i].index;
}

}  // namespace es
