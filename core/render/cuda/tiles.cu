// The tile passes on the device, one block per 16x16 tile and one thread
// per pixel, walking the tile's depth-sorted list in batches staged in
// shared memory (as gsplat does). The per-pixel rules are those of
// tile_kernels_impl.h: a Gaussian counts only inside its pixel box, alpha =
// min(0.99, o exp(-sigma)), skipped where sigma < 0 or alpha < 1/255, and a
// pixel stops before its transmittance would fall below 1e-4. The CPU's row
// skip (RowReached) only leaves out pixels below 1/255, so it has no twin
// here. The backward sums each Gaussian's per-pixel gradients over a warp
// and adds them to its 2D gradient with one atomic add per warp.

#include "core/base/cuda/cuda_check.h"
#include "core/render/cuda/raster_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kBatch = kTileSize * kTileSize;  // one entry per thread
constexpr int kGradValues = kTileGradHead + kMaxDeviceFeatures;
constexpr unsigned kFullWarp = 0xffffffffu;

// A batch of a tile's entries in shared memory.
struct Batch {
  int id[kBatch];
  float geo[kBatch][6];  // mean x, y, conic a, b, c, opacity
  int box[kBatch][4];    // px0, px1, py0, py1
  float feature[kBatch][kMaxDeviceFeatures];
};

// Thread `slot` stages entry e of the sorted list.
__device__ inline void Stage(const TileArgs& a, int e, int slot, Batch* b) {
  const int n = a.gaussians[e];
  const ProjectedGaussian& p = a.projected[n];
  b->id[slot] = n;
  b->geo[slot][0] = p.mean[0];
  b->geo[slot][1] = p.mean[1];
  b->geo[slot][2] = p.conic[0];
  b->geo[slot][3] = p.conic[1];
  b->geo[slot][4] = p.conic[2];
  b->geo[slot][5] = p.opacity;
  b->box[slot][0] = p.px0;
  b->box[slot][1] = p.px1;
  b->box[slot][2] = p.py0;
  b->box[slot][3] = p.py1;
  const int nf = 4 + a.num_extra;
  const float* f = a.features + static_cast<size_t>(nf) * n;
  for (int c = 0; c < nf; ++c) b->feature[slot][c] = f[c];
}

// The Gaussian in slot j at pixel (x, y): o exp(-sigma) before the 0.99
// clamp, 0 outside its pixel box or where sigma < 0 (RowAlphas); dx, dy
// its offsets from the mean.
__device__ inline float RawAlpha(const Batch& b, int j, int x, int y,
                                 float* dx_out, float* dy_out) {
  const int* box = b.box[j];
  if (x < box[0] || x >= box[1] || y < box[2] || y >= box[3]) return 0.0f;
  const float* g = b.geo[j];
  const float dy = static_cast<float>(y) + 0.5f - g[1];
  const float dx = static_cast<float>(x) + 0.5f - g[0];
  const float sigma =
      0.5f * g[2] * dx * dx + g[3] * dy * dx + 0.5f * g[4] * dy * dy;
  *dx_out = dx;
  *dy_out = dy;
  if (!(sigma >= 0.0f)) return 0.0f;
  return g[5] * expf(-sigma);
}

__device__ inline float WarpSum(float v) {
  for (int offset = 16; offset > 0; offset /= 2)
    v += __shfl_down_sync(kFullWarp, v, offset);
  return v;
}

__global__ void __launch_bounds__(kBatch)
    ForwardKernel(TileArgs a) {
  __shared__ Batch batch;
  const int tile = blockIdx.y * a.tiles_x + blockIdx.x;
  const int x = blockIdx.x * kTileSize + threadIdx.x;
  const int y = blockIdx.y * kTileSize + threadIdx.y;
  const int thread = threadIdx.y * kTileSize + threadIdx.x;
  const bool inside = x < a.width && y < a.height;
  const int begin = a.ranges[2 * tile], end = a.ranges[2 * tile + 1];
  const int nf = 4 + a.num_extra;
  const float max_alpha = static_cast<float>(kMaxAlpha);
  const float min_alpha = static_cast<float>(kMinAlpha);
  const float min_t = static_cast<float>(kMinTransmittance);

  float t = 1.0f;
  float acc[kMaxDeviceFeatures];
#pragma unroll
  for (int c = 0; c < kMaxDeviceFeatures; ++c) acc[c] = 0.0f;
  int last = 0;
  bool done = !inside;  // pixels past the image's edge never take part
  for (int b = begin; b < end; b += kBatch) {
    // Also the barrier before the batch is overwritten; every thread gets
    // the same count, so all leave together.
    if (__syncthreads_count(done) == kBatch) break;
    if (b + thread < end) Stage(a, b + thread, thread, &batch);
    __syncthreads();
    const int count = min(kBatch, end - b);
    for (int j = 0; j < count && !done; ++j) {
      float dx, dy;
      const float raw = RawAlpha(batch, j, x, y, &dx, &dy);
      if (!(raw >= min_alpha)) continue;
      const float alpha = raw < max_alpha ? raw : max_alpha;
      const float next_t = t * (1.0f - alpha);
      if (next_t < min_t) {
        done = true;
        break;
      }
      const float w = alpha * t;
#pragma unroll
      for (int c = 0; c < kMaxDeviceFeatures; ++c)
        if (c < nf) acc[c] += w * batch.feature[j][c];
      t = next_t;
      last = b + j - begin + 1;
    }
  }
  if (!inside) return;
  const size_t pix = static_cast<size_t>(y) * a.width + x;
  for (int c = 0; c < 3; ++c) a.rgb[3 * pix + c] = acc[c] + a.background[c] * t;
  a.alpha[pix] = 1.0f - t;
  a.depth[pix] = acc[3];
#pragma unroll
  for (int e = 0; e < kMaxDeviceExtra; ++e)
    if (e < a.num_extra) a.extra[pix * a.num_extra + e] = acc[4 + e];
  a.t_final[pix] = t;
  a.last[pix] = last;
}

__global__ void __launch_bounds__(kBatch)
    BackwardKernel(TileArgs a) {
  __shared__ Batch batch;
  __shared__ int max_last;
  const int tile = blockIdx.y * a.tiles_x + blockIdx.x;
  const int x = blockIdx.x * kTileSize + threadIdx.x;
  const int y = blockIdx.y * kTileSize + threadIdx.y;
  const int thread = threadIdx.y * kTileSize + threadIdx.x;
  const int lane = thread % 32;
  const bool inside = x < a.width && y < a.height;
  const int begin = a.ranges[2 * tile];
  const int nf = 4 + a.num_extra;
  const int stride = kTileGradHead + nf;
  const float max_alpha = static_cast<float>(kMaxAlpha);
  const float min_alpha = static_cast<float>(kMinAlpha);

  // The pixel's gradients and the forward's final state
  // (LoadTileGradients): suffix = d loss / d T_final * T_final.
  float t = 1.0f, suffix = 0.0f;
  int last = 0;
  float g_feat[kMaxDeviceFeatures];
#pragma unroll
  for (int c = 0; c < kMaxDeviceFeatures; ++c) g_feat[c] = 0.0f;
  if (inside) {
    const size_t pix = static_cast<size_t>(y) * a.width + x;
    t = a.t_final[pix];
    last = a.last[pix];
    double g_t = 0;
    if (a.d_rgb != nullptr) {
      for (int c = 0; c < 3; ++c) {
        g_feat[c] = a.d_rgb[3 * pix + c];
        g_t += static_cast<double>(a.d_rgb[3 * pix + c]) * a.background[c];
      }
    }
    if (a.d_depth != nullptr) g_feat[3] = a.d_depth[pix];
    if (a.d_extra != nullptr) {
#pragma unroll
      for (int e = 0; e < kMaxDeviceExtra; ++e)
        if (e < a.num_extra) g_feat[4 + e] = a.d_extra[pix * a.num_extra + e];
    }
    if (a.d_alpha != nullptr) g_t -= a.d_alpha[pix];
    suffix = static_cast<float>(g_t * static_cast<double>(t));
  }
  if (thread == 0) max_last = 0;
  __syncthreads();
  if (last > 0) atomicMax(&max_last, last);
  __syncthreads();
  // Entries behind every pixel's last used one took no part.
  const int stop = begin + max_last;

  for (int b_end = stop; b_end > begin; b_end -= kBatch) {
    __syncthreads();  // the previous batch has been read
    // Back to front: slot j holds entry b_end - 1 - j.
    if (b_end - 1 - thread >= begin)
      Stage(a, b_end - 1 - thread, thread, &batch);
    __syncthreads();
    const int count = min(kBatch, b_end - begin);
    for (int j = 0; j < count; ++j) {
      const int rank = b_end - 1 - j - begin;  // 0-based, in the tile list
      float grad[kGradValues];
#pragma unroll
      for (int c = 0; c < kGradValues; ++c) grad[c] = 0.0f;
      bool live = inside && rank < last;
      float dx = 0, dy = 0, raw = 0;
      if (live) {
        raw = RawAlpha(batch, j, x, y, &dx, &dy);
        live = raw >= min_alpha;
      }
      if (live) {
        // BackwardRow: T in front of the Gaussian, then d out / d alpha =
        // f T - (everything behind, background included) / (1 - alpha).
        const float* g = batch.geo[j];
        const float* f = batch.feature[j];
        const float alpha = raw < max_alpha ? raw : max_alpha;
        const float inv_one_minus = 1.0f / (1.0f - alpha);
        const float t_front = t * inv_one_minus;
        const float w = alpha * t_front;
        float g_dot_f = 0.0f;
#pragma unroll
        for (int c = 0; c < kMaxDeviceFeatures; ++c) {
          if (c < nf) {
            grad[kTileGradHead + c] = g_feat[c] * w;
            g_dot_f += g_feat[c] * f[c];
          }
        }
        const float g_alpha = g_dot_f * t_front - suffix * inv_one_minus;
        suffix += g_dot_f * w;
        t = t_front;
        // No gradient through the 0.99 clamp; d alpha / d opacity =
        // exp(-sigma) = raw / opacity.
        if (raw <= max_alpha) {
          const float g_sigma = -g_alpha * alpha;
          grad[0] = -(g[2] * dx + g[3] * dy) * g_sigma;
          grad[1] = -(g[3] * dx + g[4] * dy) * g_sigma;
          grad[2] = 0.5f * dx * dx * g_sigma;
          grad[3] = dx * dy * g_sigma;
          grad[4] = 0.5f * dy * dy * g_sigma;
          grad[5] = g_alpha * raw / g[5];
        }
      }
      // The loop bounds are the block's, so every lane gets here.
      if (!__any_sync(kFullWarp, live)) continue;
      double* out = a.grad2d + static_cast<size_t>(stride) * batch.id[j];
#pragma unroll
      for (int c = 0; c < kGradValues; ++c) {
        if (c >= stride) continue;
        const float sum = WarpSum(grad[c]);
        if (lane == 0 && sum != 0.0f)
          atomicAdd(out + c, static_cast<double>(sum));
      }
    }
  }
}

}  // namespace

void RasterizeForward(const TileArgs& a) {
  if (a.tiles_x == 0 || a.tiles_y == 0) return;
  ForwardKernel<<<dim3(a.tiles_x, a.tiles_y), dim3(kTileSize, kTileSize)>>>(a);
  ES_CUDA_CHECK_LAUNCH("ForwardKernel");
}

void RasterizeBackward(const TileArgs& a) {
  if (a.tiles_x == 0 || a.tiles_y == 0) return;
  BackwardKernel<<<dim3(a.tiles_x, a.tiles_y), dim3(kTileSize, kTileSize)>>>(
      a);
  ES_CUDA_CHECK_LAUNCH("BackwardKernel");
}

}  // namespace cuda
}  // namespace es
