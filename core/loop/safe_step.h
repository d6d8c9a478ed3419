#ifndef EULERSPLAT_CORE_LOOP_SAFE_STEP_H_
#define EULERSPLAT_CORE_LOOP_SAFE_STEP_H_

// The stress rule of EulerOptions for one point and its Jacobian, written
// once for EulerChain and LoopAnimator (euler_chain.cc) and their device
// twins (cuda/euler.cu): a non-finite velocity takes no step, one longer
// than max_step is shortened to it.

#include <cmath>

#include "core/base/host_device.h"

namespace es {

enum class StepKind { kPlain, kClamped, kNonFinite };

// Not NaN nor infinite (Inf - Inf and NaN - NaN are NaN).
ES_HOST_DEVICE inline bool FiniteValue(double v) { return v - v == 0.0; }

// Writes the step taken for velocity v.
ES_HOST_DEVICE inline StepKind SafeStep(const double* v, double max_step,
                                        double* step) {
  if (!FiniteValue(v[0]) || !FiniteValue(v[1]) || !FiniteValue(v[2])) {
    step[0] = step[1] = step[2] = 0.0;
    return StepKind::kNonFinite;
  }
  const double norm = ::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  // Finite components can still overflow the norm: treat that as clamped.
  if (norm > max_step) {
    const double s = FiniteValue(norm) ? max_step / norm : 0.0;
    for (int j = 0; j < 3; ++j) step[j] = v[j] * s;
    return StepKind::kClamped;
  }
  for (int j = 0; j < 3; ++j) step[j] = v[j];
  return StepKind::kPlain;
}

// d_v = J^T g for the step function of SafeStep at v.
ES_HOST_DEVICE inline void SafeStepBackward(const double* v, double max_step,
                                            const double* g, double* d_v) {
  double step[3];
  switch (SafeStep(v, max_step, step)) {
    case StepKind::kPlain:
      for (int j = 0; j < 3; ++j) d_v[j] = g[j];
      return;
    case StepKind::kNonFinite:
      d_v[0] = d_v[1] = d_v[2] = 0.0;
      return;
    case StepKind::kClamped: {
      const double norm2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
      const double norm = ::sqrt(norm2);
      if (!FiniteValue(norm)) {
        d_v[0] = d_v[1] = d_v[2] = 0.0;
        return;
      }
      // (max_step / |v|) (I - v v^T / |v|^2) g
      const double vg = v[0] * g[0] + v[1] * g[1] + v[2] * g[2];
      for (int j = 0; j < 3; ++j) {
        d_v[j] = max_step / norm * (g[j] - v[j] * vg / norm2);
      }
      return;
    }
  }
}

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_SAFE_STEP_H_
