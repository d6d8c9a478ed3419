#include "costs/joint_objective_options.h"

namespace es {

JointRenderTerms ImageGradientOnlyTerms() {
  JointRenderTerms none;
  none.photometric_weight = 0;
  return none;
}

uint64_t PairTextureDraw(int64_t draw, int frame_of_pair) {
  return 2 * static_cast<uint64_t>(draw) + frame_of_pair;
}

uint64_t LoopTextureDraw(int64_t draw) {
  return (uint64_t{1} << 40) + static_cast<uint64_t>(draw);
}

double UnrampedMean(double sum, int frames, double ramp, double weight) {
  // 0 at the ramp's start, where the terms vanish with it.
  return ramp > 0 ? sum / frames / (ramp * weight) : 0.0;
}

}  // namespace es
