#include "core/fields/positional_encoding.h"

#include <cmath>

#include <glog/logging.h>

namespace es {

void EncodeSinusoidal(double value, int num_frequencies, double period,
                      double* out) {
  CHECK_GT(period, 0.0);
  double angle = 2.0 * M_PI * value / period;
  for (int k = 0; k < num_frequencies; ++k) {
    out[2 * k] = std::sin(angle);
    out[2 * k + 1] = std::cos(angle);
    angle *= 2.0;
  }
}

}  // namespace es
