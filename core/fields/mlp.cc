#include "core/fields/mlp.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <glog/logging.h>
#include <omp.h>

namespace es {
namespace {

// Rows per chunk: a chunk's activations of all layers stay in L2 cache.
constexpr int kChunkRows = 512;

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
  ws->hidden.resize(depth_);
  const size_t hidden_size = static_cast<size_t>(n) * width_;
  for (std::vector<double>& h : ws->hidden) {
    if (h.size() < hidden_size) h.resize(hidden_size);
  }
  // The products run over W_l^T (in_l x out_l), so their rows are outputs.
  ws->transposed.resize(num_params());
  for (int l = 0; l <= depth_; ++l) {
    const int in = layer_in(l), o = layer_out(l);
    const double* w = params + offsets_[l];
    double* wt = ws->transposed.data() + offsets_[l];
    for (int j = 0; j < o; ++j) {
      for (int i = 0; i < in; ++i) wt[i * o + j] = w[j * in + i];
    }
  }
  const int chunks = (n + kChunkRows - 1) / kChunkRows;
  // Inside a parallel region (a share of FrameComposer's) the calling
  // thread runs every chunk.
  const bool parallel = chunks > 1 && !omp_in_parallel();
#pragma omp parallel for schedule(static) if (parallel)
  for (int c = 0; c < chunks; ++c) {
    const int r0 = c * kChunkRows;
    ForwardRows(params, r0, std::min(kChunkRows, n - r0), input, out, ws);
  }
}

void Mlp::ForwardRows(const double* params, int r0, int rows,
                      const double* input, double* out,
                      MlpWorkspace* ws) const {
  for (int l = 0; l <= depth_; ++l) {
    const int in = layer_in(l), o = layer_out(l);
    const double* a =
        l == 0 ? input + static_cast<size_t>(r0) * in
               : ws->hidden[l - 1].data() + static_cast<size_t>(r0) * width_;
    double* y = l == depth_
                    ? out + static_cast<size_t>(r0) * o
                    : ws->hidden[l].data() + static_cast<size_t>(r0) * o;
    kernels_->multiply(rows, in, o, a, ws->transposed.data() + offsets_[l],
                       params + offsets_[l] + o * in, /*accumulate=*/false, y);
    if (l < depth_) {
      const size_t size = static_cast<size_t>(rows) * o;
      for (size_t i = 0; i < size; ++i) y[i] = std::max(y[i], 0.0);
    }
  }
}

void Mlp::Backward(const double* params, const double* d_out, double* d_params,
                   double* d_input, MlpWorkspace* ws) const {
  const int n = ws->batch;
  CHECK(ws->input != nullptr) << "Mlp::Backward before Forward";
  if (depth_ > 0) {
    const size_t size = static_cast<size_t>(n) * width_;
    if (ws->grad.size() < size) ws->grad.resize(size);
    if (ws->grad_prev.size() < size) ws->grad_prev.resize(size);
  }
  const int chunks = (n + kChunkRows - 1) / kChunkRows;
  const int threads =
      chunks > 1 && !omp_in_parallel() ? omp_get_max_threads() : 1;
  // Zeroed here, not by their threads: the team may get fewer threads.
  if (d_params != nullptr) {
    ws->thread_grads.resize(threads - 1);
    for (std::vector<double>& g : ws->thread_grads) {
      g.assign(num_params(), 0.0);
    }
  }
#pragma omp parallel num_threads(threads)
  {
    const int id = omp_get_thread_num();
    double* grads = d_params;
    if (d_params != nullptr && id > 0) grads = ws->thread_grads[id - 1].data();
#pragma omp for schedule(static)
    for (int c = 0; c < chunks; ++c) {
      const int r0 = c * kChunkRows;
      BackwardRows(params, r0, std::min(kChunkRows, n - r0), d_out, grads,
                   d_input, ws);
    }
  }
  if (d_params == nullptr) return;
  for (int t = 0; t + 1 < threads; ++t) {
    const double* g = ws->thread_grads[t].data();
    for (int i = 0; i < num_params(); ++i) d_params[i] += g[i];
  }
}

void Mlp::BackwardRows(const double* params, int r0, int rows,
                       const double* d_out, double* d_params, double* d_input,
                       MlpWorkspace* ws) const {
  // Layer by layer from the output; `g` is dL/d(layer output), written into
  // grad and grad_prev alternately.
  const double* g = d_out + static_cast<size_t>(r0) * output_dim_;
  std::vector<double>* buffers[2] = {&ws->grad, &ws->grad_prev};
  for (int l = depth_; l >= 0; --l) {
    const int in = layer_in(l), o = layer_out(l);
    const double* w = params + offsets_[l];
    const double* a =
        l == 0 ? ws->input + static_cast<size_t>(r0) * in
               : ws->hidden[l - 1].data() + static_cast<size_t>(r0) * width_;
    if (d_params != nullptr) {
      double* dw = d_params + offsets_[l];
      kernels_->multiply_transposed(rows, o, in, g, a, dw);
      double* db = dw + o * in;
      for (int r = 0; r < rows; ++r) {
        for (int j = 0; j < o; ++j) db[j] += g[r * o + j];
      }
    }
    if (l == 0) {
      if (d_input != nullptr) {
        kernels_->multiply(rows, o, in, g, w, nullptr, /*accumulate=*/true,
                           d_input + static_cast<size_t>(r0) * in);
      }
      break;
    }
    // Through the ReLU of the previous layer: zero where it was inactive.
    double* next = buffers[l % 2]->data() + static_cast<size_t>(r0) * in;
    kernels_->multiply(rows, o, in, g, w, nullptr, /*accumulate=*/false, next);
    const size_t size = static_cast<size_t>(rows) * in;
    // A select, not a conditional store, so it vectorizes.
    for (size_t i = 0; i < size; ++i) next[i] = a[i] > 0.0 ? next[i] : 0.0;
    g = next;
  }
}

}  // namespace es
