#ifndef EULERSPLAT_CORE_FIELDS_MOTION_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_MOTION_FIELD_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/fields/mlp.h"
#include "core/fields/triplane.h"

namespace es {

struct MotionFieldOptions {
  TriplaneOptions triplane;  // defaults: 128^2 x 12, product
  int mlp_width = 64;
  int mlp_depth = 2;  // hidden layers
  // V = velocity_scale * box diagonal * MLP output, so an MLP output of 1
  // moves a point by velocity_scale of the box diagonal per frame whatever
  // the scene's units: initialization and learning rates are scale-free.
  double velocity_scale = 0.01;
  // Output layer weights start this much smaller than Kaiming, so V ~ 0.
  double last_layer_init_scale = 0.01;
  uint32_t seed = 1;
};

// Read-only parameter pointers (Ceres blocks) a field is evaluated with; the
// field's own storage or, e.g., the arrays Ceres hands a cost function.
struct FieldParams {
  const double* triplane = nullptr;  // Triplane::num_params()
  const double* mlp = nullptr;       // Mlp::num_params()
};

// Gradient accumulators (+=); nullptr skips that block.
struct FieldGradients {
  double* triplane = nullptr;
  double* mlp = nullptr;
  // Nullable: one flag per chunk of the triplane gradient
  // (core/fields/gradient_chunks.h), set where Backward writes.
  char* triplane_chunks = nullptr;
};

// State of one Evaluate kept for Backward, row-major arrays; buffers only
// grow, so no allocation after the first call at the largest batch.
struct FieldWorkspace {
  int batch = 0;
  const double* x = nullptr;     // not owned; must outlive Backward
  std::vector<double> features;  // MLP input, batch x its input dim
  std::vector<double> d_features;
  std::vector<double> d_mlp_out;
  MlpWorkspace mlp;
};

// Resizes *buffer to at least `size` values, never shrinking it.
void Grow(size_t size, std::vector<double>* buffer);

// The static Eulerian velocity field V: R^3 -> R^3, V(x) = output_scale() *
// MLP(triplane(x)), displacement per frame in world units.
class MotionField {
 public:
  explicit MotionField(const MotionFieldOptions& options);

  // Sets the box (normally the dynamic Gaussians' bounds) the triplane spans
  // and that the output scale follows. Parameters are kept.
  void SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  // Re-draws the parameters from `seed`.
  void Initialize(uint32_t seed);

  const MotionFieldOptions& options() const { return options_; }
  const Triplane& triplane() const { return triplane_; }
  const Mlp& mlp() const { return mlp_; }
  double box_diagonal() const;
  // velocity_scale * box diagonal * the displacement factor.
  double output_scale() const;
  // Scales V's output, and so each Euler step: Stage 3's motion warm-up
  // starts the water at factor 0, where the loop is Stage 1's model, and
  // raises it to 1. Not saved with the field: a loaded field moves at 1.
  void SetDisplacementFactor(double factor) { displacement_factor_ = factor; }
  double displacement_factor() const { return displacement_factor_; }

  std::vector<double>& triplane_params() { return triplane_params_; }
  std::vector<double>& mlp_params() { return mlp_params_; }
  FieldParams params() const;

  // v (n x 3) = V(x (n x 3)), keeping state in *ws for Backward.
  void Evaluate(const FieldParams& p, int n, const double* x, double* v,
                FieldWorkspace* ws) const;
  // Backward of the last Evaluate on *ws: given d_v (n x 3), accumulates
  // parameter gradients into grads and dL/dx into d_x (n x 3, nullable).
  void Backward(const FieldParams& p, const double* d_v,
                const FieldGradients& grads, double* d_x,
                FieldWorkspace* ws) const;

 private:
  MotionFieldOptions options_;
  Triplane triplane_;
  Mlp mlp_;
  std::vector<double> triplane_params_, mlp_params_;
  double displacement_factor_ = 1.0;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_MOTION_FIELD_H_
