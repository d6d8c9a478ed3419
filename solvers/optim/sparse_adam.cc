#include "solvers/optim/sparse_adam.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <glog/logging.h>

#include "core/fields/gradient_chunks.h"
#include "core/base/stage_profile.h"

namespace es {
namespace {

// Values per chunk: 64 doubles, one cache line's worth eight times over;
// producers' chunk flags use the same.
constexpr int kChunk = kGradientChunk;
// Below this many chunks a parallel region costs more than it saves.
constexpr int kMinParallelChunks = 1024;
// The same for Step, whose per-chunk work (a square root and a division
// per value) is several times a scan's: the fields' active chunks (a few
// hundred to a few thousand per block) are split between threads.
constexpr int kMinParallelStepChunks = 128;

int NumChunks(int size) { return (size + kChunk - 1) / kChunk; }

// Whether any of a[0..n) is non-zero (-0 counts as zero) and whether all
// are finite (x * 0 is 0 for finite x, NaN otherwise), in two branch-free
// passes that vectorize even for SSE2: an OR of the bits without the sign,
// and eight lanes of sums.
void Inspect(const double* a, int n, bool* nonzero, bool* finite) {
  uint64_t bits = 0;
  for (int i = 0; i < n; ++i) {
    uint64_t x;
    std::memcpy(&x, a + i, sizeof(x));
    bits |= x << 1;
  }
  double lanes[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    for (int l = 0; l < 8; ++l) lanes[l] += a[i + l] * 0.0;
  }
  double sum = 0.0;
  for (; i < n; ++i) sum += a[i] * 0.0;
  for (int l = 0; l < 8; ++l) sum += lanes[l];
  *nonzero = bits != 0;
  *finite = sum == 0.0;
}

}  // namespace

SparseAdam::SparseAdam(int size, const AdamOptions& options)
    : options_(options),
      m_(size, 0.0),
      v_(size, 0.0),
      live_(NumChunks(size), 0),
      touched_(NumChunks(size), 0) {}

void SparseAdam::Restore(std::vector<double> m, std::vector<double> v) {
  CHECK_EQ(m.size(), m_.size());
  CHECK_EQ(v.size(), v_.size());
  m_ = std::move(m);
  v_ = std::move(v);
  const int chunks = NumChunks(size());
  for (int c = 0; c < chunks; ++c) {
    const int begin = c * kChunk, end = std::min(size(), begin + kChunk);
    bool m_nonzero, v_nonzero, finite;
    Inspect(&m_[begin], end - begin, &m_nonzero, &finite);
    Inspect(&v_[begin], end - begin, &v_nonzero, &finite);
    live_[c] = m_nonzero || v_nonzero;
  }
}

bool SparseAdam::ScanChunk(const double* grad, int c) {
  const int begin = c * kChunk, end = std::min(size(), begin + kChunk);
  bool nonzero, finite;
  Inspect(grad + begin, end - begin, &nonzero, &finite);
  touched_[c] = nonzero;
  return finite;
}

bool SparseAdam::ScanGradient(const double* grad) {
  const int chunks = NumChunks(size());
  bool all_finite = true;
#pragma omp parallel for if (chunks >= kMinParallelChunks) \
    schedule(static) reduction(&& : all_finite)
  for (int c = 0; c < chunks; ++c) {
    all_finite = ScanChunk(grad, c) && all_finite;
  }
  return all_finite;
}

bool SparseAdam::ScanFlagged(const double* grad) {
  const int chunks = NumChunks(size());
  flagged_.clear();
  for (int c = 0; c < chunks; ++c) {
    if (touched_[c]) flagged_.push_back(c);
  }
  const int flagged = static_cast<int>(flagged_.size());
  bool all_finite = true;
#pragma omp parallel for if (flagged >= kMinParallelChunks) \
    schedule(static) reduction(&& : all_finite)
  for (int k = 0; k < flagged; ++k) {
    const int c = flagged_[k];
    all_finite = ScanChunk(grad, c) && all_finite;
  }
  return all_finite;
}

void SparseAdam::ClearGradient(double* grad) {
  const int chunks = NumChunks(size());
  for (int c = 0; c < chunks; ++c) {
    if (!touched_[c]) continue;
    touched_[c] = 0;
    const int begin = c * kChunk, end = std::min(size(), begin + kChunk);
    std::fill(grad + begin, grad + end, 0.0);
  }
}

bool SparseAdam::Step(int64_t t, double lr, double* grad, double* x) {
  ScopedStage timer(Stage::kAdam);
  const AdamStep adam(options_, t, lr);
  const int chunks = NumChunks(size());
  active_.clear();
  for (int c = 0; c < chunks; ++c) {
    // A chunk with zero gradient and zero moments would not change; one
    // that is live but whose moments have decayed to zero changes by
    // exactly zero, as AdamUpdate leaves it.
    if (live_[c] || touched_[c]) active_.push_back(c);
  }
  const int active = static_cast<int>(active_.size());
  bool all_finite = true;
#pragma omp parallel for if (active >= kMinParallelStepChunks) \
    schedule(static) reduction(&& : all_finite)
  for (int k = 0; k < active; ++k) {
    const int c = active_[k];
    const int begin = c * kChunk, end = std::min(size(), begin + kChunk);
    adam.Update(begin, end, grad, m_.data(), v_.data(), x);
    if (touched_[c]) std::fill(grad + begin, grad + end, 0.0);
    live_[c] = 1;
    bool nonzero, finite;
    Inspect(x + begin, end - begin, &nonzero, &finite);
    all_finite = all_finite && finite;
  }
  std::fill(touched_.begin(), touched_.end(), 0);
  return all_finite;
}

}  // namespace es
