#include "core/render/rasterizer.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>

#include <glog/logging.h>

#include "core/base/stage_profile.h"
#include "core/render/radix_sort.h"
#include "core/render/raster_project.h"

namespace es {
namespace {

// Per-Gaussian 2D gradient layout: d mean2d (2), d conic (3), d opacity (1),
// then one entry per feature (r, g, b, depth, extras).
constexpr int kGradHead = kTileGradHead;
// Below these sizes a parallel region costs more than it saves.
constexpr int kMinParallelSplats = 2048;
// Binning a Gaussian (two passes over its tiles) took ~0.2 us at 320x240.
constexpr int kMinParallelBinning = 2048;
constexpr size_t kMinParallelEntries = 256;

// out[0, stride) = the sum, in double, of the gradient shares (`stride`
// values each, one per tile of the Gaussian's tile rectangle p, row by
// row) of the tiles that used the Gaussian: those whose last used entry
// (tile_last_entry) is not in front of its depth index k. kStride > 0
// fixes the stride at compile time, so the sums stay in registers and the
// loop unrolls.
template <int kStride, typename S>
void SumShares(const S* share, const ProjectedSplat& p, int k, int tiles_x,
               const int* tile_last_entry, int stride, double* out) {
  if constexpr (kStride > 0) stride = kStride;
  double sum[kStride > 0 ? kStride : 1] = {};
  double* acc = kStride > 0 ? sum : out;
  if (kStride == 0)
    for (int c = 0; c < stride; ++c) out[c] = 0;
  for (int ty = p.tile_y0; ty < p.tile_y1; ++ty) {
    const int* last = tile_last_entry + ty * tiles_x;
    for (int tx = p.tile_x0; tx < p.tile_x1; ++tx, share += stride) {
      if (k > last[tx]) continue;
      for (int c = 0; c < stride; ++c) acc[c] += share[c];
    }
  }
  if constexpr (kStride > 0)
    for (int c = 0; c < kStride; ++c) out[c] = sum[c];
}

// The per-Gaussian data of the tile pass, in the precision of its loops
// (layouts: TilePass).
template <typename S>
struct TileData {
  std::vector<S> records;  // from records_begin, on a 64-byte line
  size_t records_begin = 0;
  std::vector<S> t_final;     // per pixel
  std::vector<S> entry_grad;  // per slot (TilePass::entry_grad)
};

}  // namespace

struct Rasterizer::State {
  std::optional<ProjectionCamera> camera;
  SplatView splats;
  RenderOptions options;
  int num_features = 4;  // r, g, b, depth, extras...

  std::vector<ProjectedSplat> projected;  // per input Gaussian
  std::vector<char> keep;                 // per input Gaussian
  // Per binned Gaussian k, what the binning needs: its tiles and its
  // first slot.
  struct BinItem {
    int tile_x0, tile_x1, tile_y0, tile_y1, slot;
  };
  // Sort items of the visible Gaussians: depth key, input index, and the
  // BinItem they carry through the sort, so the binning reads them in
  // depth order in sequence (a lookup of projected[] per Gaussian was a
  // cache miss each: ~40% of the binning's samples at 300k).
  struct SortItem {
    uint64_t key;
    int index;
    BinItem bin;
  };
  std::vector<SortItem> sort_items;
  std::vector<long long> run_counts;  // per thread: kept, tiles (prefix)
  RadixSortScratch<SortItem> sort_scratch;
  std::vector<int> order;                 // visible input indices, by depth
  std::vector<int> depth_rank;            // per input Gaussian: k, order[k] = n
  std::vector<int> tile_offsets;          // per tile, into tile_entries
  std::vector<int> tile_entries;          // indices into `order`
  // Per entry of tile_entries, its slot of the backward's gradient shares.
  // Input Gaussian n has the slots [slot_offsets[n], slot_offsets[n + 1])
  // (none if culled): the projection backward, in input order, reads them
  // all in sequence.
  std::vector<int> entry_slot;
  std::vector<int> slot_offsets;
  std::vector<int> cursor;                // per thread and tile, binning
  std::vector<BinItem> bin_items;         // per binned Gaussian k
  std::vector<int> last;                  // per pixel: entries used + 1
  std::vector<int> tile_last_entry;       // per tile (TilePass), backward
  TileData<float> float_data;
  TileData<double> double_data;
  std::vector<float> float_scratch;   // per thread
  std::vector<double> double_scratch;
  std::vector<double> grad2d;         // per input Gaussian (kept ones)
  bool has_grad2d = false;            // grad2d belongs to the last Forward
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
  TilePass<S> MakeTilePass();
  template <typename S>
  void ForwardTiles(RenderResult* result);
  template <typename S>
  void BackwardTiles(const RenderGradients& image_grads);
  // Whether every image gradient of the tile's pixels is zero.
  bool NoTileGradient(const RenderGradients& image_grads, int tile) const;
  // Sums each Gaussian's tile shares and chains them back to its
  // attributes (every value of *grads is written).
  template <typename S>
  void ProjectBackward(const std::vector<S>& entry_grad,
                       SplatGradients* grads);
  // Tiny renders (tests, thumbnails) run faster without thread start-up.
  bool ParallelTiles() const {
    return tile_entries.size() > kMinParallelEntries;
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
  ScopedStage timer(Stage::kProjection);
  const int n = splats.count;
  projected.resize(n);
  keep.resize(n);
  if (options.use_double) {
#pragma omp parallel for schedule(static, 1024) if (n > kMinParallelSplats)
    for (int i = 0; i < n; ++i) {
      keep[i] = ProjectSplat(*camera, splats, i, &projected[i]);
    }
  } else {
    const ProjectionInput in = MakeProjectionInput(*camera, splats);
    const auto forward = ProjectKernels(options.simd).forward;
    const int batches = (n + kProjectBatch - 1) / kProjectBatch;
#pragma omp parallel for schedule(static, 64) if (n > kMinParallelSplats)
    for (int b = 0; b < batches; ++b) {
      const int begin = b * kProjectBatch;
      forward(in, begin, std::min(kProjectBatch, n - begin),
              &projected[begin], &keep[begin]);
    }
  }
  ScopedStage sort_timer(Stage::kBinSort);
  // Front to back; ties broken by index so the order is deterministic.
  // Each thread takes one contiguous run of the input: it counts its kept
  // Gaussians and their tiles, then writes its sort items and slots after
  // the runs in front of it (the same for any thread count).
  const int threads = n > kMinParallelSplats ? omp_get_max_threads() : 1;
  slot_offsets.resize(n + 1);
  run_counts.assign(2 * (threads + 1), 0);
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const int i0 = static_cast<int>(static_cast<long long>(n) * t / nt);
    const int i1 = static_cast<int>(static_cast<long long>(n) * (t + 1) / nt);
    long long kept = 0, tiles = 0;
    for (int i = i0; i < i1; ++i) {
      if (!keep[i]) continue;
      const ProjectedSplat& p = projected[i];
      ++kept;
      tiles += (p.tile_x1 - p.tile_x0) * (p.tile_y1 - p.tile_y0);
    }
    run_counts[2 * (t + 1)] = kept;
    run_counts[2 * (t + 1) + 1] = tiles;
#pragma omp barrier
#pragma omp single
    {
      for (int r = 1; r <= nt; ++r) {
        run_counts[2 * r] += run_counts[2 * (r - 1)];
        run_counts[2 * r + 1] += run_counts[2 * (r - 1) + 1];
      }
      sort_items.resize(run_counts[2 * nt]);
      slot_offsets[n] = static_cast<int>(run_counts[2 * nt + 1]);
    }
    size_t item = run_counts[2 * t];
    int slots = static_cast<int>(run_counts[2 * t + 1]);
    for (int i = i0; i < i1; ++i) {
      slot_offsets[i] = slots;
      if (!keep[i]) continue;
      const ProjectedSplat& p = projected[i];
      const BinItem bin = {p.tile_x0, p.tile_x1, p.tile_y0, p.tile_y1, slots};
      sort_items[item++] = {NonNegativeDoubleKey(p.depth), i, bin};
      slots += (p.tile_x1 - p.tile_x0) * (p.tile_y1 - p.tile_y0);
    }
  }
  // Stable, and the items are in index order: ties stay in index order.
  RadixSortByKey(&sort_items, &sort_scratch, threads);
  const int count = static_cast<int>(sort_items.size());
  order.resize(count);
  bin_items.resize(count);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (int k = 0; k < count; ++k) {
    order[k] = sort_items[k].index;
    bin_items[k] = sort_items[k].bin;
  }
}

void Rasterizer::State::Bin() {
  ScopedStage timer(Stage::kBinSort);
  const int num_tiles = camera->tiles_x * camera->tiles_y;
  const int count = static_cast<int>(order.size());
  // Each thread bins one contiguous run of the depth order: it counts its
  // entries per tile, then fills them in after the runs in front of it, so
  // every tile's list is depth sorted and the same for any thread count.
  const int threads =
      count > kMinParallelBinning ? omp_get_max_threads() : 1;
  cursor.assign(static_cast<size_t>(threads) * num_tiles, 0);
  tile_offsets.assign(num_tiles + 1, 0);
  const auto for_each_tile = [&](const BinItem& b, auto&& visit) {
    for (int ty = b.tile_y0; ty < b.tile_y1; ++ty)
      for (int tx = b.tile_x0; tx < b.tile_x1; ++tx)
        visit(ty * camera->tiles_x + tx);
  };
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const int k0 = static_cast<int>(static_cast<long long>(count) * t / nt);
    const int k1 =
        static_cast<int>(static_cast<long long>(count) * (t + 1) / nt);
    int* mine = &cursor[static_cast<size_t>(t) * num_tiles];
    for (int k = k0; k < k1; ++k)
      for_each_tile(bin_items[k], [&](int tile) { ++mine[tile]; });
#pragma omp barrier
#pragma omp single
    {
      // Per tile: the runs' counts become the runs' start offsets.
      int total = 0;
      for (int tile = 0; tile < num_tiles; ++tile) {
        tile_offsets[tile] = total;
        for (int r = 0; r < nt; ++r) {
          int& c = cursor[static_cast<size_t>(r) * num_tiles + tile];
          const int n = c;
          c = total;
          total += n;
        }
      }
      tile_offsets[num_tiles] = total;
      tile_entries.resize(total);
      entry_slot.resize(total);
    }
    for (int k = k0; k < k1; ++k) {
      int next = bin_items[k].slot;
      for_each_tile(bin_items[k], [&](int tile) {
        const int e = mine[tile]++;
        tile_entries[e] = k;
        entry_slot[e] = next++;
      });
    }
  }
}

template <typename S>
void Rasterizer::State::Pack() {
  ScopedStage timer(Stage::kProjection);
  TileData<S>& d = data<S>();
  const int count = static_cast<int>(order.size());
  const int stride = TileRecordStride<S>(num_features);
  constexpr size_t kLine = 64 / sizeof(S);
  d.records.resize(static_cast<size_t>(stride) * count + kLine);
  d.records_begin =
      (kLine - reinterpret_cast<uintptr_t>(d.records.data()) / sizeof(S) %
                   kLine) % kLine;
  S* records = d.records.data() + d.records_begin;
  depth_rank.resize(splats.count);
  const int num_extra = splats.num_extra;
#pragma omp parallel for schedule(static, 1024) \
    if (count > kMinParallelSplats)
  for (int k = 0; k < count; ++k) {
    const int n = order[k];
    depth_rank[n] = k;
    const ProjectedSplat& p = projected[n];
    S* rec = records + static_cast<size_t>(stride) * k;
    S* box = rec + kTileRecordBox;
    box[0] = static_cast<S>(p.px0);
    box[1] = static_cast<S>(p.px1);
    box[2] = static_cast<S>(p.py0);
    box[3] = static_cast<S>(p.py1);
    S* geo = rec + kTileRecordGeom;
    geo[0] = static_cast<S>(p.mean2d[0]);
    geo[1] = static_cast<S>(p.mean2d[1]);
    geo[2] = static_cast<S>(p.conic[0]);
    geo[3] = static_cast<S>(p.conic[1]);
    geo[4] = static_cast<S>(p.conic[2]);
    geo[5] = static_cast<S>(p.opacity);
    rec[kTileRecordCutoff] = TileSigmaCutoff(static_cast<S>(p.opacity));
    S* f = rec + kTileRecordFeature;
    f[0] = static_cast<S>(p.color[0]);
    f[1] = static_cast<S>(p.color[1]);
    f[2] = static_cast<S>(p.color[2]);
    f[3] = static_cast<S>(p.depth);
    for (int e = 0; e < num_extra; ++e) {
      f[4 + e] = static_cast<S>(splats.extra[n * num_extra + e]);
    }
    for (int i = kTileRecordFeature + num_features; i < stride; ++i) {
      rec[i] = S(0);
    }
  }
}

template <typename S>
TilePass<S> Rasterizer::State::MakeTilePass() {
  TileData<S>& d = data<S>();
  TilePass<S> p;
  p.width = camera->width;
  p.height = camera->height;
  p.tiles_x = camera->tiles_x;
  p.num_features = num_features;
  p.num_extra = splats.num_extra;
  p.tile_offsets = tile_offsets.data();
  p.tile_entries = tile_entries.data();
  p.splat = d.records.data() + d.records_begin;
  p.record_stride = TileRecordStride<S>(num_features);
  for (int c = 0; c < 3; ++c) p.background[c] = options.background[c];
  p.t_final = d.t_final.data();
  p.last = last.data();
  return p;
}

template <typename S>
void Rasterizer::State::ForwardTiles(RenderResult* result) {
  ScopedStage timer(Stage::kForwardTiles);
  const size_t pixels = static_cast<size_t>(camera->width) * camera->height;
  data<S>().t_final.resize(pixels);
  last.resize(pixels);
  TilePass<S> pass = MakeTilePass<S>();
  pass.rgb = result->rgb.data();
  pass.alpha = result->alpha.data();
  pass.depth = result->depth.data();
  pass.extra = result->extra.data();
  const auto forward = TileKernels<S>(options.simd, num_features - 4).forward;
  const int per_thread = TileScratchSize(num_features);
  std::vector<S>& all_scratch = scratch<S>();
  all_scratch.resize(static_cast<size_t>(omp_get_max_threads()) * per_thread);
  const int num_tiles = camera->tiles_x * camera->tiles_y;
  long long evaluations = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : evaluations) \
    if (ParallelTiles())
  for (int tile = 0; tile < num_tiles; ++tile) {
    S* mine =
        &all_scratch[static_cast<size_t>(omp_get_thread_num()) * per_thread];
    evaluations += forward(pass, tile, mine);
  }
  pair_evaluations = evaluations;
}

template <typename S>
void Rasterizer::State::BackwardTiles(const RenderGradients& ig) {
  ScopedStage timer(Stage::kBackwardTiles);
  const int grad_stride = kGradHead + num_features;
  std::vector<S>& entry_grad = data<S>().entry_grad;
  entry_grad.resize(static_cast<size_t>(grad_stride) * tile_entries.size());
  TilePass<S> pass = MakeTilePass<S>();
  pass.d_rgb = ig.d_rgb;
  pass.d_alpha = ig.d_alpha;
  pass.d_depth = ig.d_depth;
  pass.d_extra = ig.d_extra;
  pass.entry_slot = entry_slot.data();
  pass.entry_grad = entry_grad.data();
  pass.grad_stride = grad_stride;
  tile_last_entry.resize(static_cast<size_t>(camera->tiles_x) *
                         camera->tiles_y);
  pass.tile_last_entry = tile_last_entry.data();
  const auto backward = TileKernels<S>(options.simd, num_features - 4).backward;
  const int per_thread = TileScratchSize(num_features);
  std::vector<S>& all_scratch = scratch<S>();
  all_scratch.resize(static_cast<size_t>(omp_get_max_threads()) * per_thread);
  const int num_tiles = camera->tiles_x * camera->tiles_y;
#pragma omp parallel for schedule(dynamic, 1) if (ParallelTiles())
  for (int tile = 0; tile < num_tiles; ++tile) {
    if (NoTileGradient(ig, tile)) {
      // Nothing to pass back (a loss that reads only some pixels, as the
      // loop texture's the water): no entry of the tile took part.
      tile_last_entry[tile] = -1;
      continue;
    }
    S* mine =
        &all_scratch[static_cast<size_t>(omp_get_thread_num()) * per_thread];
    backward(pass, tile, mine);
  }
}

bool Rasterizer::State::NoTileGradient(const RenderGradients& ig,
                                       int tile) const {
  const int width = camera->width, height = camera->height;
  const int x0 = (tile % camera->tiles_x) * kTileSize;
  const int y0 = (tile / camera->tiles_x) * kTileSize;
  const int x1 = std::min(x0 + kTileSize, width);
  const int y1 = std::min(y0 + kTileSize, height);
  // Each image's values of the tile's pixels, `channels` per pixel.
  const auto zero = [&](const double* image, int channels) {
    if (image == nullptr) return true;
    for (int y = y0; y < y1; ++y) {
      const double* row =
          image + (static_cast<size_t>(y) * width + x0) * channels;
      for (int i = 0; i < (x1 - x0) * channels; ++i)
        if (row[i] != 0) return false;
    }
    return true;
  };
  return zero(ig.d_rgb, 3) && zero(ig.d_alpha, 1) && zero(ig.d_depth, 1) &&
         zero(ig.d_extra, splats.num_extra);
}

template <typename S>
void Rasterizer::State::ProjectBackward(const std::vector<S>& entry_grad,
                                        SplatGradients* grads) {
  ScopedStage timer(Stage::kProjectionBackward);
  const int grad_stride = kGradHead + num_features;
  const int total = splats.count;
  const int coeffs = 3 * NumShCoeffs(splats.sh_degree);
  const int num_extra = splats.num_extra;
  grad2d.resize(static_cast<size_t>(grad_stride) * total);
  has_grad2d = true;
  const ProjectionInput in = MakeProjectionInput(*camera, splats);
  const ProjectionGradients out = MakeProjectionGradients(grads);
  const auto backward = ProjectKernels(options.simd).backward;
  // In input order, a batch of Gaussians at a time: each Gaussian's
  // attributes and gradients (SH degree 3: 768 bytes) are read and written
  // in sequence, not at random as the depth order would.
  const int batches = (total + kProjectBatch - 1) / kProjectBatch;
#pragma omp parallel for schedule(static, 16) if (total > kMinParallelSplats)
  for (int b = 0; b < batches; ++b) {
    const int begin = b * kProjectBatch;
    const int end = std::min(begin + kProjectBatch, total);
    for (int n = begin; n < end; ++n) {
      if (!keep[n]) {
        // Culled: zeros. The projection backward writes every value of a
        // kept Gaussian (and the loop below its extras).
        auto zero = [](std::vector<double>* v, size_t begin, size_t size) {
          std::fill(v->begin() + begin, v->begin() + begin + size, 0.0);
        };
        zero(&grads->means, 3 * static_cast<size_t>(n), 3);
        zero(&grads->log_scales, 3 * static_cast<size_t>(n), 3);
        zero(&grads->quats, 4 * static_cast<size_t>(n), 4);
        zero(&grads->opacity_logits, n, 1);
        zero(&grads->sh, static_cast<size_t>(coeffs) * n, coeffs);
        zero(&grads->extra, static_cast<size_t>(num_extra) * n, num_extra);
        continue;
      }
      // The Gaussian's gradient: its tiles' shares, summed in double.
      double* g2 = &grad2d[static_cast<size_t>(grad_stride) * n];
      const S* share =
          &entry_grad[static_cast<size_t>(grad_stride) * slot_offsets[n]];
      const ProjectedSplat& p = projected[n];
      const int k = depth_rank[n];
      const int* tile_last = tile_last_entry.data();
      const int tiles_x = camera->tiles_x;
      // No extra channel or one (the dynamic probability): fixed strides.
      if (grad_stride == kGradHead + 4) {
        SumShares<kGradHead + 4>(share, p, k, tiles_x, tile_last,
                                 grad_stride, g2);
      } else if (grad_stride == kGradHead + 5) {
        SumShares<kGradHead + 5>(share, p, k, tiles_x, tile_last,
                                 grad_stride, g2);
      } else {
        SumShares<0>(share, p, k, tiles_x, tile_last, grad_stride, g2);
      }
      for (int e = 0; e < num_extra; ++e) {
        grads->extra[n * num_extra + e] = g2[kGradHead + 4 + e];
      }
      if (!options.use_double) continue;
      ProjectedGradient pg;
      pg.mean2d[0] = g2[0];
      pg.mean2d[1] = g2[1];
      pg.conic[0] = g2[2];
      pg.conic[1] = g2[3];
      pg.conic[2] = g2[4];
      pg.opacity = g2[5];
      for (int c = 0; c < 3; ++c) pg.color[c] = g2[kGradHead + c];
      pg.depth = g2[kGradHead + 3];
      ProjectSplatBackward(*camera, splats, n, pg, grads);
    }
    if (!options.use_double) {
      backward(in, begin, end - begin, &keep[begin],
               &grad2d[static_cast<size_t>(grad_stride) * begin], grad_stride,
               out);
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
  if (!s.has_grad2d) return;  // no Backward since the last Forward
  for (int n : s.order) {
    (*grads)[2 * n] = s.grad2d[stride * n];
    (*grads)[2 * n + 1] = s.grad2d[stride * n + 1];
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
  s.has_grad2d = false;  // grad2d belongs to the previous Forward
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
  // Sized only: every value is written below (a full clear first was a
  // serial pass over all of them, 144 MB at 300k Gaussians of SH degree 3).
  const int coeffs = 3 * NumShCoeffs(splats.sh_degree);
  const int num_extra = splats.num_extra;
  grads->means.resize(3 * static_cast<size_t>(splats.count));
  grads->log_scales.resize(3 * static_cast<size_t>(splats.count));
  grads->quats.resize(4 * static_cast<size_t>(splats.count));
  grads->opacity_logits.resize(splats.count);
  grads->sh.resize(static_cast<size_t>(coeffs) * splats.count);
  grads->extra.resize(static_cast<size_t>(num_extra) * splats.count);
  if (s.options.use_double) {
    s.BackwardTiles<double>(image_grads);
    s.ProjectBackward(s.double_data.entry_grad, grads);
  } else {
    s.BackwardTiles<float>(image_grads);
    s.ProjectBackward(s.float_data.entry_grad, grads);
  }
}

}  // namespace es
