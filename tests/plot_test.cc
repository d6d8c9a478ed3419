// The OpenCV line charts (es_plot) and the x-t slice helpers of es_animate.

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "core/viz/line_plot.h"
#include "core/viz/xt_slice.h"
#include "core/viz/xt_slice_figure.h"

namespace es {
namespace {

TEST(LinePlotTest, NiceTicksAreRoundAndCoverTheRange) {
  EXPECT_EQ(NiceTicks(0, 97, 5), (std::vector<double>{0, 20, 40, 60, 80, 100}));
  const std::vector<double> t = NiceTicks(0.013, 0.021, 4);
  ASSERT_GE(t.size(), 2u);
  EXPECT_LE(t.front(), 0.013);
  EXPECT_GE(t.back(), 0.021);
  EXPECT_NEAR(t[1] - t[0], 0.002, 1e-12);
  // A single value still gets an axis around it.
  const std::vector<double> flat = NiceTicks(5, 5, 4);
  EXPECT_LT(flat.front(), 5);
  EXPECT_GT(flat.back(), 5);
}

// Reads the pixel under a data point: the curve's colour must be there.
cv::Vec3b PixelAt(const cv::Mat& image, const PlotMapping& m, double x,
                  double y) {
  const cv::Point2d p = m.ToPixel(x, y);
  return image.at<cv::Vec3b>(static_cast<int>(std::lround(p.y)),
                             static_cast<int>(std::lround(p.x)));
}

bool Near(const cv::Vec3b& pixel, const cv::Scalar& color) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(pixel[c] - color[c]) > 40) return false;
  }
  return true;
}

TEST(LinePlotTest, CurvesPassThroughTheirDataPoints) {
  PlotSeries a{"a", {0, 10, 20, 30}, {1, 3, 2, 5}};
  PlotSeries b{"b", {0, 10, 20, 30}, {4, NAN, 4.5, 4}};  // NaN: skipped
  PlotOptions options;
  PlotMapping m;
  const cv::Mat image = DrawLinePlot({a, b}, options, &m);
  ASSERT_EQ(image.type(), CV_8UC3);
  EXPECT_EQ(image.cols, options.width);
  EXPECT_EQ(image.rows, options.height);
  // The axis spans the data with round ends.
  EXPECT_LE(m.x_lo, 0);
  EXPECT_GE(m.x_hi, 30);
  EXPECT_LE(m.y_lo, 1);
  EXPECT_GE(m.y_hi, 5);
  // Points of a and b that the legend does not cover.
  EXPECT_TRUE(Near(PixelAt(image, m, 10, 3), SeriesColor(0)));
  EXPECT_TRUE(Near(PixelAt(image, m, 20, 2), SeriesColor(0)));
  EXPECT_TRUE(Near(PixelAt(image, m, 20, 4.5), SeriesColor(1)));
  // Away from every curve and grid line the plot is white.
  const cv::Vec3b blank = PixelAt(image, m, 27, 1.3);
  EXPECT_EQ(blank, cv::Vec3b(255, 255, 255));
}

TEST(LinePlotTest, LogAxisMapsDecadesEvenly) {
  PlotSeries s{"loss", {0, 1, 2}, {1, 0.1, 0.01}};
  PlotOptions options;
  options.log_y = true;
  PlotMapping m;
  const cv::Mat image = DrawLinePlot({s}, options, &m);
  const double y0 = m.ToPixel(0, 1).y, y1 = m.ToPixel(0, 0.1).y,
               y2 = m.ToPixel(0, 0.01).y;
  EXPECT_NEAR(y1 - y0, y2 - y1, 1e-9);
  EXPECT_GT(y2, y0);  // smaller values lower on the image
  EXPECT_TRUE(Near(PixelAt(image, m, 1, 0.1), SeriesColor(0)));
}

TEST(LinePlotTest, EmptyDataStillDrawsAnAxis) {
  const cv::Mat image = DrawLinePlot({{"none", {1, 2}, {NAN, NAN}}}, {});
  EXPECT_FALSE(image.empty());
}

// Frames whose rows 30..34 change over time while the rest stays put.
std::vector<cv::Mat> MovingBandFrames(int count) {
  std::vector<cv::Mat> frames;
  for (int k = 0; k < count; ++k) {
    cv::Mat frame(60, 40, CV_8UC3, cv::Scalar(90, 90, 90));
    frame.rowRange(30, 35).setTo(cv::Scalar(40 * (k % 3), 200, 10 * k));
    // A single flickering row elsewhere must not win over the band.
    frame.row(5).setTo(cv::Scalar(k % 2 ? 255 : 0, 90, 90));
    frames.push_back(frame);
  }
  return frames;
}

TEST(XtSliceTest, AutoRowIsInTheMovingBand) {
  RowChange change;
  for (const cv::Mat& f : MovingBandFrames(8)) change.Add(f);
  const int row = change.BusiestRow();
  EXPECT_GE(row, 30);
  EXPECT_LE(row, 34);
  // Static rows accumulate nothing.
  EXPECT_EQ(change.per_row()[50], 0.0);
}

TEST(XtSliceTest, AutoRowWithoutChangeIsTheMiddle) {
  RowChange change;
  const cv::Mat still(60, 40, CV_8UC3, cv::Scalar(1, 2, 3));
  change.Add(still);
  change.Add(still);
  EXPECT_EQ(change.BusiestRow(), 30);
}

TEST(XtSliceTest, FigureShowsTheSliceEnlargedWithMargins) {
  const std::vector<cv::Mat> frames = MovingBandFrames(12);
  XtSlice slice(32);
  for (const cv::Mat& f : frames) slice.Add(f);
  const cv::Mat figure =
      XtSliceFigure(frames[0], slice.image(), 32, 4, "x-t slice of row 32");
  ASSERT_EQ(figure.type(), CV_8UC3);
  // Narrow videos are enlarged to a readable width, with axis margins.
  EXPECT_GE(figure.cols, 480);
  EXPECT_GT(figure.rows, 240 + frames[0].rows);
  // The slice's distinct colours (one per frame) all appear in the figure.
  for (int k = 0; k < 12; ++k) {
    const cv::Vec3b want = slice.image().at<cv::Vec3b>(k, 20);
    bool found = false;
    for (int y = 0; y < figure.rows && !found; ++y) {
      for (int x = 0; x < figure.cols && !found; ++x) {
        found = figure.at<cv::Vec3b>(y, x) == want;
      }
    }
    EXPECT_TRUE(found) << "frame " << k;
  }
}

}  // namespace
}  // namespace es
