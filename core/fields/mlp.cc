#include "core/fields/mlp.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>

#include <glog/logging.h>
#include <omp.h>

namespace es {
namespace {

// Rows per chunk: a chunk's activations of all layers stay in L2 cache.
constexpr int kChunkRows = 512;

template <typename T>
constexpr bool kIsFloat = std::is_same_v<T, float>;

template <typename T>
MlpBuffers<T>& BuffersOf(MlpWorkspace* ws);
template <>
MlpBuffers<double>& BuffersOf(MlpWorkspace* ws) {
  return ws->f64;
}
template <>
MlpBuffers<float>& BuffersOf(MlpWorkspace* ws) {
  return ws->f32;
}

// The kernel set's products in T.
void Product(const MlpKernelSet& k, int rows, int kk, int n, const double* a,
             const double* b, const double* bias, bool accumulate, double* c) {
  k.multiply(rows, kk, n, a, b, bias, accumulate, c);
}
void Product(const MlpKernelSet& k, int rows, int kk, int n, const float* a,
             const float* b, const float* bias, bool accumulate, float* c) {
  k.multiply_float(rows, kk, n, a, b, bias, accumulate, c);
}
void ProductTransposed(const MlpKernelSet& k, int rows, int m, int n,
                       const double* a, const double* b, double* c) {
  k.multiply_transposed(rows, m, n, a, b, c);
}
void ProductTransposed(const MlpKernelSet& k, int rows, int m, int n,
                       const float* a, const float* b, float* c) {
  k.multiply_transposed_float(rows, m, n, a, b, c);
}

template <typename T>
void Grow(size_t size, std::vector<T>* buffer) {
  if (buffer->size() < size) buffer->resize(size);
}

// dst[i] = src[i] for i < count, converted.
template <typename To, typename From>
void Convert(const From* src, size_t count, To* dst) {
  for (size_t i = 0; i < count; ++i) dst[i] = static_cast<To>(src[i]);
}

}  // namespace

Mlp::Mlp(int input_dim, int width, int depth, int output_dim)
    : input_dim_(input_dim),
      width_(width),
      depth_(depth),
      output_dim_(output_dim),
      kernels_(&MlpKernels(SimdLevel::kAuto)) {
  CHECK_GE(input_dim, 1);
  CHECK_GE(output_dim, 1);
  CHECK_GE(depth, 0);
  CHECK(depth == 0 || width >= 1);
  offsets_.push_back(0);
  for (int l = 0; l <= depth_; ++l) {
    offsets_.push_back(offsets_.back() + layer_out(l) * (layer_in(l) + 1));
  }
}

void Mlp::Initialize(uint32_t seed, double last_layer_scale,
                     double* params) const {
  std::mt19937 rng(seed);
  for (int l = 0; l <= depth_; ++l) {
    double bound = std::sqrt(6.0 / layer_in(l));
    if (l == depth_) bound *= last_layer_scale;
    std::uniform_real_distribution<double> uniform(-bound, bound);
    double* w = params + offsets_[l];
    const int num_weights = layer_out(l) * layer_in(l);
    for (int i = 0; i < num_weights; ++i) w[i] = uniform(rng);
    for (int i = 0; i < layer_out(l); ++i) w[num_weights + i] = 0.0;
  }
}

void Mlp::Forward(const double* params, int n, const double* input, double* out,
                  MlpWorkspace* ws) const {
  ws->batch = n;
  ws->input = input;
  if (precision_ == MlpPrecision::kFloat) {
    ForwardIn<float>(params, n, out, ws);
  } else {
    ForwardIn<double>(params, n, out, ws);
  }
}

template <typename T>
void Mlp::ForwardIn(const double* params, int n, double* out,
                    MlpWorkspace* ws) const {
  MlpBuffers<T>& b = BuffersOf<T>(ws);
  b.hidden.resize(depth_);
  for (std::vector<T>& h : b.hidden) Grow(static_cast<size_t>(n) * width_, &h);
  if constexpr (kIsFloat<T>) {
    Grow(static_cast<size_t>(n) * input_dim_, &b.input);
    Grow(static_cast<size_t>(n) * output_dim_, &b.out);
    b.weights.resize(num_params());
    Convert(params, num_params(), b.weights.data());
  }
  // The products run over W_l^T (in_l x out_l), so their rows are outputs.
  b.transposed.resize(num_params());
  for (int l = 0; l <= depth_; ++l) {
    const int in = layer_in(l), o = layer_out(l);
    const double* w = params + offsets_[l];
    T* wt = b.transposed.data() + offsets_[l];
    for (int j = 0; j < o; ++j) {
      for (int i = 0; i < in; ++i)
        wt[i * o + j] = static_cast<T>(w[j * in + i]);
    }
    Convert(w + o * in, o, wt + o * in);
  }
  const int chunks = (n + kChunkRows - 1) / kChunkRows;
  // Inside a parallel region (a share of FrameComposer's) the calling
  // thread runs every chunk.
  const bool parallel = chunks > 1 && !omp_in_parallel();
#pragma omp parallel for schedule(static) if (parallel)
  for (int c = 0; c < chunks; ++c) {
    const int r0 = c * kChunkRows;
    ForwardRows<T>(r0, std::min(kChunkRows, n - r0), out, ws);
  }
}

template <typename T>
void Mlp::ForwardRows(int r0, int rows, double* out, MlpWorkspace* ws) const {
  MlpBuffers<T>& b = BuffersOf<T>(ws);
  const size_t in_offset = static_cast<size_t>(r0) * input_dim_;
  const size_t out_offset = static_cast<size_t>(r0) * output_dim_;
  const T* x;
  T* y_out;
  if constexpr (kIsFloat<T>) {
    Convert(ws->input + in_offset, static_cast<size_t>(rows) * input_dim_,
            b.input.data() + in_offset);
    x = b.input.data() + in_offset;
    y_out = b.out.data() + out_offset;
  } else {
    x = ws->input + in_offset;
    y_out = out + out_offset;
  }
  for (int l = 0; l <= depth_; ++l) {
    const int in = layer_in(l), o = layer_out(l);
    const T* a =
        l == 0 ? x : b.hidden[l - 1].data() + static_cast<size_t>(r0) * width_;
    T* y =
        l == depth_ ? y_out : b.hidden[l].data() + static_cast<size_t>(r0) * o;
    const T* wt = b.transposed.data() + offsets_[l];
    Product(*kernels_, rows, in, o, a, wt, wt + o * in, /*accumulate=*/false,
            y);
    if (l < depth_) {
      const size_t size = static_cast<size_t>(rows) * o;
      for (size_t i = 0; i < size; ++i) y[i] = std::max(y[i], T(0));
    }
  }
  if constexpr (kIsFloat<T>) {
    Convert(y_out, static_cast<size_t>(rows) * output_dim_, out + out_offset);
  }
}

void Mlp::Backward(const double* params, const double* d_out, double* d_params,
                   double* d_input, MlpWorkspace* ws) const {
  CHECK(ws->input != nullptr) << "Mlp::Backward before Forward";
  if (precision_ == MlpPrecision::kFloat) {
    BackwardIn<float>(params, d_out, d_params, d_input, ws);
  } else {
    BackwardIn<double>(params, d_out, d_params, d_input, ws);
  }
}

template <typename T>
void Mlp::BackwardIn(const double* params, const double* d_out,
                     double* d_params, double* d_input,
                     MlpWorkspace* ws) const {
  MlpBuffers<T>& b = BuffersOf<T>(ws);
  const int n = ws->batch;
  if (depth_ > 0) {
    Grow(static_cast<size_t>(n) * width_, &b.grad);
    Grow(static_cast<size_t>(n) * width_, &b.grad_prev);
  }
  if constexpr (kIsFloat<T>) {
    Grow(static_cast<size_t>(n) * output_dim_, &b.d_out);
    if (d_input != nullptr) {
      Grow(static_cast<size_t>(n) * input_dim_, &b.d_input);
    }
  }
  const int chunks = (n + kChunkRows - 1) / kChunkRows;
  const int threads =
      chunks > 1 && !omp_in_parallel() ? omp_get_max_threads() : 1;
  // In double the first thread adds into d_params itself; in float every
  // thread sums into a float array of its own. Zeroed here, not by their
  // threads: the team may get fewer threads.
  const int first_own = kIsFloat<T> ? 0 : 1;
  if (d_params != nullptr) {
    b.thread_grads.resize(threads - first_own);
    for (std::vector<T>& g : b.thread_grads) g.assign(num_params(), T(0));
  }
#pragma omp parallel num_threads(threads)
  {
    const int id = omp_get_thread_num();
    T* grads = nullptr;
    if (d_params != nullptr) {
      if constexpr (kIsFloat<T>) {
        grads = b.thread_grads[id].data();
      } else {
        grads = id == 0 ? d_params : b.thread_grads[id - 1].data();
      }
    }
#pragma omp for schedule(static)
    for (int c = 0; c < chunks; ++c) {
      const int r0 = c * kChunkRows;
      BackwardRows<T>(params, r0, std::min(kChunkRows, n - r0), d_out, grads,
                      d_input, ws);
    }
  }
  if (d_params == nullptr) return;
  for (const std::vector<T>& g : b.thread_grads) {
    for (int i = 0; i < num_params(); ++i) d_params[i] += g[i];
  }
}

template <typename T>
void Mlp::BackwardRows(const double* params, int r0, int rows,
                       const double* d_out, T* d_params, double* d_input,
                       MlpWorkspace* ws) const {
  MlpBuffers<T>& b = BuffersOf<T>(ws);
  const size_t in_offset = static_cast<size_t>(r0) * input_dim_;
  const size_t out_offset = static_cast<size_t>(r0) * output_dim_;
  // Layer by layer from the output; `g` is dL/d(layer output), written into
  // grad and grad_prev alternately.
  const T* g;
  const T* x;
  const T* weights;
  if constexpr (kIsFloat<T>) {
    Convert(d_out + out_offset, static_cast<size_t>(rows) * output_dim_,
            b.d_out.data() + out_offset);
    g = b.d_out.data() + out_offset;
    x = b.input.data() + in_offset;
    weights = b.weights.data();
  } else {
    g = d_out + out_offset;
    x = ws->input + in_offset;
    weights = params;
  }
  std::vector<T>* buffers[2] = {&b.grad, &b.grad_prev};
  for (int l = depth_; l >= 0; --l) {
    const int in = layer_in(l), o = layer_out(l);
    const T* w = weights + offsets_[l];
    const T* a =
        l == 0 ? x : b.hidden[l - 1].data() + static_cast<size_t>(r0) * width_;
    if (d_params != nullptr) {
      T* dw = d_params + offsets_[l];
      ProductTransposed(*kernels_, rows, o, in, g, a, dw);
      T* db = dw + o * in;
      for (int r = 0; r < rows; ++r) {
        for (int j = 0; j < o; ++j) db[j] += g[r * o + j];
      }
    }
    if (l == 0) {
      if (d_input == nullptr) break;
      if constexpr (kIsFloat<T>) {
        T* d_x = b.d_input.data() + in_offset;
        Product(*kernels_, rows, o, in, g, w, nullptr, /*accumulate=*/false,
                d_x);
        const size_t size = static_cast<size_t>(rows) * in;
        for (size_t i = 0; i < size; ++i) d_input[in_offset + i] += d_x[i];
      } else {
        Product(*kernels_, rows, o, in, g, w, nullptr, /*accumulate=*/true,
                d_input + in_offset);
      }
      break;
    }
    // Through the ReLU of the previous layer: zero where it was inactive.
    T* next = buffers[l % 2]->data() + static_cast<size_t>(r0) * in;
    Product(*kernels_, rows, o, in, g, w, nullptr, /*accumulate=*/false, next);
    const size_t size = static_cast<size_t>(rows) * in;
    // A select, not a conditional store, so it vectorizes.
    for (size_t i = 0; i < size; ++i) next[i] = a[i] > T(0) ? next[i] : T(0);
    g = next;
  }
}

}  // namespace es
