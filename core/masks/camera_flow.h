#ifndef EULERSPLAT_CORE_MASKS_CAMERA_FLOW_H_
#define EULERSPLAT_CORE_MASKS_CAMERA_FLOW_H_

#include <opencv2/core.hpp>

#include "core/model/camera.h"

namespace es {

// The flow that camera motion alone induces from frame a to frame b over
// `depth` (a's depth per pixel, CV_32FC1, 0 = no surface): CV_32FC2 pixel
// offsets, NaN where there is no depth or the point falls behind b.
cv::Mat CameraFlow(const cv::Mat& depth, const Camera& a, const Camera& b);

// image carried from its frame to the frame of camera_flow (which maps that
// frame's pixels into image's), bilinear; `known` (CV_8UC1) is 0 where the
// flow is unknown or leaves the image, else 1.
void CarryByCameraFlow(const cv::Mat& image, const cv::Mat& camera_flow,
                       cv::Mat* out, cv::Mat* known);

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_CAMERA_FLOW_H_
