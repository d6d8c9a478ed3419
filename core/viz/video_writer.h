#ifndef EULERSPLAT_CORE_VIZ_VIDEO_WRITER_H_
#define EULERSPLAT_CORE_VIZ_VIDEO_WRITER_H_

#include <string>

#include <opencv2/core.hpp>

namespace es {

// A rendered H x W x 3 RGB buffer in [0, 1] (RenderResult::rgb) as an 8-bit
// BGR image, values clamped and rounded.
cv::Mat RgbToBgr8(const double* rgb, int width, int height);

// Name of animation frame `index` in a frame directory: frame_000042.png.
std::string AnimationFrameName(int index);

// Writes frames dir/frame_000000.png, ... and, on Finish, encodes them into
// an MP4: with the ffmpeg binary when it is on the PATH (H.264, yuv420p,
// plays everywhere), else with cv::VideoWriter's mp4v codec.
class VideoWriter {
 public:
  // Creates frame_dir and removes frame_*.png files already in it. Throws
  // InputError if it cannot create it.
  VideoWriter(const std::string& frame_dir, double fps);

  // bgr: CV_8UC3, every frame the same size. Throws InputError naming the
  // file if it cannot be written.
  void Add(const cv::Mat& bgr);
  // Encodes the frames written so far into mp4_path and returns the encoder
  // used ("ffmpeg" or "opencv-mp4v"). Throws InputError if neither works.
  std::string Finish(const std::string& mp4_path);

  int frames() const { return frames_; }

 private:
  std::string frame_dir_;
  double fps_;
  int frames_ = 0;
  cv::Size size_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_VIDEO_WRITER_H_
