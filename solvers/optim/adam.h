#ifndef EULERSPLAT_SOLVERS_OPTIM_ADAM_H_
#define EULERSPLAT_SOLVERS_OPTIM_ADAM_H_

#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "core/model/gaussians.h"
#include "solvers/optim/adam_value.h"

namespace es {

struct AdamOptions {
  double beta1 = 0.9;
  double beta2 = 0.999;
  double eps = 1e-15;  // 3DGS's value: scales can have tiny gradients
};

// One bias-corrected Adam update (PyTorch's formulation) of a parameter
// block of n values at step t >= 1: m, v are the block's moments.
void AdamUpdate(const AdamOptions& options, int64_t t, double lr, int n,
                const double* grad, double* m, double* v, double* x);

// AdamUpdate in pieces: the constants of step t, then the update of values
// [begin, end), the same arithmetic value by value.
struct AdamStep : AdamConstants {
  AdamStep(const AdamOptions& options, int64_t t, double lr);
  void Update(int begin, int end, const double* grad, double* m, double* v,
              double* x) const {
    for (int i = begin; i < end; ++i) {
      AdamValueUpdate(*this, grad[i], &m[i], &v[i], &x[i]);
    }
  }
};

// Learning rates of the GaussianSet arrays; the SH array has one rate for
// its DC coefficients and one for the higher bands.
struct GaussianLearningRates {
  double means = 0;
  double log_scales = 0;
  double quats = 0;
  double opacity_logits = 0;
  double sh_dc = 0;
  double sh_rest = 0;
  double dynamic_logits = 0;
};

// Each GaussianSet array's rate, in kGaussianArrays order; the SH array's
// is its DC rate (the higher bands take sh_rest).
inline constexpr double GaussianLearningRates::*kArrayLearningRates[] = {
    &GaussianLearningRates::means,
    &GaussianLearningRates::log_scales,
    &GaussianLearningRates::quats,
    &GaussianLearningRates::opacity_logits,
    &GaussianLearningRates::sh_dc,
    &GaussianLearningRates::dynamic_logits,
};
static_assert(std::size(kArrayLearningRates) == kNumGaussianArrays,
              "one learning rate per GaussianSet array (kGaussianArrays)");

// GaussianAdam's whole state, as checkpoints store it.
struct GaussianAdamState {
  GaussianSet m, v;  // first and second moments
  int64_t step = 0;
};

// Adam over the GaussianSet parameter blocks. The moments are GaussianSets
// of the same shape, so densification and SH-degree changes edit them with
// the same operations as the parameters (new Gaussians start at zero
// moments, as in 3DGS).
class GaussianAdam {
 public:
  explicit GaussianAdam(const AdamOptions& options = {}) : options_(options) {}

  // Zero moments shaped like `params`; the step counter restarts.
  void Reset(const GaussianSet& params);
  // One step on every block with a non-zero learning rate.
  void Step(const GaussianLearningRates& lr, const GaussianSet& grad,
            GaussianSet* params);

  void Filter(const std::vector<bool>& keep);
  void AppendZeros(int count);
  void SetShDegree(int degree);
  void ResetOpacityMoments();

  int64_t step() const { return step_; }
  GaussianAdamState state() const { return {m_, v_, step_}; }
  void Restore(const GaussianAdamState& state);
  GaussianSet& m() { return m_; }
  GaussianSet& v() { return v_; }
  const GaussianSet& m() const { return m_; }
  const GaussianSet& v() const { return v_; }

 private:
  AdamOptions options_;
  int64_t step_ = 0;
  GaussianSet m_, v_;
};

// A GaussianSet of n Gaussians with every value zero (quaternions included),
// e.g. for gradients and moments.
GaussianSet ZeroGaussians(int n, int sh_degree);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_ADAM_H_
