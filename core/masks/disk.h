#ifndef EULERSPLAT_CORE_MASKS_DISK_H_
#define EULERSPLAT_CORE_MASKS_DISK_H_

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace es {

// A round structuring element of the given radius (at least 1 pixel).
inline cv::Mat Disk(int radius) {
  radius = std::max(radius, 1);
  return cv::getStructuringElement(cv::MORPH_ELLIPSE,
                                   cv::Size(2 * radius + 1, 2 * radius + 1));
}

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_DISK_H_
