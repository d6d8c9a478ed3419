#ifndef EULERSPLAT_CORE_FIELDS_MLP_H_
#define EULERSPLAT_CORE_FIELDS_MLP_H_

#include <cstdint>
#include <vector>

#include "core/fields/mlp_kernels.h"

namespace es {

// The arithmetic an Mlp runs in. Parameters, inputs, outputs and
// gradients are doubles either way; kFloat converts them at the network's
// edges and runs the layers in float, twice the lanes per vector (Stage 3
// trains its fields so; the gradient tests check kDouble).
enum class MlpPrecision { kDouble, kFloat };

// Activations and scratch of one precision, as row-major arrays.
template <typename T>
struct MlpBuffers {
  // Post-ReLU activations, one batch x width array per layer.
  std::vector<std::vector<T>> hidden;
  // dL/d(layer output), alternating layers (batch x width each).
  std::vector<T> grad, grad_prev;
  // Every layer's W_l^T (in_l x out_l) at W_l's offset and b_l after it,
  // for Forward.
  std::vector<T> transposed;
  // kFloat: the parameters as given, for Backward's products with W_l.
  std::vector<T> weights;
  // Parameter gradients of the threads that do not add into the caller's
  // array (kDouble: all but the first; kFloat: all), summed at the end.
  std::vector<std::vector<T>> thread_grads;
  // kFloat: the input, output, d_out and d_input rows in float.
  std::vector<T> input, out, d_out, d_input;
};

// What Mlp::Forward keeps for Mlp::Backward, and the backward scratch.
// Buffers only grow: no allocation after the first call at the largest
// batch size.
struct MlpWorkspace {
  int batch = 0;
  const double* input = nullptr;  // not owned; must outlive Backward
  MlpBuffers<double> f64;
  MlpBuffers<float> f32;
};

// Fully connected network: `depth` hidden layers of `width` ReLU units and a
// linear output layer. Batched over rows (batch x features, row-major): the
// batch is cut into chunks of rows that go through all layers while they
// sit in cache, chunks in parallel (OpenMP), each layer one product of
// core/fields/mlp_kernels.h for the best instruction set the CPU has, in
// double or float (MlpPrecision).
//
// Weights are ONE contiguous double array (a Ceres parameter block). Layer
// l = 0 .. depth maps in_l -> out_l (in_0 = input_dim, out_depth =
// output_dim, width otherwise) and stores W_l (out_l x in_l, row-major) then
// b_l (out_l), layer after layer.
class Mlp {
 public:
  Mlp(int input_dim, int width, int depth, int output_dim);

  int input_dim() const { return input_dim_; }
  int output_dim() const { return output_dim_; }
  int width() const { return width_; }
  int depth() const { return depth_; }
  int num_params() const { return offsets_.back(); }
  // The kernels' instruction set (kAuto: the best the CPU supports; tests
  // and benchmarks compare them).
  void set_simd_level(SimdLevel level) { kernels_ = &MlpKernels(level); }
  void set_precision(MlpPrecision precision) { precision_ = precision; }
  MlpPrecision precision() const { return precision_; }

  // Kaiming-uniform weights (bound sqrt(6 / in), seeded), zero biases; the
  // output layer's weights are multiplied by last_layer_scale so a new
  // network outputs nearly zero.
  void Initialize(uint32_t seed, double last_layer_scale, double* params) const;

  // out (n x output_dim) = MLP(input (n x input_dim)). Keeps the input
  // pointer and the activations in *ws for Backward.
  void Forward(const double* params, int n, const double* input, double* out,
               MlpWorkspace* ws) const;

  // Backward of the last Forward on *ws: given d_out (n x output_dim),
  // accumulates dL/dparams into d_params and dL/dinput into d_input
  // (n x input_dim). Either may be nullptr.
  void Backward(const double* params, const double* d_out, double* d_params,
                double* d_input, MlpWorkspace* ws) const;

 private:
  // Forward and Backward in T's arithmetic.
  template <typename T>
  void ForwardIn(const double* params, int n, double* out,
                 MlpWorkspace* ws) const;
  template <typename T>
  void BackwardIn(const double* params, const double* d_out, double* d_params,
                  double* d_input, MlpWorkspace* ws) const;
  // One chunk of rows [r0, r0 + rows) of Forward / Backward.
  template <typename T>
  void ForwardRows(int r0, int rows, double* out, MlpWorkspace* ws) const;
  template <typename T>
  void BackwardRows(const double* params, int r0, int rows, const double* d_out,
                    T* d_params, double* d_input, MlpWorkspace* ws) const;
  int layer_in(int l) const { return l == 0 ? input_dim_ : width_; }
  int layer_out(int l) const { return l == depth_ ? output_dim_ : width_; }

  int input_dim_, width_, depth_, output_dim_;
  std::vector<int> offsets_;  // start of W_l; offsets_.back() = total size
  const MlpKernelSet* kernels_;
  MlpPrecision precision_ = MlpPrecision::kDouble;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_MLP_H_
