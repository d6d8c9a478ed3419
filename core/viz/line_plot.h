#ifndef EULERSPLAT_CORE_VIZ_LINE_PLOT_H_
#define EULERSPLAT_CORE_VIZ_LINE_PLOT_H_

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace es {

// One curve. Points with a non-finite coordinate (a value not measured at
// that row, or <= 0 on a log axis) are skipped; the rest are joined in
// order and marked with dots when there are few of them.
struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
};

struct PlotOptions {
  std::string title, x_label, y_label;
  bool log_y = false;
  int width = 900, height = 560;
};

// "Nice" tick values (1, 2 or 5 times a power of ten apart) covering
// [lo, hi] with about `count` ticks; the first is <= lo, the last >= hi.
std::vector<double> NiceTicks(double lo, double hi, int count);

// Where data coordinates land in a plot image: the axes' data range and
// the pixel rectangle of the plotting area.
struct PlotMapping {
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;  // log10 values if log_y
  bool log_y = false;
  cv::Rect area;

  cv::Point2d ToPixel(double x, double y) const;
};

// A line chart on white with axes, ticks, labels, title and a legend,
// drawn with OpenCV (no plotting dependency): BGR, CV_8UC3. `mapping`, if
// given, receives the data-to-pixel mapping (for tests and overlays).
cv::Mat DrawLinePlot(const std::vector<PlotSeries>& series,
                     const PlotOptions& options,
                     PlotMapping* mapping = nullptr);

// The colour of the i-th series (BGR), distinct for the first eight.
cv::Scalar SeriesColor(int i);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_LINE_PLOT_H_
