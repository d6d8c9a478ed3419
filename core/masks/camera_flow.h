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

// How far each pixel of `image` lies outside the range (per channel, min
// to max) of `other` over a (2 radius + 1)^2 square around it, mean over
// channels: 0 where `other` holds the same colour within radius pixels.
// A difference that forgives misregistration by up to radius pixels
// (radius 0: |image - other|). Both CV_32FC3; returns CV_32FC1.
cv::Mat TolerantDifference(const cv::Mat& image, const cv::Mat& other,
                           int radius);

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_CAMERA_FLOW_H_
