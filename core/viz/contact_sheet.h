#ifndef EULERSPLAT_CORE_VIZ_CONTACT_SHEET_H_
#define EULERSPLAT_CORE_VIZ_CONTACT_SHEET_H_

#include <string>

#include <opencv2/core.hpp>

namespace es {

// One image for a person to look at: `count` frames of a scene directory,
// evenly spaced over the video, each beside its water mask (gray when the
// scene has none), two pairs per row, labelled with the frame name. BGR,
// 8-bit. Throws InputError when images/ has no frames or a mask is
// unreadable.
cv::Mat MakeContactSheet(const std::string& scene_dir, int count);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_CONTACT_SHEET_H_
