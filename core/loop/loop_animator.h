#ifndef EULERSPLAT_CORE_LOOP_LOOP_ANIMATOR_H_
#define EULERSPLAT_CORE_LOOP_LOOP_ANIMATOR_H_

#include <vector>

#include "core/fields/motion_field.h"
#include "core/loop/euler_chain.h"

namespace es {

// Alg. 2: looping animation at O(N) per frame. Start() places every
// Gaussian at its cycle index for a frame (Alg. 1, O(N L) once); Advance()
// then takes one Euler step per Gaussian per frame, resetting a Gaussian to
// its canonical position when its cycle index wraps from L - 1 to 0. The
// cycle number p is 0 at inference, so the animation has period L exactly.
class LoopAnimator {
 public:
  LoopAnimator(const MotionField* field, const EulerOptions& options,
               int cycle_length);

  // x0 (n x 3) is copied; start_times has n entries in [0, L).
  void Start(const FieldParams& params, int n, const double* x0,
             const std::vector<int>& start_times, int frame);
  void Advance(const FieldParams& params);

  int frame() const { return frame_; }
  // n x 3, in the order of x0.
  const std::vector<double>& positions() const { return positions_; }
  const std::vector<int>& cycle_indices() const { return cycle_index_; }
  // Accumulated since Start().
  const EulerStats& stats() const { return stats_; }

 private:
  const MotionField* field_;
  int cycle_length_;
  int frame_ = 0;
  std::vector<double> canonical_, positions_, velocity_;
  std::vector<int> cycle_index_;
  EulerChain chain_;
  EulerStats stats_;
  FieldWorkspace workspace_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_ANIMATOR_H_
