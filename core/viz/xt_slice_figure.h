#ifndef EULERSPLAT_CORE_VIZ_XT_SLICE_FIGURE_H_
#define EULERSPLAT_CORE_VIZ_XT_SLICE_FIGURE_H_

#include <opencv2/core.hpp>
#include <string>

namespace es {

// An x-t slice a person reads at a glance (BGR, CV_8UC3): a title, the
// video's first frame with the sliced row drawn across it, and below it the
// slice (time downwards) enlarged to a readable size, with a time axis in
// frames on the left (loop boundaries, every `cycle_length` frames, marked
// in red), an x axis in pixels below and their labels. `frame`: CV_8UC3;
// `slice`: one row per frame, as wide as `frame`.
cv::Mat XtSliceFigure(const cv::Mat& frame, const cv::Mat& slice, int row,
                      int cycle_length, const std::string& title);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_XT_SLICE_FIGURE_H_
