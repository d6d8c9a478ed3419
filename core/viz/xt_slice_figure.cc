#include "core/viz/xt_slice_figure.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/base/number_text.h"
#include "core/viz/line_plot.h"

namespace es {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kScale = 0.5;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kLoop(40, 40, 220);     // red: loop boundaries
const cv::Scalar kRowLine(0, 215, 255);  // yellow: the sliced row
// The slice is enlarged to about this size so a 60-frame, 160-px video is
// not a thin strip.
constexpr int kMinWidth = 480;
constexpr int kMinSliceHeight = 240;
constexpr int kMaxSliceHeight = 1200;

int TextWidth(const std::string& text) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, kScale, 1, &baseline).width;
}

void Text(cv::Mat* image, const std::string& text, cv::Point at,
          const cv::Scalar& color = kInk) {
  cv::putText(*image, text, at, kFont, kScale, color, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat XtSliceFigure(const cv::Mat& frame, const cv::Mat& slice, int row,
                      int cycle_length, const std::string& title) {
  CHECK_EQ(frame.type(), CV_8UC3);
  CHECK_EQ(slice.type(), CV_8UC3);
  CHECK_EQ(frame.cols, slice.cols);
  CHECK_GT(slice.rows, 0);
  const int sx = std::max(1, (kMinWidth + frame.cols - 1) / frame.cols);
  const int sy = std::clamp((kMinSliceHeight + slice.rows - 1) / slice.rows, 1,
                            std::max(1, kMaxSliceHeight / slice.rows));
  cv::Mat big_frame, big_slice;
  cv::resize(frame, big_frame, {frame.cols * sx, frame.rows * sx}, 0, 0,
             cv::INTER_NEAREST);
  cv::resize(slice, big_slice, {slice.cols * sx, slice.rows * sy}, 0, 0,
             cv::INTER_NEAREST);
  const int row_y = static_cast<int>((row + 0.5) * sx);
  cv::line(big_frame, {0, row_y}, {big_frame.cols - 1, row_y}, kRowLine,
           std::max(1, sx / 2), cv::LINE_AA);

  const int left = 78, right = 24, top = 40, gap = 34, bottom = 56;
  const int width =
      std::max(left + big_frame.cols + right, TextWidth(title) + 20);
  const int frame_top = top;
  const int slice_top = frame_top + big_frame.rows + gap;
  const int height = slice_top + big_slice.rows + bottom;
  cv::Mat figure(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  big_frame.copyTo(
      figure(cv::Rect(left, frame_top, big_frame.cols, big_frame.rows)));
  big_slice.copyTo(
      figure(cv::Rect(left, slice_top, big_slice.cols, big_slice.rows)));
  cv::rectangle(figure, {left - 1, slice_top - 1},
                {left + big_slice.cols, slice_top + big_slice.rows}, kInk, 1);

  Text(&figure, title, {std::max(4, width / 2 - TextWidth(title) / 2), 26});
  Text(&figure, "row " + std::to_string(row),
       {left - 8 - TextWidth("row " + std::to_string(row)),
        frame_top + row_y + 5},
       kInk);
  Text(&figure, "frame 0 with the sliced row (yellow)",
       {left, frame_top + big_frame.rows + 20});

  // Time axis: frames, downwards; loop boundaries in red, outside the data.
  for (double t : NiceTicks(0, slice.rows, 6)) {
    if (t > slice.rows) break;
    const int y = slice_top + static_cast<int>(t * sy);
    cv::line(figure, {left - 6, y}, {left - 1, y}, kInk, 1);
    const std::string tick = ShortNumber(t);
    Text(&figure, tick, {left - 10 - TextWidth(tick), y + 5});
  }
  if (cycle_length > 0) {
    for (int t = cycle_length; t < slice.rows; t += cycle_length) {
      const int y = slice_top + t * sy;
      cv::line(figure, {left - 14, y}, {left - 2, y}, kLoop, 2);
      cv::line(figure, {left + big_slice.cols + 1, y},
               {left + big_slice.cols + 12, y}, kLoop, 2);
    }
  }
  cv::Mat t_label(22, TextWidth("t (frame)") + 8, CV_8UC3,
                  cv::Scalar(255, 255, 255));
  Text(&t_label, "t (frame)", {4, 16});
  cv::rotate(t_label, t_label, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int label_y = slice_top + big_slice.rows / 2 - t_label.rows / 2;
  if (label_y >= 0 && label_y + t_label.rows <= figure.rows) {
    t_label.copyTo(figure(cv::Rect(4, label_y, t_label.cols, t_label.rows)));
  }

  // x axis: pixel columns.
  const int axis_y = slice_top + big_slice.rows;
  for (double x : NiceTicks(0, slice.cols, 6)) {
    if (x > slice.cols) break;
    const int px = left + static_cast<int>(x * sx);
    cv::line(figure, {px, axis_y}, {px, axis_y + 5}, kInk, 1);
    const std::string tick = ShortNumber(x);
    Text(&figure, tick, {px - TextWidth(tick) / 2, axis_y + 20});
  }
  std::string x_label = "x (pixel column)";
  if (cycle_length > 0) {
    x_label += "   red ticks: loop boundaries (every " +
               std::to_string(cycle_length) + " frames)";
  }
  Text(&figure, x_label,
       {left + big_slice.cols / 2 - TextWidth(x_label) / 2, axis_y + 44});
  return figure;
}

}  // namespace es
