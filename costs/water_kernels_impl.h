// The water losses' kernels (costs/water_kernels.h). Included only by
// water_kernels_{sse2,avx2,avx512}.cc, each compiled for its
// instruction set with ES_WATER_KERNELS_ISA naming its namespace and
// -ffp-contract=off (CMakeLists.txt), so that every set rounds as the
// others do. Everything here has internal linkage and calls no
// out-of-line library code (memcpy aside), so nothing compiled for AVX2 /
// AVX-512 runs on a CPU without it.
//
// Every blur pass is a gather: an output sums its terms from 0.0 in the
// order in which a scatter into zeroed outputs would add them, and blocks
// of outputs stay in vector registers over all their taps (one store per
// output, not one per tap).

#if !defined(ES_WATER_KERNELS_ISA)
#error "define ES_WATER_KERNELS_ISA before this header"
#endif

#include <cstddef>
#include <type_traits>

#include "core/base/simd_vector.h"
#include "costs/water_kernels.h"

namespace es {
namespace ES_WATER_KERNELS_ISA {
namespace {

// Independent sums in flight: enough to hide the adds' latency.
constexpr int kAccumulators = 8;
constexpr int kBlock = kLanes * kAccumulators;

inline int Min(int a, int b) { return a < b ? a : b; }
inline int Max(int a, int b) { return a > b ? a : b; }
inline int Clamp(int v, int lo, int hi) { return Min(Max(v, lo), hi); }

// out[x] = sum_t k[t] src[t][x] over t = 0 .. terms - 1 in order, for x in
// [begin, end).
void SumTerms(const double* const* src, const double* k, int terms,
              int begin, int end, double* out) {
  int x = begin;
  for (; x + kBlock <= end; x += kBlock) {
    Vec acc[kAccumulators];
    for (Vec& a : acc) a = Vec{};
    for (int t = 0; t < terms; ++t) {
      const double kt = k[t];
      const double* s = src[t] + x;
      for (int a = 0; a < kAccumulators; ++a)
        acc[a] += kt * Load(s + a * kLanes);
    }
    __builtin_memcpy(out + x, acc, sizeof(acc));
  }
  for (; x < end; ++x) {
    double acc = 0.0;
    for (int t = 0; t < terms; ++t) acc += k[t] * src[t][x];
    out[x] = acc;
  }
}

// Each row through a copy padded with its clamped ends.
void BlurRows(const double* in, int w, int h, const double* k, int r,
              const WaterFilterScratch& s, double* out) {
  const int taps = 2 * r + 1;
  double* line = s.line;
  for (int j = 0; j < taps; ++j) s.sources[j] = line + j;
  for (int y = 0; y < h; ++y) {
    const double* row = in + static_cast<size_t>(y) * w;
    for (int m = 0; m < r; ++m) {
      line[m] = row[0];
      line[r + w + m] = row[w - 1];
    }
    __builtin_memcpy(line + r, row, sizeof(double) * w);
    SumTerms(s.sources, k, taps, 0, w, out + static_cast<size_t>(y) * w);
  }
}

// Output row y gathers the rows clamp(y + j - r).
void BlurColumns(const double* in, int w, int h, const double* k, int r,
                 const WaterFilterScratch& s, double* out) {
  const int taps = 2 * r + 1;
  for (int y = 0; y < h; ++y) {
    for (int j = 0; j < taps; ++j)
      s.sources[j] = in + static_cast<size_t>(Clamp(y + j - r, 0, h - 1)) * w;
    SumTerms(s.sources, k, taps, 0, w, out + static_cast<size_t>(y) * w);
  }
}

// The rows' adjoint as a scatter of a row into a zeroed padded line builds
// it: pad[q] = sum over taps j in order of k[j] g[q - j] (0 <= q - j < w);
// g_in is pad[r .. r + w) with the ends then folded onto the border
// pixels.
double PaddedAdjointAt(const double* g, int q, int w, const double* k,
                       int r) {
  double acc = 0.0;
  for (int j = Max(0, q - w + 1); j <= Min(2 * r, q); ++j)
    acc += k[j] * g[q - j];
  return acc;
}

void BlurRowsAdjoint(const double* g_out, int w, int h, const double* k,
                     int r, const WaterFilterScratch& s, double* g_in) {
  const int taps = 2 * r + 1;
  // Where pad[x + r] has all its taps and x is no border pixel.
  const int begin = Min(Max(r, 1), w);
  const int end = Max(begin, Min(w - r, w - 1));
  for (int y = 0; y < h; ++y) {
    const double* g = g_out + static_cast<size_t>(y) * w;
    double* dst = g_in + static_cast<size_t>(y) * w;
    for (int j = 0; j < taps; ++j) s.sources[j] = g + r - j;
    SumTerms(s.sources, k, taps, begin, end, dst);
    for (int x = 0; x < begin; ++x)
      dst[x] = PaddedAdjointAt(g, x + r, w, k, r);
    for (int x = end; x < w; ++x)
      dst[x] = PaddedAdjointAt(g, x + r, w, k, r);
    for (int m = 0; m < r; ++m) {
      dst[0] += PaddedAdjointAt(g, m, w, k, r);
      dst[w - 1] += PaddedAdjointAt(g, w + r + m, w, k, r);
    }
  }
}

// The columns' adjoint as a scatter of rows i = 0 .. h - 1 in order, each
// through its taps j in order, into the zeroed rows clamp(i + j - r)
// builds it.
void BlurColumnsAdjoint(const double* g_out, int w, int h, const double* k,
                        int r, const WaterFilterScratch& s, double* g_in) {
  for (int p = 0; p < h; ++p) {
    int terms = 0;
    for (int i = Max(0, p - r); i <= Min(h - 1, p + r); ++i) {
      // Row i's taps landing on row p: one inside, a run at a clamped
      // border.
      const int lo = p == 0 ? 0 : p - i + r;
      const int hi = p == h - 1 ? 2 * r : p - i + r;
      for (int j = Max(lo, 0); j <= Min(hi, 2 * r); ++j) {
        s.sources[terms] = g_out + static_cast<size_t>(i) * w;
        s.coefficients[terms++] = k[j];
      }
    }
    SumTerms(s.sources, s.coefficients, terms, 0, w,
             g_in + static_cast<size_t>(p) * w);
  }
}

// No branch per pixel, so the loop vectorizes (sqrt and the division are
// exactly rounded on every set; -fno-math-errno lets sqrt be one
// instruction).
void AmplitudeTerms(const double* e_rendered, const double* e_input,
                    const double* water, long n, double floor, double eps,
                    double scale, double count, double* term,
                    double* d_energy) {
  for (long p = 0; p < n; ++p) {
    const double er = e_rendered[p] > 0.0 ? e_rendered[p] : 0.0;
    const double ei = e_input[p] > 0.0 ? e_input[p] : 0.0;
    const double a = __builtin_sqrt(er + floor);
    const double b = __builtin_sqrt(ei + eps);
    const double sign = a > b ? 1.0 : (a < b ? -1.0 : 0.0);
    const bool in = water[p] != 0.0;
    term[p] = in ? __builtin_fabs(a - b) : 0.0;
    d_energy[p] = in ? scale * sign / (2 * a * count) : 0.0;
  }
}

constexpr int kNeighbours = 9;

// Runs run(std::integral_constant<int, M>(), j0) over the directions in
// chunks of M = 16, then 4, then 1, each chunk's sums held in registers.
template <typename Run>
void InDirectionChunks(int projections, Run run) {
  int j = 0;
  for (; j + 16 <= projections; j += 16)
    run(std::integral_constant<int, 16>(), j);
  for (; j + 4 <= projections; j += 4)
    run(std::integral_constant<int, 4>(), j);
  for (; j < projections; ++j) run(std::integral_constant<int, 1>(), j);
}

// Project for directions [j0, j0 + M), kLanes pixels at a time: their M
// sums stay in registers over all the features.
template <int M>
void ProjectDirections(const TextureProjection& p, long begin, long end,
                       int j0, double* out) {
  const int dims = kNeighbours * p.count;
  const double* d = p.directions + static_cast<long>(j0) * dims;
  long i = begin;
  for (; i + kLanes <= end; i += kLanes) {
    Vec acc[M];
    for (Vec& a : acc) a = Vec{};
    for (int b = 0; b < p.count; ++b) {
      const double* band = p.bands[b];
      const int* taps = p.taps[b % p.levels] + kNeighbours * i;
      for (int o = 0; o < kNeighbours; ++o) {
        Vec v;
        for (int l = 0; l < kLanes; ++l)
          v[l] = band[taps[kNeighbours * l + o]];
        const int f = kNeighbours * b + o;
        for (int m = 0; m < M; ++m)
          acc[m] += v * d[static_cast<long>(m) * dims + f];
      }
    }
    for (int m = 0; m < M; ++m)
      Store(acc[m], out + static_cast<long>(j0 + m) * p.n + i);
  }
  for (; i < end; ++i) {
    for (int m = 0; m < M; ++m) {
      double acc = 0.0;
      for (int b = 0; b < p.count; ++b) {
        const int* taps = p.taps[b % p.levels] + kNeighbours * i;
        for (int o = 0; o < kNeighbours; ++o)
          acc += p.bands[b][taps[o]] *
                 d[static_cast<long>(m) * dims + kNeighbours * b + o];
      }
      out[static_cast<long>(j0 + m) * p.n + i] = acc;
    }
  }
}

void Project(const TextureProjection& p, long begin, long end, double* out) {
  InDirectionChunks(p.projections, [&](auto m, int j0) {
    ProjectDirections<decltype(m)::value>(p, begin, end, j0, out);
  });
}

// kLanes pixels at a time: their gradients by the projections are read
// once for all nine features of band b.
template <int M>
void ProjectAdjointDirections(const TextureProjection& p, int b, int j0,
                              const double* d_proj, double* d_band) {
  const int dims = kNeighbours * p.count;
  const int* taps = p.taps[b % p.levels];
  const double* d = p.directions + static_cast<long>(j0) * dims +
                    kNeighbours * b;  // (9 b, j0)
  long i = 0;
  for (; i + kLanes <= p.n; i += kLanes) {
    Vec g[M];
    for (int m = 0; m < M; ++m)
      g[m] = Load(d_proj + static_cast<long>(j0 + m) * p.n + i);
    Vec v[kNeighbours];
    for (int o = 0; o < kNeighbours; ++o) {
      v[o] = Vec{};
      for (int m = 0; m < M; ++m)
        v[o] += g[m] * d[static_cast<long>(m) * dims + o];
    }
    // Pixel by pixel, as the one-pixel loop below: the same order of
    // adds into d_band whatever the vectors' width.
    for (int l = 0; l < kLanes; ++l)
      for (int o = 0; o < kNeighbours; ++o)
        d_band[taps[kNeighbours * (i + l) + o]] += v[o][l];
  }
  for (; i < p.n; ++i) {
    for (int o = 0; o < kNeighbours; ++o) {
      double v = 0.0;
      for (int m = 0; m < M; ++m)
        v += d_proj[static_cast<long>(j0 + m) * p.n + i] *
             d[static_cast<long>(m) * dims + o];
      d_band[taps[kNeighbours * i + o]] += v;
    }
  }
}

void ProjectAdjoint(const TextureProjection& p, int b, const double* d_proj,
                    double* d_band) {
  InDirectionChunks(p.projections, [&](auto m, int j0) {
    ProjectAdjointDirections<decltype(m)::value>(p, b, j0, d_proj, d_band);
  });
}

const WaterKernelSet kKernels = {&BlurRows,        &BlurColumns,
                                 &BlurRowsAdjoint, &BlurColumnsAdjoint,
                                 &AmplitudeTerms,  &Project,
                                 &ProjectAdjoint};

}  // namespace

const WaterKernelSet& Kernels() { return kKernels; }

}  // namespace ES_WATER_KERNELS_ISA
}  // namespace es
