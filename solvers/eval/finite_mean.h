#ifndef EULERSPLAT_SOLVERS_EVAL_FINITE_MEAN_H_
#define EULERSPLAT_SOLVERS_EVAL_FINITE_MEAN_H_

#include <cmath>
#include <limits>

namespace es {

// Mean of the finite values added (NaN if none): a per-frame metric that is
// undefined on some frames (e.g. water PSNR without water) is averaged over
// the frames where it is defined.
class FiniteMean {
 public:
  void Add(double v) {
    if (!std::isfinite(v)) return;
    sum_ += v;
    ++count_;
  }
  double Get() const {
    return count_ ? sum_ / count_ : std::numeric_limits<double>::quiet_NaN();
  }

 private:
  double sum_ = 0;
  int count_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_FINITE_MEAN_H_
