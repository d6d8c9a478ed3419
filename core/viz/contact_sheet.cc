#include "core/viz/contact_sheet.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr int kPairsPerRow = 2;
constexpr int kGap = 4;  // pixels between tiles

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

cv::Mat Read(const fs::path& path, int flags) {
  cv::Mat image = cv::imread(path.string(), flags);
  if (image.empty()) throw InputError(path.string() + ": cannot read image");
  return image;
}

}  // namespace

cv::Mat MakeContactSheet(const std::string& scene_dir, int count) {
  if (count < 1) throw InputError("contact sheet: --count must be >= 1");
  const fs::path images_dir = fs::path(scene_dir) / "images";
  const fs::path masks_dir = fs::path(scene_dir) / "masks";
  if (!fs::is_directory(images_dir))
    throw InputError(images_dir.string() + ": not a directory");
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(images_dir))
    if (entry.is_regular_file() && IsImageFile(entry.path()))
      frames.push_back(entry.path());
  if (frames.empty())
    throw InputError(images_dir.string() + ": no png/jpg frames");
  std::sort(frames.begin(), frames.end());
  count = std::min<int>(count, frames.size());

  const cv::Mat first = Read(frames.front(), cv::IMREAD_COLOR);
  const int w = first.cols, h = first.rows;
  const int rows = (count + kPairsPerRow - 1) / kPairsPerRow;
  const int columns = std::min(count, kPairsPerRow);
  cv::Mat sheet(rows * (h + kGap) + kGap, columns * (2 * w + 3 * kGap),
                CV_8UC3, cv::Scalar(40, 40, 40));
  for (int k = 0; k < count; ++k) {
    const size_t index =
        count > 1 ? k * (frames.size() - 1) / (count - 1) : 0;
    const fs::path& frame = frames[index];
    cv::Mat image = Read(frame, cv::IMREAD_COLOR);
    cv::resize(image, image, cv::Size(w, h));
    cv::Mat mask(h, w, CV_8UC3, cv::Scalar(128, 128, 128));
    const fs::path mask_path = masks_dir / frame.filename();
    if (fs::exists(mask_path)) {
      cv::Mat gray = Read(mask_path, cv::IMREAD_GRAYSCALE);
      cv::resize(gray, gray, cv::Size(w, h), 0, 0, cv::INTER_NEAREST);
      cv::cvtColor(gray, mask, cv::COLOR_GRAY2BGR);
    }
    const int x = (k % kPairsPerRow) * (2 * w + 3 * kGap) + kGap;
    const int y = (k / kPairsPerRow) * (h + kGap) + kGap;
    image.copyTo(sheet(cv::Rect(x, y, w, h)));
    mask.copyTo(sheet(cv::Rect(x + w + kGap, y, w, h)));
    const double font = std::max(0.3, h / 600.0);
    cv::putText(sheet, frame.filename().string(),
                cv::Point(x + 3, y + static_cast<int>(14 * font / 0.4)),
                cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(0, 255, 255), 1,
                cv::LINE_AA);
  }
  return sheet;
}

}  // namespace es
