#ifndef EULERSPLAT_CORE_MASKS_RESIDUAL_CHANGE_H_
#define EULERSPLAT_CORE_MASKS_RESIDUAL_CHANGE_H_

#include <vector>

#include <opencv2/core.hpp>

#include "core/model/camera.h"

namespace es {

// One frame's residual against a static model, with what is needed to find
// the same surface point in other frames.
struct ResidualFrame {
  Camera camera;
  cv::Mat residual;  // CV_32FC3, frame - static render (signed)
  cv::Mat depth;     // CV_32FC1, the static model's depth, 0 = no surface
  int time_index = 0;
};

struct ResidualChangeOptions {
  int gap = 4;        // video frames between compared frames
  int partners = 3;   // compared frames on each side: gap, 2 gap, ...
  int min_partners = 2;  // fewer known comparisons: unknown
  // Pixels of slack: a residual counts as unchanged when it lies within
  // the range of the other frame's carried residual over this radius.
  // Fine static texture (boards, gravel a few pixels wide) misregistered
  // by a pixel would otherwise look changed; 0: compare pixel to pixel.
  int tolerance = 1;
};

// How much each frame's residual differs from the same surface point's
// residual at other times: per pixel, the median over the partner frames
// (time_index +- k * gap) of |residual_i - residual_j carried to i by the
// camera motion over frame i's depth|, mean over channels. A static surface
// the model has not learned misfits the same way at every time, so its
// residual is carried along and cancels; water changes within a few frames
// and does not. Frames far apart in time make slow water decorrelate; the
// median ignores a partner that sees something else there (a disocclusion,
// a droplet passing). CV_32FC1 per frame; -1 where fewer than min_partners
// comparisons are known (no depth, or the point leaves the other view).
// With a tolerance, a comparison is the distance from the range of the
// carried residual around the pixel (0 inside it).
std::vector<cv::Mat> ResidualChange(const std::vector<ResidualFrame>& frames,
                                    const ResidualChangeOptions& options);

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_RESIDUAL_CHANGE_H_
