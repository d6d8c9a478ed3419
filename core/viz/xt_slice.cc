#include "core/viz/xt_slice.h"

#include <string>

#include <glog/logging.h>

#include "core/io/input_error.h"

namespace es {

void XtSlice::Add(const cv::Mat& frame) {
  if (row_ < 0 || row_ >= frame.rows) {
    throw InputError("--xt_slice: row " + std::to_string(row_) +
                     " is outside the " + std::to_string(frame.rows) +
                     "-row frame");
  }
  CHECK(slice_.empty() ||
        (frame.cols == slice_.cols && frame.type() == slice_.type()));
  slice_.push_back(frame.row(row_));
}

}  // namespace es
