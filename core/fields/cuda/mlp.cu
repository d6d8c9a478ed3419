// The MLP's dense layers on the device (Mlp, core/fields/mlp.h): each
// product tiled over kTile x kTile blocks of the batch and the layer's
// units, the tiles staged through shared memory. Double throughout (see
// field_kernels.h); sums run in another order than the CPU's kernels, so
// results agree to rounding.

#include "core/fields/cuda/field_kernels.h"
#include "core/base/cuda/cuda_check.h"

namespace es {
namespace cuda {
namespace {

constexpr int kTile = 16;
// Rows of the batch one block of the weight gradient sums before its
// atomic add (at least; more where the batch would need more than
// kMaxGridY blocks): enough work per block, enough blocks for a large
// batch.
constexpr int kGradientRows = 256;
constexpr int kMaxGridY = 65535;
constexpr int kThreads = 256;

__host__ __device__ int Tiles(long long n) {
  return static_cast<int>((n + kTile - 1) / kTile);
}

// blockIdx.x: tile of rows, blockIdx.y: tile of outputs; thread (tx, ty)
// computes y[row ty][output tx].
__global__ void ForwardKernel(int rows, int in, int out, const double* a,
                              const double* w, const double* b, bool relu,
                              double* y) {
  __shared__ double sa[kTile][kTile + 1];  // [row][k]
  __shared__ double sw[kTile][kTile + 1];  // [output][k]
  const int tx = threadIdx.x, ty = threadIdx.y;
  const int r0 = blockIdx.x * kTile, j0 = blockIdx.y * kTile;
  const int r = r0 + ty, j = j0 + tx;
  double acc = 0.0;
  for (int k0 = 0; k0 < in; k0 += kTile) {
    const int k = k0 + tx;
    sa[ty][tx] = r < rows && k < in ? a[static_cast<long long>(r) * in + k]
                                    : 0.0;
    sw[ty][tx] = j0 + ty < out && k < in
                     ? w[static_cast<long long>(j0 + ty) * in + k]
                     : 0.0;
    __syncthreads();
    for (int kk = 0; kk < kTile; ++kk) acc += sa[ty][kk] * sw[tx][kk];
    __syncthreads();
  }
  if (r >= rows || j >= out) return;
  double v = acc + b[j];
  if (relu && v < 0.0) v = 0.0;  // std::max(v, 0.0): NaN stays NaN
  y[static_cast<long long>(r) * out + j] = v;
}

// blockIdx.x: tile of rows, blockIdx.y: tile of inputs; thread (tx, ty)
// computes d[row ty][input tx] = sum_j g[row][j] w[j][input].
__global__ void InputGradientKernel(int rows, int out, int in,
                                    const double* g, const double* w,
                                    const double* relu_input,
                                    bool accumulate, double* d) {
  __shared__ double sg[kTile][kTile + 1];  // [row][j]
  __shared__ double sw[kTile][kTile + 1];  // [j][input]
  const int tx = threadIdx.x, ty = threadIdx.y;
  const int r0 = blockIdx.x * kTile, i0 = blockIdx.y * kTile;
  const int r = r0 + ty, i = i0 + tx;
  double acc = 0.0;
  for (int j0 = 0; j0 < out; j0 += kTile) {
    sg[ty][tx] = r < rows && j0 + tx < out
                     ? g[static_cast<long long>(r) * out + j0 + tx]
                     : 0.0;
    sw[ty][tx] = j0 + ty < out && i < in
                     ? w[static_cast<long long>(j0 + ty) * in + i]
                     : 0.0;
    __syncthreads();
    for (int jj = 0; jj < kTile; ++jj) acc += sg[ty][jj] * sw[jj][tx];
    __syncthreads();
  }
  if (r >= rows || i >= in) return;
  const long long at = static_cast<long long>(r) * in + i;
  if (relu_input != nullptr) {
    acc = relu_input[at] > 0.0 ? acc : 0.0;
  }
  d[at] = accumulate ? d[at] + acc : acc;
}

// blockIdx.x: tile of (output, input) pairs, input in+1 standing for the
// bias; blockIdx.y: block_rows rows of the batch. Thread (tx, ty) sums
// g[row][output ty] a[row][input tx] over those rows and adds it to dw (or
// db) atomically.
__global__ void WeightGradientKernel(int rows, int block_rows, int in,
                                     int out, const double* g,
                                     const double* a, double* dw,
                                     double* db) {
  __shared__ double sg[kTile][kTile + 1];  // [row][output]
  __shared__ double sa[kTile][kTile + 1];  // [row][input]
  const int tx = threadIdx.x, ty = threadIdx.y;
  const int input_tiles = Tiles(in + 1);
  const int j0 = (blockIdx.x / input_tiles) * kTile;
  const int i0 = (blockIdx.x % input_tiles) * kTile;
  const long long begin = static_cast<long long>(blockIdx.y) * block_rows;
  const int first = static_cast<int>(begin);
  const int last = static_cast<int>(min(static_cast<long long>(rows),
                                        begin + block_rows));
  double acc = 0.0;
  for (int r0 = first; r0 < last; r0 += kTile) {
    const int r = r0 + ty;
    const bool row = r < last;
    sg[ty][tx] = row && j0 + tx < out
                     ? g[static_cast<long long>(r) * out + j0 + tx]
                     : 0.0;
    const int i = i0 + tx;
    sa[ty][tx] = !row   ? 0.0
                 : i < in ? a[static_cast<long long>(r) * in + i]
                 : i == in ? 1.0  // the bias's input
                           : 0.0;
    __syncthreads();
    for (int rr = 0; rr < kTile; ++rr) acc += sg[rr][ty] * sa[rr][tx];
    __syncthreads();
  }
  const int j = j0 + ty, i = i0 + tx;
  if (j >= out || i > in) return;
  atomicAdd(i < in ? dw + static_cast<long long>(j) * in + i : db + j, acc);
}

__global__ void ScaleKernel(long long count, int dim, const double* scales,
                            const double* in, double* out) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i < count) out[i] = in[i] * scales[i % dim];
}

}  // namespace

void LayerForwardKernel(int rows, int in, int out, const double* a,
                        const double* w, const double* b, bool relu,
                        double* y) {
  if (rows == 0) return;
  ForwardKernel<<<dim3(Tiles(rows), Tiles(out)), dim3(kTile, kTile)>>>(
      rows, in, out, a, w, b, relu, y);
  ES_CUDA_CHECK_LAUNCH("LayerForwardKernel");
}

void LayerInputGradientKernel(int rows, int out, int in, const double* g,
                              const double* w, const double* relu_input,
                              bool accumulate, double* d) {
  if (rows == 0) return;
  InputGradientKernel<<<dim3(Tiles(rows), Tiles(in)), dim3(kTile, kTile)>>>(
      rows, out, in, g, w, relu_input, accumulate, d);
  ES_CUDA_CHECK_LAUNCH("LayerInputGradientKernel");
}

void LayerWeightGradientKernel(int rows, int in, int out, const double* g,
                               const double* a, double* dw, double* db) {
  if (rows == 0) return;
  // A multiple of the tile, so only the last block has a partial tile.
  auto blocks = [rows](long long block_rows) {
    return (rows + block_rows - 1) / block_rows;
  };
  int block_rows = kGradientRows;
  while (blocks(block_rows) > kMaxGridY) block_rows *= 2;
  const int chunks = static_cast<int>(blocks(block_rows));
  WeightGradientKernel<<<dim3(Tiles(out) * Tiles(in + 1), chunks),
                         dim3(kTile, kTile)>>>(rows, block_rows, in, out, g,
                                               a, dw, db);
  ES_CUDA_CHECK_LAUNCH("LayerWeightGradientKernel");
}

void ScaleColumnsKernel(long long count, int dim, const double* scales,
                        const double* in, double* out) {
  if (count == 0) return;
  const int blocks = static_cast<int>((count + kThreads - 1) / kThreads);
  ScaleKernel<<<blocks, kThreads>>>(count, dim, scales, in, out);
  ES_CUDA_CHECK_LAUNCH("ScaleColumnsKernel");
}

}  // namespace cuda
}  // namespace es
