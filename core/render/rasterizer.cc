#include "core/render/rasterizer.h"

// Lets GCC turn the selects in the row loops below into vector blends (it
// keeps branches while a comparison might raise a floating-point exception
// flag); values are unchanged and nothing here reads those flags.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-trapping-math")
#endif

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <optional>

#include <glog/logging.h>

#include "core/render/raster_project.h"

namespace es {
namespace {

constexpr int kTilePixels = kTileSize * kTileSize;
// Per binned Gaussian in the tile pass: mean x, mean y, conic a, b, c, opacity.
constexpr int kGeomStride = 6;
// Per-Gaussian 2D gradient layout: d mean2d (2), d conic (3), d opacity (1),
// then one entry per feature (r, g, b, depth, extras).
constexpr int kGradHead = 6;
// Below these sizes a parallel region costs more than it saves.
constexpr int kMinParallelSplats = 2048;
constexpr size_t kMinParallelEntries = 256;

// The per-tile data, in the precision of the inner loops.
template <typename S>
struct TileData {
  std::vector<S> geom;     // kGeomStride per visible Gaussian (depth order)
  std::vector<S> feature;  // num_features per visible Gaussian
  std::vector<int> box;    // px0, px1, py0, py1 per visible Gaussian
  std::vector<S> t_final;  // per pixel
};

// exp(x) for float x <= 0: Cephes' expf polynomial (about 1 ulp), written
// without a library call so the row loop below vectorizes. Double (the
// reference precision) keeps std::exp.
inline float ExpNonPositive(float x) {
  x = x > -87.0f ? x : -87.0f;
  // Round x / ln 2 to an integer n by the 1.5 * 2^23 trick.
  const float shifted = x * 1.44269504088896341f + 12582912.0f;
  const float n = shifted - 12582912.0f;
  int32_t n_bits;
  std::memcpy(&n_bits, &shifted, sizeof(n_bits));
  n_bits -= 0x4B400000;  // the bits of 12582912.0f
  const float r = x - n * 0.693359375f + n * 2.12194440e-4f;
  float p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  p = p * r * r + r + 1.0f;
  const int32_t scale_bits = (n_bits + 127) << 23;
  float scale;
  std::memcpy(&scale, &scale_bits, sizeof(scale));
  return p * scale;
}
inline double ExpNonPositive(double x) { return std::exp(std::min(x, 0.0)); }

// A binned Gaussian in the tile pass.
template <typename S>
struct Footprint {
  S mx, my, ca, cb, cc, opacity;
  explicit Footprint(const S* geo)
      : mx(geo[0]), my(geo[1]), ca(geo[2]), cb(geo[3]), cc(geo[4]),
        opacity(geo[5]) {}
};

// The Gaussian on pixels [x0, x1) of row y: raw[x - x0] = o exp(-sigma),
// alpha before the 0.99 clamp, with sigma = 0.5 d^T conic d and 0 where
// sigma < 0. Forward and backward share it so both take exactly the same
// skip decisions.
template <typename S>
inline void RowAlphas(const Footprint<S>& g, int y, int x0, int x1, S* raw) {
  const S dy = static_cast<S>(y) + S(0.5) - g.my;
  const S row_term = S(0.5) * g.cc * dy * dy;
  const S cross = g.cb * dy;
#pragma omp simd
  for (int x = x0; x < x1; ++x) {
    const S dx = static_cast<S>(x) + S(0.5) - g.mx;
    const S sigma = S(0.5) * g.ca * dx * dx + cross * dx + row_term;
    const S a = g.opacity * ExpNonPositive(-sigma);
    raw[x - x0] = sigma >= S(0) ? a : S(0);
  }
}

// Composites one Gaussian (features f: r, g, b, depth) over n pixels of a
// tile row, front to back, with the 3DGS rules: skip alpha < 1/255, clamp
// alpha at 0.99, stop a pixel before T would fall below 1e-4. Per-pixel
// arrays start at the row's first pixel; w receives each pixel's weight
// alpha * T (0 where skipped) for the extra channels. Written without
// branches so it vectorizes. Returns how many pixels stopped.
template <typename S>
inline int CompositeRow(int n, const S* raw, const S* f, int rank, S* t,
                        S* done, int* last, S* acc0, S* acc1, S* acc2,
                        S* acc3, S* w) {
  const S max_alpha = static_cast<S>(kMaxAlpha);
  const S min_alpha = static_cast<S>(kMinAlpha);
  const S min_t = static_cast<S>(kMinTransmittance);
  const S f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3];
  int stopped = 0;
#pragma omp simd reduction(+ : stopped)
  for (int i = 0; i < n; ++i) {
    const S r = raw[i];
    const bool live = r >= min_alpha && done[i] == S(0);
    const S alpha = live ? (r < max_alpha ? r : max_alpha) : S(0);
    const S next_t = t[i] * (S(1) - alpha);
    const bool stop = live && next_t < min_t;
    const bool use = live && !stop;
    const S wi = use ? alpha * t[i] : S(0);
    acc0[i] += wi * f0;
    acc1[i] += wi * f1;
    acc2[i] += wi * f2;
    acc3[i] += wi * f3;
    w[i] = wi;
    t[i] = use ? next_t : t[i];
    last[i] = use ? rank : last[i];
    done[i] = stop ? S(1) : done[i];
    stopped += stop ? 1 : 0;
  }
  return stopped;
}

// One Gaussian's 2D gradient summed over the pixels of a tile.
template <typename S>
struct FootprintGradient {
  S mx = 0, my = 0, ca = 0, cb = 0, cc = 0, opacity = 0;
  S f0 = 0, f1 = 0, f2 = 0, f3 = 0;
};

// Backward of CompositeRow, back to front, for n pixels of row y starting
// at pixel x0: recovers T in front of the Gaussian (T / (1 - alpha)),
// accumulates the Gaussian's gradients into *out and updates the per-pixel
// suffix (d loss / d everything behind). g0..g3 are the pixels' gradients
// for r, g, b, depth and g_extra_dot their extra gradients dotted with this
// Gaussian's extras; w receives the weights for the extra channels.
// Returns whether any pixel used the Gaussian.
template <typename S>
inline bool BackwardRow(int n, const S* raw, const Footprint<S>& g,
                        const S* f, int rank, int x0, int y, const int* last,
                        S* t, S* suffix, const S* g0, const S* g1,
                        const S* g2, const S* g3, const S* g_extra_dot, S* w,
                        FootprintGradient<S>* out) {
  const S max_alpha = static_cast<S>(kMaxAlpha);
  const S min_alpha = static_cast<S>(kMinAlpha);
  const S f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3];
  const S inv_opacity = S(1) / g.opacity;
  const S dy = static_cast<S>(y) + S(0.5) - g.my;
  const S dx0 = static_cast<S>(x0) + S(0.5) - g.mx;
  S mx = 0, my = 0, ca = 0, cb = 0, cc = 0, op = 0;
  S a0 = 0, a1 = 0, a2 = 0, a3 = 0;
  int used = 0;
#pragma omp simd reduction(+ : mx, my, ca, cb, cc, op, a0, a1, a2, a3, used)
  for (int i = 0; i < n; ++i) {
    const S r = raw[i];
    const bool live = r >= min_alpha && rank < last[i];
    const S alpha = live ? (r < max_alpha ? r : max_alpha) : S(0);
    const S one_minus = S(1) - alpha;
    const S t_front = t[i] / one_minus;  // T in front of this Gaussian
    const S wi = alpha * t_front;
    w[i] = wi;
    a0 += g0[i] * wi;
    a1 += g1[i] * wi;
    a2 += g2[i] * wi;
    a3 += g3[i] * wi;
    const S g_dot_f =
        g0[i] * f0 + g1[i] * f1 + g2[i] * f2 + g3[i] * f3 + g_extra_dot[i];
    // out = sum_i f_i a_i T_i + bg T_N: d out / d a_i = f_i T_i -
    // (everything behind i, background and 1 - alpha included) / (1 - a_i).
    const S g_alpha = g_dot_f * t_front - suffix[i] / one_minus;
    suffix[i] += g_dot_f * wi;  // wi = 0 where not live
    t[i] = t_front;
    // No gradient through the 0.99 clamp.
    const S g_sigma = live && r <= max_alpha ? -g_alpha * alpha : S(0);
    op += live && r <= max_alpha ? g_alpha * r * inv_opacity : S(0);
    const S dx = dx0 + static_cast<S>(i);
    ca += S(0.5) * dx * dx * g_sigma;
    cb += dx * dy * g_sigma;
    cc += S(0.5) * dy * dy * g_sigma;
    mx -= (g.ca * dx + g.cb * dy) * g_sigma;
    my -= (g.cb * dx + g.cc * dy) * g_sigma;
    used += live ? 1 : 0;
  }
  out->mx += mx;
  out->my += my;
  out->ca += ca;
  out->cb += cb;
  out->cc += cc;
  out->opacity += op;
  out->f0 += a0;
  out->f1 += a1;
  out->f2 += a2;
  out->f3 += a3;
  return used > 0;
}

}  // namespace

struct Rasterizer::State {
  std::optional<ProjectionCamera> camera;
  SplatView splats;
  RenderOptions options;
  int num_features = 4;  // r, g, b, depth, extras...

  std::vector<ProjectedSplat> projected;  // per input Gaussian
  std::vector<char> keep;                 // per input Gaussian
  std::vector<int> order;                 // visible input indices, by depth
  std::vector<int> tile_offsets;          // per tile, into tile_entries
  std::vector<int> tile_entries;          // indices into `order`
  std::vector<int> cursor;                // per tile, while binning
  std::vector<int> last;                  // per pixel: entries used + 1
  TileData<float> float_data;
  TileData<double> double_data;
  std::vector<float> float_scratch;   // per thread
  std::vector<double> double_scratch;
  std::vector<double> grad2d;         // per visible Gaussian
  long long pair_evaluations = 0;

  template <typename S>
  TileData<S>& data();
  template <typename S>
  std::vector<S>& scratch();

  void Project();
  void Bin();
  template <typename S>
  void Pack();
  template <typename S>
  void ForwardTiles(RenderResult* result);
  template <typename S>
  void BackwardTiles(const RenderGradients& image_grads);
  // Tiny renders (tests, thumbnails) run faster without thread start-up.
  bool ParallelTiles() const {
    return tile_entries.size() > kMinParallelEntries;
  }
  int ScratchPerThread() const {
    return kTilePixels * (num_features + 2) + num_features;
  }
};

template <>
TileData<float>& Rasterizer::State::data<float>() { return float_data; }
template <>
TileData<double>& Rasterizer::State::data<double>() { return double_data; }
template <>
std::vector<float>& Rasterizer::State::scratch<float>() {
  return float_scratch;
}
template <>
std::vector<double>& Rasterizer::State::scratch<double>() {
  return double_scratch;
}

void Rasterizer::State::Project() {
  const int n = splats.count;
  projected.resize(n);
  keep.resize(n);
#pragma omp parallel for schedule(static, 1024) if (n > kMinParallelSplats)
  for (int i = 0; i < n; ++i) {
    keep[i] = ProjectSplat(*camera, splats, i, &projected[i]);
  }
  order.clear();
  for (int i = 0; i < n; ++i) {
    if (keep[i]) order.push_back(i);
  }
  // Front to back; ties broken by index so the order is deterministic.
  std::sort(order.begin(), order.end(), [this](int a, int b) {
    const double da = projected[a].depth, db = projected[b].depth;
    return da < db || (da == db && a < b);
  });
}

void Rasterizer::State::Bin() {
  const int num_tiles = camera->tiles_x * camera->tiles_y;
  tile_offsets.assign(num_tiles + 1, 0);
  for (int v : order) {
    const ProjectedSplat& p = projected[v];
    for (int ty = p.tile_y0; ty < p.tile_y1; ++ty) {
      for (int tx = p.tile_x0; tx < p.tile_x1; ++tx) {
        ++tile_offsets[ty * camera->tiles_x + tx + 1];
      }
    }
  }
  std::partial_sum(tile_offsets.begin(), tile_offsets.end(),
                   tile_offsets.begin());
  tile_entries.resize(tile_offsets.back());
  // Filling in depth order keeps every tile's list depth sorted.
  cursor.assign(tile_offsets.begin(), tile_offsets.end() - 1);
  for (int k = 0; k < static_cast<int>(order.size()); ++k) {
    const ProjectedSplat& p = projected[order[k]];
    for (int ty = p.tile_y0; ty < p.tile_y1; ++ty) {
      for (int tx = p.tile_x0; tx < p.tile_x1; ++tx) {
        tile_entries[cursor[ty * camera->tiles_x + tx]++] = k;
      }
    }
  }
}

template <typename S>
void Rasterizer::State::Pack() {
  TileData<S>& d = data<S>();
  const int count = static_cast<int>(order.size());
  d.geom.resize(static_cast<size_t>(kGeomStride) * count);
  d.feature.resize(static_cast<size_t>(num_features) * count);
  d.box.resize(4 * static_cast<size_t>(count));
  const int num_extra = splats.num_extra;
#pragma omp parallel for schedule(static, 1024) \
    if (count > kMinParallelSplats)
  for (int k = 0; k < count; ++k) {
    const int n = order[k];
    const ProjectedSplat& p = projected[n];
    S* geo = &d.geom[static_cast<size_t>(kGeomStride) * k];
    geo[0] = static_cast<S>(p.mean2d[0]);
    geo[1] = static_cast<S>(p.mean2d[1]);
    geo[2] = static_cast<S>(p.conic[0]);
    geo[3] = static_cast<S>(p.conic[1]);
    geo[4] = static_cast<S>(p.conic[2]);
    geo[5] = static_cast<S>(p.opacity);
    int* box = &d.box[4 * static_cast<size_t>(k)];
    box[0] = p.px0;
    box[1] = p.px1;
    box[2] = p.py0;
    box[3] = p.py1;
    S* f = &d.feature[static_cast<size_t>(num_features) * k];
    f[0] = static_cast<S>(p.color[0]);
    f[1] = static_cast<S>(p.color[1]);
    f[2] = static_cast<S>(p.color[2]);
    f[3] = static_cast<S>(p.depth);
    for (int e = 0; e < num_extra; ++e) {
      f[4 + e] = static_cast<S>(splats.extra[n * num_extra + e]);
    }
  }
}

template <typename S>
void Rasterizer::State::ForwardTiles(RenderResult* result) {
  TileData<S>& d = data<S>();
  const int width = camera->width, height = camera->height;
  const int tiles_x = camera->tiles_x;
  const int num_tiles = tiles_x * camera->tiles_y;
  const int nf = num_features, num_extra = splats.num_extra;
  d.t_final.resize(static_cast<size_t>(width) * height);
  last.resize(static_cast<size_t>(width) * height);
  const int per_thread = ScratchPerThread();
  scratch<S>().resize(static_cast<size_t>(omp_get_max_threads()) *
                      per_thread);
  const Eigen::Vector3d& bg = options.background;
  long long evaluations = 0;

#pragma omp parallel for schedule(dynamic, 1) reduction(+ : evaluations) \
    if (ParallelTiles())
  for (int tile = 0; tile < num_tiles; ++tile) {
    // Per-pixel state of the tile, one array per quantity.
    S* t = &scratch<S>()[static_cast<size_t>(omp_get_thread_num()) *
                         per_thread];
    S* done = t + kTilePixels;
    S* accum = done + kTilePixels;  // nf arrays
    int tile_last[kTilePixels];
    S w[kTileSize], raw[kTileSize];
    const int x0 = (tile % tiles_x) * kTileSize;
    const int y0 = (tile / tiles_x) * kTileSize;
    const int x1 = std::min(x0 + kTileSize, width);
    const int y1 = std::min(y0 + kTileSize, height);
    std::fill(t, t + kTilePixels, S(1));
    std::fill(done, done + kTilePixels * (nf + 1), S(0));
    std::fill(tile_last, tile_last + kTilePixels, 0);
    int active = (x1 - x0) * (y1 - y0);
    const int begin = tile_offsets[tile], end = tile_offsets[tile + 1];
    for (int e = begin; e < end && active > 0; ++e) {
      const int k = tile_entries[e];
      const int* box = &d.box[4 * static_cast<size_t>(k)];
      const int bx0 = std::max(x0, box[0]), bx1 = std::min(x1, box[1]);
      const int by0 = std::max(y0, box[2]), by1 = std::min(y1, box[3]);
      if (bx0 >= bx1 || by0 >= by1) continue;
      evaluations += static_cast<long long>(bx1 - bx0) * (by1 - by0);
      const Footprint<S> g(&d.geom[static_cast<size_t>(kGeomStride) * k]);
      const S* f = &d.feature[static_cast<size_t>(nf) * k];
      const int n = bx1 - bx0;
      for (int y = by0; y < by1; ++y) {
        RowAlphas(g, y, bx0, bx1, raw);
        const int p = (y - y0) * kTileSize + (bx0 - x0);
        active -= CompositeRow(n, raw, f, e - begin + 1, t + p, done + p,
                               tile_last + p, accum + p,
                               accum + kTilePixels + p,
                               accum + 2 * kTilePixels + p,
                               accum + 3 * kTilePixels + p, w);
        for (int c = 4; c < nf; ++c) {
          S* acc = accum + c * kTilePixels + p;
          const S fc = f[c];
          for (int i = 0; i < n; ++i) acc[i] += w[i] * fc;
        }
      }
    }
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const int p = (y - y0) * kTileSize + (x - x0);
        const size_t pix = static_cast<size_t>(y) * width + x;
        const double tf = t[p];
        for (int c = 0; c < 3; ++c) {
          result->rgb[3 * pix + c] = accum[c * kTilePixels + p] + bg[c] * tf;
        }
        result->alpha[pix] = 1 - tf;
        result->depth[pix] = accum[3 * kTilePixels + p];
        for (int c = 0; c < num_extra; ++c) {
          result->extra[pix * num_extra + c] =
              accum[(4 + c) * kTilePixels + p];
        }
        d.t_final[pix] = t[p];
        last[pix] = tile_last[p];
      }
    }
  }
  pair_evaluations = evaluations;
}

template <typename S>
void Rasterizer::State::BackwardTiles(const RenderGradients& ig) {
  TileData<S>& d = data<S>();
  const int width = camera->width, height = camera->height;
  const int tiles_x = camera->tiles_x;
  const int num_tiles = tiles_x * camera->tiles_y;
  const int nf = num_features, num_extra = splats.num_extra;
  const int grad_stride = kGradHead + nf;
  grad2d.assign(static_cast<size_t>(grad_stride) * order.size(), 0.0);
  const int per_thread = ScratchPerThread();
  scratch<S>().resize(static_cast<size_t>(omp_get_max_threads()) *
                      per_thread);
  const Eigen::Vector3d& bg = options.background;

#pragma omp parallel for schedule(dynamic, 1) if (ParallelTiles())
  for (int tile = 0; tile < num_tiles; ++tile) {
    const int begin = tile_offsets[tile], end = tile_offsets[tile + 1];
    if (begin == end) continue;
    S* t = &scratch<S>()[static_cast<size_t>(omp_get_thread_num()) *
                         per_thread];
    S* suffix = t + kTilePixels;         // see BackwardRow
    S* g_feat = suffix + kTilePixels;    // nf arrays of pixel gradients
    S* acc_extra = g_feat + nf * kTilePixels;  // a Gaussian's, per extra
    int tile_last[kTilePixels] = {0};
    S w[kTileSize], raw[kTileSize], g_extra_dot[kTileSize];
    const int x0 = (tile % tiles_x) * kTileSize;
    const int y0 = (tile / tiles_x) * kTileSize;
    const int x1 = std::min(x0 + kTileSize, width);
    const int y1 = std::min(y0 + kTileSize, height);
    int max_last = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const int p = (y - y0) * kTileSize + (x - x0);
        const size_t pix = static_cast<size_t>(y) * width + x;
        double g_bg = 0;
        for (int c = 0; c < 3; ++c) {
          const double gc = ig.d_rgb ? ig.d_rgb[3 * pix + c] : 0.0;
          g_feat[c * kTilePixels + p] = static_cast<S>(gc);
          g_bg += gc * bg[c];
        }
        g_feat[3 * kTilePixels + p] =
            static_cast<S>(ig.d_depth ? ig.d_depth[pix] : 0.0);
        for (int c = 0; c < num_extra; ++c) {
          g_feat[(4 + c) * kTilePixels + p] = static_cast<S>(
              ig.d_extra ? ig.d_extra[pix * num_extra + c] : 0.0);
        }
        const double g_alpha = ig.d_alpha ? ig.d_alpha[pix] : 0.0;
        t[p] = d.t_final[pix];
        // The background term and alpha = 1 - T_final both scale T_final.
        suffix[p] = static_cast<S>((g_bg - g_alpha) * d.t_final[pix]);
        tile_last[p] = last[pix];
        max_last = std::max(max_last, last[pix]);
      }
    }
    std::fill(g_extra_dot, g_extra_dot + kTileSize, S(0));
    for (int e = begin + max_last - 1; e >= begin; --e) {
      const int k = tile_entries[e];
      const int* box = &d.box[4 * static_cast<size_t>(k)];
      const int bx0 = std::max(x0, box[0]), bx1 = std::min(x1, box[1]);
      const int by0 = std::max(y0, box[2]), by1 = std::min(y1, box[3]);
      if (bx0 >= bx1 || by0 >= by1) continue;
      const Footprint<S> g(&d.geom[static_cast<size_t>(kGeomStride) * k]);
      const S* f = &d.feature[static_cast<size_t>(nf) * k];
      const int n = bx1 - bx0;
      FootprintGradient<S> acc;
      std::fill(acc_extra, acc_extra + num_extra, S(0));
      bool touched = false;
      for (int y = by0; y < by1; ++y) {
        RowAlphas(g, y, bx0, bx1, raw);
        const int p = (y - y0) * kTileSize + (bx0 - x0);
        for (int c = 4; c < nf; ++c) {
          const S* gc = g_feat + c * kTilePixels + p;
          const S fc = f[c];
          for (int i = 0; i < n; ++i) {
            g_extra_dot[i] = (c == 4 ? S(0) : g_extra_dot[i]) + gc[i] * fc;
          }
        }
        touched |= BackwardRow(n, raw, g, f, e - begin, bx0, y,
                               tile_last + p, t + p, suffix + p,
                               g_feat + p, g_feat + kTilePixels + p,
                               g_feat + 2 * kTilePixels + p,
                               g_feat + 3 * kTilePixels + p, g_extra_dot, w,
                               &acc);
        for (int c = 4; c < nf; ++c) {
          const S* gc = g_feat + c * kTilePixels + p;
          S sum = 0;
          for (int i = 0; i < n; ++i) sum += gc[i] * w[i];
          acc_extra[c - 4] += sum;
        }
      }
      if (!touched) continue;
      const S local[kGradHead + 4] = {acc.mx, acc.my, acc.ca, acc.cb,
                                      acc.cc, acc.opacity, acc.f0, acc.f1,
                                      acc.f2, acc.f3};
      double* out = &grad2d[static_cast<size_t>(grad_stride) * k];
      for (int c = 0; c < kGradHead + 4; ++c) {
#pragma omp atomic
        out[c] += static_cast<double>(local[c]);
      }
      for (int c = 0; c < num_extra; ++c) {
#pragma omp atomic
        out[kGradHead + 4 + c] += static_cast<double>(acc_extra[c]);
      }
    }
  }
}

Rasterizer::Rasterizer() : state_(new State) {}
Rasterizer::~Rasterizer() { delete state_; }

int Rasterizer::num_visible() const {
  return static_cast<int>(state_->order.size());
}

long long Rasterizer::num_pair_evaluations() const {
  return state_->pair_evaluations;
}

void Rasterizer::Radii(std::vector<int>* radii) const {
  const State& s = *state_;
  radii->assign(s.splats.count, 0);
  for (int n : s.order) (*radii)[n] = s.projected[n].radius;
}

void Rasterizer::Mean2dGradients(std::vector<double>* grads) const {
  const State& s = *state_;
  grads->assign(2 * static_cast<size_t>(s.splats.count), 0.0);
  const size_t stride = kGradHead + s.num_features;
  if (s.grad2d.size() != stride * s.order.size()) return;  // no Backward
  for (size_t k = 0; k < s.order.size(); ++k) {
    (*grads)[2 * s.order[k]] = s.grad2d[stride * k];
    (*grads)[2 * s.order[k] + 1] = s.grad2d[stride * k + 1];
  }
}

void Rasterizer::Forward(const Camera& camera, const SplatView& splats,
                         const RenderOptions& options, RenderResult* result) {
  CHECK(camera.width > 0 && camera.height > 0 && camera.fx > 0 &&
        camera.fy > 0)
      << "invalid camera " << camera.width << "x" << camera.height;
  CHECK(splats.sh_degree >= 0 && splats.sh_degree <= kMaxShDegree);
  CHECK_GE(splats.num_extra, 0);
  State& s = *state_;
  s.camera.emplace(camera);
  s.splats = splats;
  s.options = options;
  s.num_features = 4 + splats.num_extra;
  s.grad2d.clear();  // belongs to the previous Forward
  s.Project();
  s.Bin();

  const size_t pixels = static_cast<size_t>(camera.width) * camera.height;
  result->width = camera.width;
  result->height = camera.height;
  result->rgb.resize(3 * pixels);
  result->alpha.resize(pixels);
  result->depth.resize(pixels);
  result->extra.resize(pixels * splats.num_extra);
  if (options.use_double) {
    s.Pack<double>();
    s.ForwardTiles<double>(result);
  } else {
    s.Pack<float>();
    s.ForwardTiles<float>(result);
  }
}

void Rasterizer::Backward(const RenderGradients& image_grads,
                          SplatGradients* grads) {
  State& s = *state_;
  CHECK(s.camera.has_value()) << "Backward before Forward";
  const SplatView& splats = s.splats;
  grads->Resize(splats.count, splats.sh_degree, splats.num_extra);
  if (s.options.use_double) {
    s.BackwardTiles<double>(image_grads);
  } else {
    s.BackwardTiles<float>(image_grads);
  }
  const int grad_stride = kGradHead + s.num_features;
  const int count = static_cast<int>(s.order.size());
  const int num_extra = splats.num_extra;
#pragma omp parallel for schedule(static, 256) \
    if (count > kMinParallelSplats)
  for (int k = 0; k < count; ++k) {
    const int n = s.order[k];
    const double* g2 = &s.grad2d[static_cast<size_t>(grad_stride) * k];
    ProjectedGradient pg;
    pg.mean2d[0] = g2[0];
    pg.mean2d[1] = g2[1];
    pg.conic[0] = g2[2];
    pg.conic[1] = g2[3];
    pg.conic[2] = g2[4];
    pg.opacity = g2[5];
    for (int c = 0; c < 3; ++c) pg.color[c] = g2[kGradHead + c];
    pg.depth = g2[kGradHead + 3];
    ProjectSplatBackward(*s.camera, splats, n, pg, grads);
    for (int e = 0; e < num_extra; ++e) {
      grads->extra[n * num_extra + e] = g2[kGradHead + 4 + e];
    }
  }
}

SplatView SplatView::Of(const GaussianSet& g) {
  SplatView v;
  v.count = g.size();
  v.sh_degree = g.sh_degree;
  v.means = g.means.data();
  v.log_scales = g.log_scales.data();
  v.quats = g.quats.data();
  v.opacity_logits = g.opacity_logits.data();
  v.sh = g.sh.data();
  return v;
}

void SplatGradients::Resize(int count, int sh_degree, int num_extra) {
  means.assign(3 * count, 0.0);
  log_scales.assign(3 * count, 0.0);
  quats.assign(4 * count, 0.0);
  opacity_logits.assign(count, 0.0);
  sh.assign(3 * NumShCoeffs(sh_degree) * count, 0.0);
  extra.assign(static_cast<size_t>(num_extra) * count, 0.0);
}

}  // namespace es
