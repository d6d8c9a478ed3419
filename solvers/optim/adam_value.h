#ifndef EULERSPLAT_SOLVERS_OPTIM_ADAM_VALUE_H_
#define EULERSPLAT_SOLVERS_OPTIM_ADAM_VALUE_H_

// Adam's update of one value, written once for AdamStep::Update (adam.h)
// and the device kernel (cuda/adam.cu).

#include <cmath>

#include "core/base/host_device.h"

namespace es {

// One step's constants at one learning rate: the moments' decays, eps,
// and the bias corrections folded into `step` and `inv_sqrt_bc2`.
struct AdamConstants {
  double beta1 = 0, beta2 = 0, eps = 0, step = 0, inv_sqrt_bc2 = 0;
};

// Moves x by one Adam step for gradient g, updating its moments m and v.
ES_HOST_DEVICE ES_FORCE_INLINE void AdamValueUpdate(const AdamConstants& c,
                                                    double g, double* m,
                                                    double* v, double* x) {
  *m = c.beta1 * *m + (1.0 - c.beta1) * g;
  *v = c.beta2 * *v + (1.0 - c.beta2) * g * g;
  *x -= c.step * *m / (::sqrt(*v) * c.inv_sqrt_bc2 + c.eps);
}

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_ADAM_VALUE_H_
