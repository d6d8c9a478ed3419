#include "core/viz/line_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/base/number_text.h"

namespace es {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTextScale = 0.5;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(225, 225, 225);
// Curves with at most this many points get a dot on each.
constexpr size_t kMaxDottedPoints = 40;

std::string TickText(double v) {
  return ShortNumber(std::abs(v) < 1e-12 ? 0.0 : v);
}

int TextWidth(const std::string& text, double scale = kTextScale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline).width;
}

void Text(cv::Mat* image, const std::string& text, cv::Point at,
          double scale = kTextScale, const cv::Scalar& color = kInk) {
  cv::putText(*image, text, at, kFont, scale, color, 1, cv::LINE_AA);
}

// Finite (and, for a log axis, positive) value, transformed to axis units.
bool AxisValue(double v, bool log, double* out) {
  if (!std::isfinite(v) || (log && v <= 0)) return false;
  *out = log ? std::log10(v) : v;
  return true;
}

// Ticks of a log axis spanning [lo, hi] (in log10 units): every power of
// ten, and 2 and 5 times them when the span is short.
std::vector<double> LogTicks(double lo, double hi) {
  std::vector<double> ticks;
  const bool fine = hi - lo < 2.5;
  for (int e = static_cast<int>(std::floor(lo));
       e <= static_cast<int>(std::ceil(hi)); ++e) {
    for (double m : {1.0, 2.0, 5.0}) {
      if (m != 1.0 && !fine) continue;
      const double t = e + std::log10(m);
      if (t >= lo - 1e-9 && t <= hi + 1e-9) ticks.push_back(t);
    }
  }
  return ticks;
}

}  // namespace

std::vector<double> NiceTicks(double lo, double hi, int count) {
  if (!(hi > lo)) {
    const double pad = lo == 0 ? 1.0 : std::abs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  const double raw = (hi - lo) / std::max(1, count);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * power;
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw * (1 - 1e-9)) {
      step = m * power;
      break;
    }
  }
  std::vector<double> ticks;
  const double first = std::floor(lo / step + 1e-9) * step;
  for (double t = first; t < hi + step * (1 - 1e-9); t += step) {
    ticks.push_back(t);
  }
  if (ticks.back() < hi - 1e-9 * step) ticks.push_back(ticks.back() + step);
  return ticks;
}

cv::Point2d PlotMapping::ToPixel(double x, double y) const {
  const double v = log_y ? std::log10(y) : y;
  return {area.x + (x - x_lo) / (x_hi - x_lo) * area.width,
          area.y + area.height - (v - y_lo) / (y_hi - y_lo) * area.height};
}

cv::Scalar SeriesColor(int i) {
  static const cv::Scalar kColors[] = {
      {180, 119, 31},  {14, 127, 255}, {44, 160, 44},   {40, 39, 214},
      {189, 103, 148}, {75, 86, 140},  {194, 119, 227}, {127, 127, 127}};
  return kColors[i % 8];
}

cv::Mat DrawLinePlot(const std::vector<PlotSeries>& series,
                     const PlotOptions& options, PlotMapping* mapping) {
  cv::Mat image(options.height, options.width, CV_8UC3,
                cv::Scalar(255, 255, 255));
  // Data range over every drawable point.
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  for (const PlotSeries& s : series) {
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      double x, y;
      if (!AxisValue(s.x[i], false, &x) ||
          !AxisValue(s.y[i], options.log_y, &y)) {
        continue;
      }
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
  }
  const bool empty = !std::isfinite(x_lo);
  if (empty) x_lo = y_lo = 0, x_hi = y_hi = 1;

  const std::vector<double> x_ticks = NiceTicks(x_lo, x_hi, 6);
  std::vector<double> y_ticks;
  PlotMapping m;
  m.log_y = options.log_y;
  m.x_lo = x_ticks.front();
  m.x_hi = x_ticks.back();
  if (options.log_y) {
    if (!(y_hi > y_lo)) y_lo -= 0.5, y_hi += 0.5;
    m.y_lo = y_lo - 0.03 * (y_hi - y_lo);
    m.y_hi = y_hi + 0.03 * (y_hi - y_lo);
    y_ticks = LogTicks(m.y_lo, m.y_hi);
  } else {
    y_ticks = NiceTicks(y_lo, y_hi, 6);
    m.y_lo = y_ticks.front();
    m.y_hi = y_ticks.back();
  }
  int label_width = 0;
  for (double t : y_ticks) {
    label_width = std::max(
        label_width, TextWidth(TickText(options.log_y ? std::pow(10, t) : t)));
  }
  const int left = 40 + label_width, right = 24, top = 44, bottom = 62;
  m.area = cv::Rect(left, top, options.width - left - right,
                    options.height - top - bottom);
  if (mapping != nullptr) *mapping = m;

  // Grid, ticks and tick labels.
  const cv::Rect& a = m.area;
  for (double t : x_ticks) {
    const int px = static_cast<int>(std::lround(m.ToPixel(t, 1).x));
    cv::line(image, {px, a.y}, {px, a.y + a.height}, kGrid, 1);
    const std::string text = TickText(t);
    Text(&image, text, {px - TextWidth(text) / 2, a.y + a.height + 20});
  }
  for (double t : y_ticks) {
    const double value = options.log_y ? std::pow(10, t) : t;
    const int py = static_cast<int>(std::lround(m.ToPixel(m.x_lo, value).y));
    cv::line(image, {a.x, py}, {a.x + a.width, py}, kGrid, 1);
    const std::string text = TickText(value);
    Text(&image, text, {a.x - 8 - TextWidth(text), py + 5});
  }
  cv::rectangle(image, a, kInk, 1);

  // Labels and title.
  Text(&image, options.x_label,
       {a.x + a.width / 2 - TextWidth(options.x_label) / 2,
        options.height - 14});
  cv::Mat y_label(24, std::max(1, TextWidth(options.y_label) + 8), CV_8UC3,
                  cv::Scalar(255, 255, 255));
  Text(&y_label, options.y_label, {4, 17});
  cv::rotate(y_label, y_label, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int label_y = std::max(0, a.y + a.height / 2 - y_label.rows / 2);
  if (label_y + y_label.rows <= image.rows) {
    y_label.copyTo(image(cv::Rect(4, label_y, y_label.cols, y_label.rows)));
  }
  Text(&image, options.title,
       {options.width / 2 - TextWidth(options.title, 0.6) / 2, 28}, 0.6);
  if (empty) {
    Text(&image, "no data", {a.x + a.width / 2 - 30, a.y + a.height / 2});
  }

  // Curves, clipped to the plotting area.
  cv::Mat area = image(a);
  const cv::Point2d origin(a.x, a.y);
  for (size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    std::vector<cv::Point> points;
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      double x, y;
      if (!AxisValue(s.x[i], false, &x) ||
          !AxisValue(s.y[i], options.log_y, &y)) {
        continue;
      }
      const cv::Point2d p = m.ToPixel(s.x[i], s.y[i]) - origin;
      points.emplace_back(static_cast<int>(std::lround(p.x)),
                          static_cast<int>(std::lround(p.y)));
    }
    const cv::Scalar color = SeriesColor(static_cast<int>(k));
    if (points.size() > 1) {
      cv::polylines(area, points, false, color, 2, cv::LINE_AA);
    }
    if (points.size() <= kMaxDottedPoints) {
      for (const cv::Point& p : points) {
        cv::circle(area, p, 4, color, cv::FILLED, cv::LINE_AA);
      }
    }
  }

  // Legend in the corner of the area that hides the fewest data points.
  int legend_width = 0;
  for (const PlotSeries& s : series) {
    legend_width = std::max(legend_width, TextWidth(s.label));
  }
  if (series.size() > 1 || (series.size() == 1 && !series[0].label.empty())) {
    const cv::Size box_size(legend_width + 46,
                            static_cast<int>(series.size()) * 20 + 8);
    const cv::Point corners[] = {
        {a.x + a.width - box_size.width - 6, a.y + 6},
        {a.x + a.width - box_size.width - 6,
         a.y + a.height - box_size.height - 6},
        {a.x + 6, a.y + 6},
        {a.x + 6, a.y + a.height - box_size.height - 6}};
    cv::Rect box(corners[0], box_size);
    int fewest = std::numeric_limits<int>::max();
    for (const cv::Point& corner : corners) {
      const cv::Rect candidate(corner, box_size);
      int hidden = 0;
      for (const PlotSeries& s : series) {
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
          double x, y;
          if (AxisValue(s.x[i], false, &x) &&
              AxisValue(s.y[i], options.log_y, &y)) {
            hidden += candidate.contains(m.ToPixel(s.x[i], s.y[i]));
          }
        }
      }
      if (hidden < fewest) {
        fewest = hidden;
        box = candidate;
      }
    }
    cv::rectangle(image, box, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(image, box, kGrid, 1);
    for (size_t k = 0; k < series.size(); ++k) {
      const int y = box.y + 16 + static_cast<int>(k) * 20;
      cv::line(image, {box.x + 6, y - 4}, {box.x + 34, y - 4},
               SeriesColor(static_cast<int>(k)), 3, cv::LINE_AA);
      Text(&image, series[k].label, {box.x + 40, y});
    }
  }
  return image;
}

}  // namespace es
