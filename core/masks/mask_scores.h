#ifndef EULERSPLAT_CORE_MASKS_MASK_SCORES_H_
#define EULERSPLAT_CORE_MASKS_MASK_SCORES_H_

#include <vector>

#include <opencv2/core.hpp>

namespace es {

// How well a mask matches a true one (both binary: > 0.5 of their range is
// water). IoU alone hides which way a mask is wrong: scenery taken for
// water lowers the precision, water missed the recall.
struct MaskScore {
  double iou = 1;        // 1 when both are empty
  double precision = 1;  // of the estimate's water, the true share; 1 if
                         // it has none (it claims nothing wrong)
  double recall = 1;     // of the true water, the found share; 1 if none
};

MaskScore ScoreMask(const cv::Mat& estimate, const cv::Mat& truth);

// The mean of each score over the frames (estimates[i] against
// truths[i]); all 1 when there are none.
MaskScore MeanMaskScore(const std::vector<cv::Mat>& estimates,
                        const std::vector<cv::Mat>& truths);

// Intersection over union of two binary masks; 1 when both are empty.
double MaskIou(const cv::Mat& a, const cv::Mat& b);

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_MASK_SCORES_H_
