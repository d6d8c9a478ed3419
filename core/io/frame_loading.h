#ifndef EULERSPLAT_CORE_IO_FRAME_LOADING_H_
#define EULERSPLAT_CORE_IO_FRAME_LOADING_H_

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace es {

// Name of frame `index` of a video in images/, as COLMAP sees it once the
// video is split into frames: frame_000000.png, frame_000001.png, ...
std::string VideoFrameName(int index);

// Reads the frames `names` (paths relative to images_dir) from image files
// (png/jpg) in images_dir or, if it holds no images but one video file, from
// that video's frames (see VideoFrameName). Calls visit(i, image, source)
// once per names[i], with image in BGR order, 8 or 16 bits per channel, and
// source naming the file (and video frame) for error messages. Throws
// InputError listing every name that does not exist.
void ForEachFrameImage(
    const std::string& images_dir, const std::vector<std::string>& names,
    const std::function<void(int, const cv::Mat&, const std::string&)>& visit);

// The position in the video of each frame `names` (paths relative to
// images_dir): the frame number for a video's frames (see VideoFrameName),
// else the rank of the name among all image files of images_dir in name
// order, so that frames missing from `names` still take up their place.
// Throws InputError naming a name that is neither.
std::vector<int> FrameTimeIndices(const std::string& images_dir,
                                  const std::vector<std::string>& names);

// The mask files of images `names` in masks_dir: for each a file of the same
// name, else the same stem with .png. Throws InputError listing every image
// that has neither.
std::vector<std::string> FindMaskFiles(const std::string& masks_dir,
                                       const std::vector<std::string>& names);

// Reads a mask file as CV_32FC1 in [0, 1] (white = 1).
cv::Mat ReadMask(const std::string& path);

// BGR 8- or 16-bit image -> CV_32FC3 RGB in [0, 1].
cv::Mat ToRgbFloat(const cv::Mat& bgr);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_FRAME_LOADING_H_
