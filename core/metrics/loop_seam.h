#ifndef EULERSPLAT_CORE_METRICS_LOOP_SEAM_H_
#define EULERSPLAT_CORE_METRICS_LOOP_SEAM_H_

#include <vector>

#include <opencv2/core.hpp>

namespace es {

// How visible the loop boundary is in a fixed-view animation with period L.
// The change between consecutive frames k and k + 1 is their mean absolute
// difference over pixels and channels (inside `mask` if one is given).
// Pairs with (first_frame + k + 1) a multiple of L cross a loop boundary;
// all others lie within a cycle. score = mean boundary change / mean
// within-cycle change: ~1 means the loop is seamless (the boundary looks
// like any other frame step), > 1 a visible jump, e.g. every Gaussian
// snapping back to its canonical position at once.
struct LoopSeamScore {
  double boundary_change = 0;
  double within_change = 0;
  // NaN if either set of pairs is empty. A still sequence scores 1; +inf
  // if only the boundary changes.
  double score = 0;
  int boundary_pairs = 0;
  int within_pairs = 0;
};

// frames: animation frames first_frame >= 0, first_frame + 1, ..., all the same
// size and type (any channel count, 8-bit or float). mask: empty, or H x W
// single channel, > 0.5 (or > 127 for 8-bit) marks the pixels counted.
// Needs more than L frames to see a boundary; use >= 3 cycles for a stable
// within-cycle mean.
LoopSeamScore ComputeLoopSeam(const std::vector<cv::Mat>& frames,
                              int cycle_length, int first_frame = 0,
                              const cv::Mat& mask = cv::Mat());

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_LOOP_SEAM_H_
