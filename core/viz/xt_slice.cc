#include "core/viz/xt_slice.h"

#include <algorithm>
#include <string>

#include <opencv2/core.hpp>

#include <glog/logging.h>

#include "core/base/input_error.h"

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

void RowChange::Add(const cv::Mat& frame) {
  cv::Mat current;
  frame.convertTo(current, CV_64F);
  if (!previous_.empty()) {
    CHECK(current.size() == previous_.size() &&
          current.type() == previous_.type());
    cv::Mat difference = cv::abs(current - previous_);
    difference = difference.reshape(1, difference.rows);
    cv::Mat sums;
    cv::reduce(difference, sums, 1, cv::REDUCE_SUM, CV_64F);
    change_.resize(sums.rows, 0.0);
    for (int r = 0; r < sums.rows; ++r) change_[r] += sums.at<double>(r);
  }
  previous_ = current;
}

int RowChange::BusiestRow() const {
  constexpr int kBand = 2;
  const int rows = static_cast<int>(change_.size());
  if (rows == 0) return previous_.rows / 2;
  int best = rows / 2;
  double best_sum = 0;
  for (int r = 0; r < rows; ++r) {
    double sum = 0;
    for (int k = std::max(0, r - kBand); k <= std::min(rows - 1, r + kBand);
         ++k) {
      sum += change_[k];
    }
    if (sum > best_sum) {
      best_sum = sum;
      best = r;
    }
  }
  return best;
}

}  // namespace es
