// The per-tile forward and backward passes of the rasterizer. Included only
// by tile_kernels_{sse2,avx2,avx512}.cc, each compiled for its instruction
// set with ES_TILE_ISA naming its namespace. Everything here has internal
// linkage and calls no out-of-line library code, so no function compiled
// for AVX2 / AVX-512 can be merged into, or called from, code that runs on
// a CPU without it.

#if !defined(ES_TILE_ISA) || !defined(ES_TILE_FULL_ROWS)
#error "define ES_TILE_ISA and ES_TILE_FULL_ROWS before this header"
#endif

// Lets GCC turn the selects in the row loops below into vector blends (it
// keeps branches while a comparison might raise a floating-point exception
// flag); values are unchanged and nothing here reads those flags.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-trapping-math")
#endif

#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/render/raster_constants.h"
#include "core/render/tile_kernels.h"

namespace es {
namespace ES_TILE_ISA {
namespace {

constexpr int kTilePixels = kTileSize * kTileSize;
// Whether a Gaussian's rows run over a fixed window of the tile row (a
// fixed trip count, whole vectors for AVX-512 / AVX2, no scalar remainder)
// with the pixels outside its box masked to alpha 0, or over its box only
// (fewer lanes wasted with 4-wide SSE2). The window is the whole row, or
// its half kNarrow wide placed over the box where the box fits in it (at
// 16 lanes per row a typical box filled about 10; small boxes far fewer).
// Pixels with alpha 0 take no part in either pass, so all give the same
// sums up to their order.
constexpr bool kFullRows = ES_TILE_FULL_ROWS;
constexpr int kNarrow = kTileSize / 2;

inline int MinInt(int a, int b) { return a < b ? a : b; }
inline int MaxInt(int a, int b) { return a > b ? a : b; }

#include "core/render/exp_polynomial.inc"

// exp(x) for float x <= 0 (ExpPolynomial). Double (the reference
// precision) keeps the library exp.
inline float ExpNonPositive(float x) {
  return ExpPolynomial(x > -87.0f ? x : -87.0f);
}
inline double ExpNonPositive(double x) {
  return __builtin_exp(x < 0.0 ? x : 0.0);
}

// A binned Gaussian in the tile pass.
template <typename S>
struct Footprint {
  S mx, my, ca, cb, cc, opacity;
  S cutoff;  // TileSigmaCutoff
  S slope;   // dx of a row's least sigma per dy: -b / a
  explicit Footprint(const S* geo)
      : mx(geo[0]), my(geo[1]), ca(geo[2]), cb(geo[3]), cc(geo[4]),
        opacity(geo[5]), cutoff(geo[kTileRecordCutoff - kTileRecordGeom]),
        slope(ca > S(0) ? -cb / ca : S(0)) {}
};

// Whether row y can hold a pixel in [lo, hi) where the Gaussian reaches
// kMinAlpha: whether sigma's least value on the row's segment (the
// continuous one, so at most its pixels' least) is not above the cutoff.
// Rows it rules out have no pixel with alpha >= kMinAlpha; both passes
// skip them.
template <typename S>
inline bool RowReached(const Footprint<S>& g, int y, int lo, int hi) {
  if (!(g.ca > S(0))) return true;
  const S dy = static_cast<S>(y) + S(0.5) - g.my;
  const S dx_lo = static_cast<S>(lo) + S(0.5) - g.mx;
  const S dx_hi = static_cast<S>(hi) - S(0.5) - g.mx;
  S dx = g.slope * dy;
  dx = dx < dx_lo ? dx_lo : (dx > dx_hi ? dx_hi : dx);
  const S sigma =
      S(0.5) * g.ca * dx * dx + g.cb * dy * dx + S(0.5) * g.cc * dy * dy;
  return !(sigma > g.cutoff);
}

// The part of a tile one Gaussian's pixel box covers: pixels [x0, x1) x
// [y0, y1) (empty when x0 >= x1 or y0 >= y1).
struct Span {
  int x0, x1, y0, y1;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
};

struct TileRect {
  int x0, x1, y0, y1;
  TileRect(int tile, int tiles_x, int width, int height)
      : x0((tile % tiles_x) * kTileSize),
        x1(MinInt(x0 + kTileSize, width)),
        y0((tile / tiles_x) * kTileSize),
        y1(MinInt(y0 + kTileSize, height)) {}
  // box: a record's pixel box (whole numbers in S).
  template <typename S>
  Span Clip(const S* box) const {
    return {MaxInt(x0, static_cast<int>(box[0])),
            MinInt(x1, static_cast<int>(box[1])),
            MaxInt(y0, static_cast<int>(box[2])),
            MinInt(y1, static_cast<int>(box[3]))};
  }
  // Offset of pixel (x, y) in the tile's per-pixel arrays.
  int Offset(int x, int y) const { return (y - y0) * kTileSize + (x - x0); }
};

// The pixels of one row a Gaussian is evaluated on: n pixels from x0, of
// which those in [lo, hi) (its box within the tile) count.
struct RowRange {
  int x0, n, lo, hi;
};

// The row window of a span, n kTileSize or kNarrow with full rows, else
// the span's width. Forward and backward call it on the same span, so both
// evaluate the same pixels.
inline RowRange RowOf(const TileRect& r, const Span& s) {
  if (!kFullRows) return {s.x0, s.x1 - s.x0, s.x0, s.x1};
  if (s.x1 - s.x0 > kNarrow) return {r.x0, kTileSize, s.x0, s.x1};
  return {MinInt(s.x0, r.x0 + kTileSize - kNarrow), kNarrow, s.x0, s.x1};
}

// Runs body(std::integral_constant<int, N>) with N the row window's width
// when it is one of the fixed ones (so its loops get a constant trip
// count), else with N = 0 (the width is row.n).
template <typename Body>
inline auto WithRowWidth(const RowRange& row, Body&& body) {
  if constexpr (kFullRows) {
    if (row.n == kNarrow) return body(std::integral_constant<int, kNarrow>());
    return body(std::integral_constant<int, kTileSize>());
  } else {
    return body(std::integral_constant<int, 0>());
  }
}

// The Gaussian on the n pixels of row y from x0: raw[i] = o exp(-sigma),
// alpha before the 0.99 clamp, with sigma = 0.5 d^T conic d, and 0 where
// sigma < 0 or outside [lo, hi). Forward and backward share it so both take
// exactly the same skip decisions.
template <int kN, typename S>
inline void RowAlphas(const Footprint<S>& g, int y, const RowRange& row,
                      S* raw) {
  const int n = kN > 0 ? kN : row.n;
  const S dy = static_cast<S>(y) + S(0.5) - g.my;
  const S row_term = S(0.5) * g.cc * dy * dy;
  const S cross = g.cb * dy;
  const int x0 = row.x0, lo = row.lo, hi = row.hi;
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const int x = x0 + i;
    const S dx = static_cast<S>(x) + S(0.5) - g.mx;
    const S sigma = S(0.5) * g.ca * dx * dx + cross * dx + row_term;
    const S a = g.opacity * ExpNonPositive(-sigma);
    raw[i] = sigma >= S(0) && x >= lo && x < hi ? a : S(0);
  }
}

// The extra channels a pass renders: kExtra when the kernel was compiled
// for that count (0 and 1, the common cases, so their loops unroll), else
// the pass's own count (kExtra = -1).
template <int kExtra, typename S>
inline int NumExtra(const TilePass<S>& p) {
  return kExtra >= 0 ? kExtra : p.num_extra;
}

// Binned Gaussian k's record (TilePass::splat).
template <typename S>
inline const S* Record(const TilePass<S>& p, int k) {
  return p.splat + static_cast<size_t>(p.record_stride) * k;
}

// How many entries ahead of the one in hand the tile loops prefetch: the
// records are scattered over the depth order (a tile's Gaussians are a
// sparse subset), so each is a cache miss unless asked for early.
constexpr int kPrefetchAhead = 6;

// Asks for the cache lines of entry e's record.
template <typename S>
inline void PrefetchRecord(const TilePass<S>& p, int e) {
  const char* rec = reinterpret_cast<const char*>(Record(p, p.tile_entries[e]));
  const int bytes = p.record_stride * static_cast<int>(sizeof(S));
  for (int b = 0; b < bytes; b += 64) __builtin_prefetch(rec + b);
}

// Whether a pixel of a tile row has not stopped yet (done[i] is 0 or 1).
template <typename S>
inline bool RowLive(const S* done) {
  S least = 1;
#pragma omp simd reduction(min : least)
  for (int i = 0; i < kTileSize; ++i) least = done[i] < least ? done[i] : least;
  return least == S(0);
}

// Whether any of a tile row's flags (each 0 or 1) is set.
template <typename S>
inline bool AnySet(const S* flags) {
  S most = 0;
#pragma omp simd reduction(max : most)
  for (int i = 0; i < kTileSize; ++i) most = flags[i] > most ? flags[i] : most;
  return most != S(0);
}

// The sum of a row's kTileSize lanes, as a tree of vector adds (an
// omp simd sum reduction ends in one scalar add per lane); a is overwritten.
template <typename S>
inline S SumLanes(S* a) {
  static_assert(kTileSize == 16, "the tree below adds 16 lanes");
  for (int i = 0; i < 8; ++i) a[i] += a[i + 8];
  for (int i = 0; i < 4; ++i) a[i] += a[i + 4];
  return (a[0] + a[2]) + (a[1] + a[3]);
}

// ---------------------------------------------------------------- forward

// Composites one Gaussian (features f: r, g, b, depth) over n pixels of a
// tile row, front to back, with the 3DGS rules: skip alpha < 1/255, clamp
// alpha at 0.99, stop a pixel before T would fall below 1e-4. Per-pixel
// arrays start at the row's first pixel; w receives each pixel's weight
// alpha * T (0 where skipped) for the extra channels, and stopped[i] is
// set to 1 where a pixel stopped (kept per lane: a reduction to one flag
// per row cost a chain of horizontal maxes per row). Written without
// branches so it vectorizes.
template <typename S>
inline void CompositeRow(int n, const S* raw, const S* f, int rank,
                         S* __restrict t, S* __restrict done,
                         int* __restrict last, S* __restrict acc0,
                         S* __restrict acc1, S* __restrict acc2,
                         S* __restrict acc3, S* __restrict w,
                         S* __restrict stopped) {
  const S max_alpha = static_cast<S>(kMaxAlpha);
  const S min_alpha = static_cast<S>(kMinAlpha);
  const S min_t = static_cast<S>(kMinTransmittance);
  const S f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3];
  // Plain loads and `&` rather than `&&` (a short-circuit load of done[i]
  // is a masked load GCC does not vectorize) keep the loop vectorized.
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const S r = raw[i], d = done[i], ti = t[i];
    const int li = last[i];
    const bool live = (r >= min_alpha) & (d == S(0));
    const S alpha = live ? (r < max_alpha ? r : max_alpha) : S(0);
    const S next_t = ti * (S(1) - alpha);
    const bool stop = live & (next_t < min_t);
    const bool use = live & !stop;
    const S wi = use ? alpha * ti : S(0);
    acc0[i] += wi * f0;
    acc1[i] += wi * f1;
    acc2[i] += wi * f2;
    acc3[i] += wi * f3;
    w[i] = wi;
    // Every lane is stored, as minima and maxima equal to the selects
    // (use ? next_t : ti with next_t <= ti <= 1, use ? rank : li with
    // li < rank, ...): GCC turns `x[i] = c ? v : x[i]` into a masked
    // store, which the next Gaussian's load of the same pixels cannot take
    // its value from (a stall on each row).
    const S t_use = use ? next_t : S(2);
    t[i] = t_use < ti ? t_use : ti;
    const int use_rank = use ? rank : 0;
    last[i] = li > use_rank ? li : use_rank;
    const S stop_flag = stop ? S(1) : S(0);
    done[i] = d > stop_flag ? d : stop_flag;
    const S stopped_i = stopped[i];
    stopped[i] = stopped_i > stop_flag ? stopped_i : stop_flag;
  }
}

// Writes the composited tile (per-pixel arrays t and accum, nf features)
// into the pass's images, a tile row at a time.
template <typename S>
void StoreTile(const TilePass<S>& p, const TileRect& r, const S* t,
               const S* accum, const int* tile_last) {
  const double bg0 = p.background[0], bg1 = p.background[1],
               bg2 = p.background[2];
  const int num_extra = p.num_extra;
  const int n = r.x1 - r.x0;
  for (int y = r.y0; y < r.y1; ++y) {
    const int q = r.Offset(r.x0, y);
    const size_t pix = static_cast<size_t>(y) * p.width + r.x0;
    const S* tq = t + q;
    const S* a0 = accum + q;
    const S* a1 = a0 + kTilePixels;
    const S* a2 = a1 + kTilePixels;
    const S* a3 = a2 + kTilePixels;
    const int* lq = tile_last + q;
    double* rgb = p.rgb + 3 * pix;
    double* alpha = p.alpha + pix;
    double* depth = p.depth + pix;
    S* t_final = p.t_final + pix;
    int* last = p.last + pix;
#pragma omp simd
    for (int i = 0; i < n; ++i) {
      const double tf = tq[i];
      rgb[3 * i] = a0[i] + bg0 * tf;
      rgb[3 * i + 1] = a1[i] + bg1 * tf;
      rgb[3 * i + 2] = a2[i] + bg2 * tf;
      alpha[i] = 1 - tf;
      depth[i] = a3[i];
      t_final[i] = tq[i];
      last[i] = lq[i];
    }
    for (int c = 0; c < num_extra; ++c) {
      const S* ac = accum + (4 + c) * kTilePixels + q;
      double* extra = p.extra + pix * num_extra + c;
#pragma omp simd
      for (int i = 0; i < n; ++i) extra[i * num_extra] = ac[i];
    }
  }
}

template <typename S, int kExtra>
long long ForwardTile(const TilePass<S>& p, int tile, S* scratch) {
  const TileRect r(tile, p.tiles_x, p.width, p.height);
  const int nf = 4 + NumExtra<kExtra>(p);
  // Per-pixel state of the tile, one array per quantity.
  S* t = scratch;
  S* done = t + kTilePixels;
  S* accum = done + kTilePixels;  // nf arrays
  int tile_last[kTilePixels];
  S w[kTileSize], raw[kTileSize], stop_lanes[kTileSize];
  for (int i = 0; i < kTilePixels; ++i) t[i] = S(1);
  for (int i = 0; i < kTilePixels * (nf + 1); ++i) done[i] = S(0);
  for (int i = 0; i < kTilePixels; ++i) tile_last[i] = 0;
  // Pixels past the image's edge count as done; rows where every pixel
  // is done are skipped (exactly: a done pixel takes no part), and the
  // tile ends when no row is live.
  for (int y = 0; y < kTileSize; ++y)
    for (int x = 0; x < kTileSize; ++x)
      if (r.x0 + x >= r.x1 || r.y0 + y >= r.y1) done[y * kTileSize + x] = 1;
  bool row_live[kTileSize];
  int live_rows = 0;
  for (int y = 0; y < kTileSize; ++y) {
    row_live[y] = RowLive(done + y * kTileSize);
    live_rows += row_live[y];
  }
  long long evaluations = 0;
  const int begin = p.tile_offsets[tile], end = p.tile_offsets[tile + 1];
  for (int e = begin; e < MinInt(end, begin + kPrefetchAhead); ++e)
    PrefetchRecord(p, e);
  for (int e = begin; e < end && live_rows > 0; ++e) {
    if (e + kPrefetchAhead < end) PrefetchRecord(p, e + kPrefetchAhead);
    const S* rec = Record(p, p.tile_entries[e]);
    const Span s = r.Clip(rec + kTileRecordBox);
    if (s.empty()) continue;
    evaluations += static_cast<long long>(s.x1 - s.x0) * (s.y1 - s.y0);
    const Footprint<S> g(rec + kTileRecordGeom);
    const S* f = rec + kTileRecordFeature;
    const RowRange row = RowOf(r, s);
    for (int i = 0; i < kTileSize; ++i) stop_lanes[i] = S(0);
    WithRowWidth(row, [&](auto width) {
      constexpr int kN = decltype(width)::value;
      const int n = kN > 0 ? kN : row.n;
      for (int y = s.y0; y < s.y1; ++y) {
        if (!row_live[y - r.y0] || !RowReached(g, y, row.lo, row.hi))
          continue;
        RowAlphas<kN>(g, y, row, raw);
        const int q = r.Offset(row.x0, y);
        CompositeRow(n, raw, f, e - begin + 1, t + q, done + q,
                     tile_last + q, accum + q, accum + kTilePixels + q,
                     accum + 2 * kTilePixels + q, accum + 3 * kTilePixels + q,
                     w, stop_lanes);
        for (int c = 4; c < nf; ++c) {
          S* acc = accum + c * kTilePixels + q;
          const S fc = f[c];
#pragma omp simd
          for (int i = 0; i < n; ++i) acc[i] += w[i] * fc;
        }
      }
      return 0;
    });
    // Only a stop can end a row.
    if (!AnySet(stop_lanes)) continue;
    for (int y = s.y0; y < s.y1; ++y) {
      bool& live = row_live[y - r.y0];
      if (live && !RowLive(done + (y - r.y0) * kTileSize)) {
        live = false;
        --live_rows;
      }
    }
  }
  StoreTile(p, r, t, accum, tile_last);
  return evaluations;
}

// --------------------------------------------------------------- backward

// The tile's per-pixel state for the backward pass.
template <typename S>
struct BackwardTileState {
  S* t;          // transmittance, recovered back to front
  S* suffix;     // d loss / d (everything behind), see BackwardRow
  S* g_feat;     // num_features arrays of pixel gradients
  S* lane_extra;  // one Gaussian's extra-channel gradients, per lane
  S* grad;        // where one Gaussian's summed gradient goes (its entry)
  int last[kTilePixels];
  int row_last[kTileSize];  // the largest last[] of each row
};

// Loads the pixel gradients and the forward's final state, a tile row at a
// time; returns the largest number of entries any pixel of the tile used.
template <typename S>
int LoadTileGradients(const TilePass<S>& p, const TileRect& r,
                      BackwardTileState<S>* st) {
  const int num_extra = p.num_extra;
  const int n = r.x1 - r.x0;
  int max_last = 0;
  for (int i = 0; i < kTileSize; ++i) st->row_last[i] = 0;
  for (int y = r.y0; y < r.y1; ++y) {
    const int q = r.Offset(r.x0, y);
    const size_t pix = static_cast<size_t>(y) * p.width + r.x0;
    // d loss / d T_final: the background term and alpha = 1 - T_final.
    double g_t[kTileSize];
    for (int i = 0; i < n; ++i) g_t[i] = 0;
    for (int c = 0; c < 3; ++c) {
      S* g = st->g_feat + c * kTilePixels + q;
      if (p.d_rgb == nullptr) {
        for (int i = 0; i < n; ++i) g[i] = S(0);
        continue;
      }
      const double* d = p.d_rgb + 3 * pix + c;
      const double bg = p.background[c];
#pragma omp simd
      for (int i = 0; i < n; ++i) {
        g[i] = static_cast<S>(d[3 * i]);
        g_t[i] += d[3 * i] * bg;
      }
    }
    const auto load = [n](const double* d, S* g) {
      if (d == nullptr) {
        for (int i = 0; i < n; ++i) g[i] = S(0);
        return;
      }
#pragma omp simd
      for (int i = 0; i < n; ++i) g[i] = static_cast<S>(d[i]);
    };
    load(p.d_depth ? p.d_depth + pix : nullptr,
         st->g_feat + 3 * kTilePixels + q);
    for (int c = 0; c < num_extra; ++c) {
      S* g = st->g_feat + (4 + c) * kTilePixels + q;
      if (p.d_extra == nullptr) {
        for (int i = 0; i < n; ++i) g[i] = S(0);
        continue;
      }
      const double* d = p.d_extra + pix * num_extra + c;
#pragma omp simd
      for (int i = 0; i < n; ++i) g[i] = static_cast<S>(d[i * num_extra]);
    }
    if (p.d_alpha != nullptr) {
      const double* d = p.d_alpha + pix;
#pragma omp simd
      for (int i = 0; i < n; ++i) g_t[i] -= d[i];
    }
    const S* t_final = p.t_final + pix;
    const int* last = p.last + pix;
    S* t = st->t + q;
    S* suffix = st->suffix + q;
    int* tile_last = st->last + q;
    int row_last = 0;
#pragma omp simd reduction(max : row_last)
    for (int i = 0; i < n; ++i) {
      t[i] = t_final[i];
      suffix[i] = static_cast<S>(g_t[i] * static_cast<double>(t_final[i]));
      tile_last[i] = last[i];
      row_last = last[i] > row_last ? last[i] : row_last;
    }
    st->row_last[y - r.y0] = row_last;
    max_last = MaxInt(max_last, row_last);
  }
  return max_last;
}

// One Gaussian's 2D gradient over a tile, kept per lane of a row: the row
// loops add lane by lane (no horizontal sum per row) and Sum() adds the
// lanes once per Gaussian and tile. A lane is one column of the tile, so
// its dx is the same on every row: the geometry terms keep only the sums
// of g_sigma, dy g_sigma and dy^2 g_sigma over the rows (three per lane,
// not five), and Sum() applies dx and the conic once.
template <typename S>
struct LaneGradient {
  // sum g_sigma, sum dy g_sigma, sum dy^2 g_sigma, sum g_alpha exp(-sigma),
  // then the feature weights sum g_c w for r, g, b, depth.
  static constexpr int kTerms = 8;
  S term[kTerms][kTileSize];

  void Clear() {
    for (int c = 0; c < kTerms; ++c)
      for (int i = 0; i < kTileSize; ++i) term[c][i] = S(0);
  }
  // Writes the Gaussian's kTileGradHead + 4 gradient values (geometry,
  // opacity, r, g, b, depth) to out; dx0 is lane 0's x offset from the
  // mean. The lanes are overwritten.
  void Sum(const Footprint<S>& g, S dx0, S* out) {
    S* s0 = term[0];
    S* sy = term[1];
    S mx[kTileSize], my[kTileSize], ca[kTileSize], cb[kTileSize];
#pragma omp simd
    for (int i = 0; i < kTileSize; ++i) {
      const S dx = dx0 + static_cast<S>(i);
      const S dx_s0 = dx * s0[i];
      mx[i] = -(g.ca * dx_s0 + g.cb * sy[i]);
      my[i] = -(g.cb * dx_s0 + g.cc * sy[i]);
      ca[i] = S(0.5) * dx * dx_s0;
      cb[i] = dx * sy[i];
    }
    out[0] = SumLanes(mx);
    out[1] = SumLanes(my);
    out[2] = SumLanes(ca);
    out[3] = SumLanes(cb);
    out[4] = S(0.5) * SumLanes(term[2]);
    out[5] = SumLanes(term[3]) / g.opacity;
    for (int c = 0; c < 4; ++c) out[kTileGradHead + c] = SumLanes(term[4 + c]);
  }
};

// inv[i] = 1 / (1 - alpha[i]) for the n = kN lanes of a row (alpha in
// [0, 0.99]). A vector division of 16 floats is one of the slowest
// instructions of the row; with AVX-512 / AVX2 the reciprocal estimate and
// one Newton step give it to about 2 ulp, well inside the float
// tolerance. Elsewhere (double, SSE2, or a variable width) a division.
template <int kN, typename S>
inline void OneMinusReciprocal(int n, const S* alpha, S* inv) {
#if defined(__AVX2__)
  if constexpr (std::is_same<S, float>::value && kN % 8 == 0 && kN > 0) {
#if defined(__AVX512F__)
    if constexpr (kN == 16) {
      const __m512 x = _mm512_sub_ps(_mm512_set1_ps(1.0f),
                                     _mm512_loadu_ps(alpha));
      // maskz: GCC 12 warns on the plain form's undefined source.
      const __m512 r = _mm512_maskz_rcp14_ps(0xFFFF, x);
      // r (2 - x r)
      _mm512_storeu_ps(
          inv, _mm512_mul_ps(r, _mm512_fnmadd_ps(x, r, _mm512_set1_ps(2.0f))));
      return;
    }
#endif
    for (int i = 0; i < kN; i += 8) {
      const __m256 x = _mm256_sub_ps(_mm256_set1_ps(1.0f),
                                     _mm256_loadu_ps(alpha + i));
      const __m256 r = _mm256_rcp_ps(x);
      _mm256_storeu_ps(inv + i,
                       _mm256_mul_ps(r, _mm256_fnmadd_ps(
                                            x, r, _mm256_set1_ps(2.0f))));
    }
    return;
  }
#endif
#pragma omp simd
  for (int i = 0; i < n; ++i) inv[i] = S(1) / (S(1) - alpha[i]);
}

// Backward of CompositeRow, back to front, for the n = kN (0: row.n)
// pixels of row y starting at pixel x0: recovers T in front of the
// Gaussian (T / (1 - alpha)), adds the Gaussian's gradients lane by lane
// into *lanes and updates the per-pixel suffix (d loss / d everything
// behind). g0..g3 are the pixels' gradients for r, g, b, depth and
// g_extra_dot their extra gradients dotted with this Gaussian's extras; w
// receives the weights for the extra channels.
template <int kN, typename S>
inline void BackwardRow(int n, const S* raw, const Footprint<S>& g,
                        const S* f, int rank, int y, const int* last,
                        S* __restrict t, S* __restrict suffix,
                        const S* g0, const S* g1, const S* g2, const S* g3,
                        const S* g_extra_dot, S* __restrict w,
                        LaneGradient<S>* lanes) {
  const S max_alpha = static_cast<S>(kMaxAlpha);
  const S min_alpha = static_cast<S>(kMinAlpha);
  const S f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3];
  const S dy = static_cast<S>(y) + S(0.5) - g.my;
  const S dy2 = dy * dy;
  S alpha[kTileSize], inv[kTileSize];
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const S r = raw[i];
    const bool live = (r >= min_alpha) & (rank < last[i]);
    alpha[i] = live ? (r < max_alpha ? r : max_alpha) : S(0);
  }
  OneMinusReciprocal<kN>(n, alpha, inv);
  S* __restrict s0 = lanes->term[0];
  S* __restrict sy = lanes->term[1];
  S* __restrict syy = lanes->term[2];
  S* __restrict op = lanes->term[3];
  S* __restrict a0 = lanes->term[4];
  S* __restrict a1 = lanes->term[5];
  S* __restrict a2 = lanes->term[6];
  S* __restrict a3 = lanes->term[7];
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    const S r = raw[i];
    const bool live = (r >= min_alpha) & (rank < last[i]);
    const S a = alpha[i];
    const S inv_one_minus = inv[i];
    const S si = suffix[i];
    // T in front of this Gaussian (exactly T where it took no part: a
    // reciprocal estimate of 1 may come out a rounding below 1).
    const S t_front = live ? t[i] * inv_one_minus : t[i];
    const S wi = a * t_front;
    w[i] = wi;
    // Selects, not products with wi = 0, so a non-finite gradient of a
    // pixel the Gaussian does not reach cannot leak into its sums.
    a0[i] += live ? g0[i] * wi : S(0);
    a1[i] += live ? g1[i] * wi : S(0);
    a2[i] += live ? g2[i] * wi : S(0);
    a3[i] += live ? g3[i] * wi : S(0);
    const S g_dot_f =
        g0[i] * f0 + g1[i] * f1 + g2[i] * f2 + g3[i] * f3 + g_extra_dot[i];
    // out = sum_i f_i a_i T_i + bg T_N: d out / d a_i = f_i T_i -
    // (everything behind i, background and 1 - alpha included) / (1 - a_i).
    const S g_alpha = g_dot_f * t_front - si * inv_one_minus;
    suffix[i] = si + (live ? g_dot_f * wi : S(0));
    t[i] = t_front;
    // No gradient through the 0.99 clamp. d alpha / d opacity =
    // exp(-sigma) = r / opacity (the division in Sum).
    const bool unclamped = live & (r <= max_alpha);
    const S g_sigma = unclamped ? -g_alpha * a : S(0);
    op[i] += unclamped ? g_alpha * r : S(0);
    s0[i] += g_sigma;
    sy[i] += dy * g_sigma;
    syy[i] += dy2 * g_sigma;
  }
}

// The rows of BackwardGaussian, kN lanes each (0: row.n).
template <int kN, int kExtra, typename S>
inline void BackwardRows(const TilePass<S>& p, const TileRect& r,
                         const Span& s, const RowRange& row,
                         const Footprint<S>& g, const S* f, int rank,
                         BackwardTileState<S>* st, LaneGradient<S>* lanes) {
  const int nf = 4 + NumExtra<kExtra>(p);
  const int n = kN > 0 ? kN : row.n;
  S w[kTileSize], raw[kTileSize], g_extra_dot[kTileSize];
  for (int i = 0; i < kTileSize; ++i) g_extra_dot[i] = S(0);
  for (int y = s.y0; y < s.y1; ++y) {
    // No pixel of the row used this Gaussian: T and suffix stay as they are.
    if (rank >= st->row_last[y - r.y0] || !RowReached(g, y, row.lo, row.hi))
      continue;
    RowAlphas<kN>(g, y, row, raw);
    const int q = r.Offset(row.x0, y);
    const S* gf = st->g_feat + q;
    for (int c = 4; c < nf; ++c) {
      const S* gc = gf + c * kTilePixels;
      const S fc = f[c];
#pragma omp simd
      for (int i = 0; i < n; ++i)
        g_extra_dot[i] = (c == 4 ? S(0) : g_extra_dot[i]) + gc[i] * fc;
    }
    BackwardRow<kN>(n, raw, g, f, rank, y, st->last + q, st->t + q,
                    st->suffix + q, gf, gf + kTilePixels,
                    gf + 2 * kTilePixels, gf + 3 * kTilePixels, g_extra_dot,
                    w, lanes);
    for (int c = 4; c < nf; ++c) {
      const S* gc = gf + c * kTilePixels;
      S* lane = st->lane_extra + (c - 4) * kTileSize;
#pragma omp simd
      for (int i = 0; i < n; ++i)
        lane[i] += w[i] != S(0) ? gc[i] * w[i] : S(0);
    }
  }
}

// Walks one Gaussian (entry `rank` of the tile's list, record rec) back
// over its span of the tile, writing its gradient to st->grad (zeros where
// no pixel used it: every lane term is then exactly zero).
template <typename S, int kExtra>
void BackwardGaussian(const TilePass<S>& p, const TileRect& r, const Span& s,
                      const S* rec, int rank, BackwardTileState<S>* st) {
  const int num_extra = NumExtra<kExtra>(p);
  const Footprint<S> g(rec + kTileRecordGeom);
  const S* f = rec + kTileRecordFeature;
  const RowRange row = RowOf(r, s);
  LaneGradient<S> lanes;
  lanes.Clear();
  for (int i = 0; i < num_extra * kTileSize; ++i) st->lane_extra[i] = S(0);
  WithRowWidth(row, [&](auto width) {
    constexpr int kN = decltype(width)::value;
    BackwardRows<kN, kExtra>(p, r, s, row, g, f, rank, st, &lanes);
    return 0;
  });
  for (int c = 0; c < num_extra; ++c)
    st->grad[kTileGradHead + 4 + c] = SumLanes(st->lane_extra + c * kTileSize);
  lanes.Sum(g, static_cast<S>(row.x0) + S(0.5) - g.mx, st->grad);
}

template <typename S, int kExtra>
void BackwardTile(const TilePass<S>& p, int tile, S* scratch) {
  const int begin = p.tile_offsets[tile], end = p.tile_offsets[tile + 1];
  p.tile_last_entry[tile] = -1;
  if (begin == end) return;
  const TileRect r(tile, p.tiles_x, p.width, p.height);
  BackwardTileState<S> st;
  st.t = scratch;
  st.suffix = st.t + kTilePixels;
  st.g_feat = st.suffix + kTilePixels;
  st.lane_extra = st.g_feat + p.num_features * kTilePixels;
  for (int i = 0; i < kTilePixels; ++i) st.last[i] = 0;
  if (kFullRows && r.x1 - r.x0 < kTileSize) {
    // Full rows also run over the pixels past the image's right edge.
    const int n = (p.num_features + 2) * kTilePixels;
    for (int i = 0; i < n; ++i) st.t[i] = S(0);
  }
  const int max_last = LoadTileGradients(p, r, &st);
  const int stride = p.grad_stride;
  const auto slot = [&](int e) {
    return p.entry_grad + static_cast<size_t>(stride) * p.entry_slot[e];
  };
  // Entries behind every pixel's last one took no part (not written).
  const int first = begin + max_last - 1;
  if (max_last > 0) p.tile_last_entry[tile] = p.tile_entries[first];
  for (int e = first; e > MaxInt(begin - 1, first - kPrefetchAhead); --e)
    PrefetchRecord(p, e);
  for (int e = first; e >= begin; --e) {
    if (e - kPrefetchAhead >= begin) {
      PrefetchRecord(p, e - kPrefetchAhead);
      __builtin_prefetch(slot(e - kPrefetchAhead), 1);
    }
    const S* rec = Record(p, p.tile_entries[e]);
    const Span s = r.Clip(rec + kTileRecordBox);
    S* out = slot(e);
    st.grad = out;
    if (s.empty()) {
      for (int c = 0; c < stride; ++c) out[c] = S(0);
    } else {
      BackwardGaussian<S, kExtra>(p, r, s, rec, e - begin, &st);
    }
  }
}

template <typename S, int kExtra>
const TileKernelSet<S> kKernels = {&ForwardTile<S, kExtra>,
                                   &BackwardTile<S, kExtra>};

template <typename S>
const TileKernelSet<S>& KernelsFor(int num_extra) {
  switch (num_extra) {
    case 0:
      return kKernels<S, 0>;
    case 1:
      return kKernels<S, 1>;
    default:
      return kKernels<S, -1>;
  }
}

}  // namespace

const TileKernelSet<float>& FloatKernels(int num_extra) {
  return KernelsFor<float>(num_extra);
}
const TileKernelSet<double>& DoubleKernels(int num_extra) {
  return KernelsFor<double>(num_extra);
}

}  // namespace ES_TILE_ISA
}  // namespace es
