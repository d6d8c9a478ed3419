#include "solvers/pipeline/run_sheet.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/image_file.h"
#include "core/viz/video_writer.h"

namespace es {
namespace {

namespace fs = std::filesystem;

// Training plots (es_plot) that go on the contact sheet, in this order.
const char* const kSheetPlots[] = {"static_psnr.png", "joint_loss.png",
                                   "joint_psnr.png"};
// Height of a plot on the contact sheet: its text stays readable.
constexpr int kSheetPlotHeight = 400;

}  // namespace

void WriteRunContactSheet(const fs::path& out, int cycle_length) {
  std::vector<std::pair<cv::Mat, std::string>> tiles;
  const auto add = [&](const fs::path& dir, const std::string& label) {
    for (int k = 0; k < 4; ++k) {
      const int frame = k * cycle_length / 4;
      cv::Mat image = cv::imread(
          (dir / AnimationFrameName(frame)).string(), cv::IMREAD_COLOR);
      if (!image.empty()) {
        tiles.emplace_back(image, label + " t=" + std::to_string(frame));
      }
    }
  };
  add(out / "animate_fixed" / "frames", "fixed view");
  add(out / "animate" / "tracks", "tracks");
  std::vector<cv::Mat> plots;
  int plots_width = 0;
  for (const char* name : kSheetPlots) {
    cv::Mat plot = cv::imread((out / "plots" / name).string(),
                              cv::IMREAD_COLOR);
    if (plot.empty()) continue;
    cv::resize(plot, plot,
               {plot.cols * kSheetPlotHeight / plot.rows, kSheetPlotHeight},
               0, 0, cv::INTER_AREA);
    plots_width += plot.cols;
    plots.push_back(plot);
  }
  if (tiles.empty() && plots.empty()) return;
  const int columns = 4;
  cv::Size size(0, 0);
  if (!tiles.empty()) {
    size = tiles[0].first.size();
    const double grow = std::max(
        1.0, static_cast<double>(plots_width) / (columns * size.width));
    size = cv::Size(static_cast<int>(size.width * grow),
                    static_cast<int>(size.height * grow));
  }
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  const int width = std::max(columns * size.width, plots_width);
  const int plots_height = plots.empty() ? 0 : kSheetPlotHeight;
  cv::Mat sheet(rows * size.height + plots_height, width, CV_8UC3,
                cv::Scalar(40, 40, 40));
  for (size_t i = 0; i < tiles.size(); ++i) {
    cv::Mat tile = tiles[i].first;
    if (tile.size() != size) cv::resize(tile, tile, size);
    const cv::Rect where((i % columns) * size.width,
                         (i / columns) * size.height, size.width,
                         size.height);
    tile.copyTo(sheet(where));
    const double font = std::max(0.4, size.width / 640.0);
    cv::putText(sheet, tiles[i].second,
                where.tl() + cv::Point(6, static_cast<int>(20 * font / 0.5)),
                cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(255, 255, 255), 1,
                cv::LINE_AA);
  }
  int x = 0;
  for (const cv::Mat& plot : plots) {
    plot.copyTo(sheet(cv::Rect(x, rows * size.height, plot.cols, plot.rows)));
    x += plot.cols;
  }
  WriteImageAtomically((out / "contact_sheet.png").string(), sheet);
}

}  // namespace es
