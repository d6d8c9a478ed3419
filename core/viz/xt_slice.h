#ifndef EULERSPLAT_CORE_VIZ_XT_SLICE_H_
#define EULERSPLAT_CORE_VIZ_XT_SLICE_H_

#include <opencv2/core.hpp>

namespace es {

// The x-t slice of a video: one image row per frame, row `row` of frame k
// becoming row k of the slice. In a fixed-view animation every loop
// boundary is a horizontal line of the slice, so a seam shows as a visible
// discontinuity there while a seamless loop shows only the water's streaks.
class XtSlice {
 public:
  explicit XtSlice(int row) : row_(row) {}

  // Appends row `row` of frame (any type; every frame the same width and
  // type). Throws InputError if the row is outside the frame.
  void Add(const cv::Mat& frame);

  int row() const { return row_; }
  int frames() const { return slice_.rows; }
  // frames() x width, the frames' type.
  const cv::Mat& image() const { return slice_; }

 private:
  int row_;
  cv::Mat slice_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_XT_SLICE_H_
