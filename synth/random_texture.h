#ifndef EULERSPLAT_SYNTH_RANDOM_TEXTURE_H_
#define EULERSPLAT_SYNTH_RANDOM_TEXTURE_H_

#include <cstdint>

#include <opencv2/core.hpp>

namespace es {

// A smooth random float image in [0, 1] (CV_32FC(channels)) with detail at
// two scales (blurred noise of sigma 1.5 and 6 px, summed), so every pyramid
// level of an optical-flow estimator sees structure. Deterministic in seed.
cv::Mat TwoScaleTexture(int width, int height, int channels, uint64_t seed);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_RANDOM_TEXTURE_H_
