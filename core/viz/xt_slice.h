#ifndef EULERSPLAT_CORE_VIZ_XT_SLICE_H_
#define EULERSPLAT_CORE_VIZ_XT_SLICE_H_

#include <vector>

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

// Where a fixed-view video moves: per image row, the summed absolute change
// between consecutive frames. Static scenery adds nothing, moving water a
// lot, so the busiest row is the one an x-t slice should cut through.
class RowChange {
 public:
  // Adds a frame (any type; every frame the same size and type).
  void Add(const cv::Mat& frame);

  // The row of most change, summed over a band of +-2 rows so one noisy
  // row does not win over a band of water; the middle row before any
  // change was seen.
  int BusiestRow() const;
  const std::vector<double>& per_row() const { return change_; }

 private:
  cv::Mat previous_;
  std::vector<double> change_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_XT_SLICE_H_
