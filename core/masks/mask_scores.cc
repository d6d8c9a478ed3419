#include "core/masks/mask_scores.h"

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

namespace es {
namespace {

cv::Mat Binary(const cv::Mat& m) {
  cv::Mat f, out;
  m.convertTo(f, CV_32F, m.depth() == CV_8U ? 1.0 / 255 : 1.0);
  cv::threshold(f, out, 0.5, 1, cv::THRESH_BINARY);
  out.convertTo(out, CV_8U);
  return out;
}

}  // namespace

MaskScore ScoreMask(const cv::Mat& estimate, const cv::Mat& truth) {
  CHECK_EQ(estimate.size(), truth.size());
  const cv::Mat e = Binary(estimate), t = Binary(truth);
  const int both = cv::countNonZero(e & t);
  const int found = cv::countNonZero(e), real = cv::countNonZero(t);
  const int either = found + real - both;
  MaskScore s;
  if (either > 0) s.iou = static_cast<double>(both) / either;
  if (found > 0) s.precision = static_cast<double>(both) / found;
  if (real > 0) s.recall = static_cast<double>(both) / real;
  return s;
}

MaskScore MeanMaskScore(const std::vector<cv::Mat>& estimates,
                        const std::vector<cv::Mat>& truths) {
  CHECK_EQ(estimates.size(), truths.size());
  if (estimates.empty()) return MaskScore();
  MaskScore mean{0, 0, 0};
  const double n = static_cast<double>(estimates.size());
  for (size_t i = 0; i < estimates.size(); ++i) {
    const MaskScore s = ScoreMask(estimates[i], truths[i]);
    mean.iou += s.iou / n;
    mean.precision += s.precision / n;
    mean.recall += s.recall / n;
  }
  return mean;
}

double MaskIou(const cv::Mat& a, const cv::Mat& b) {
  return ScoreMask(a, b).iou;
}

}  // namespace es
