#include "solvers/train/cuda/device_frame_images.h"

#include <glog/logging.h>

namespace es {
namespace cuda {
namespace {

// A frame's float image (or mask) of `channels` channels as one device
// array in row-major order.
void UploadImage(const cv::Mat& image, const Camera& camera, int channels,
                 DeviceBuffer<float>* device) {
  CHECK_EQ(image.type(), CV_MAKETYPE(CV_32F, channels));
  CHECK(image.cols == camera.width && image.rows == camera.height)
      << "image " << image.cols << "x" << image.rows << " for a camera of "
      << camera.width << "x" << camera.height;
  const cv::Mat dense = image.isContinuous() ? image : image.clone();
  device->Upload(dense.ptr<float>(), dense.total() * channels);
}

}  // namespace

DeviceFrameImages::DeviceFrameImages(const std::vector<Frame>& frames,
                                     const std::vector<int>& train,
                                     bool masks)
    : images_(frames.size()), masks_(frames.size()), masks_on_(masks) {
  for (int i : train) {
    const Frame& f = frames[i];
    UploadImage(f.image, f.camera, 3, &images_[i]);
    if (masks) UploadImage(f.mask, f.camera, 1, &masks_[i]);
  }
}

const float* DeviceFrameImages::image(int frame) const {
  const DeviceBuffer<float>& b = images_.at(frame);
  CHECK_GT(b.size(), 0u) << "frame " << frame << " is not a training frame";
  return b.data();
}

const float* DeviceFrameImages::mask(int frame) const {
  if (!masks_on_) return nullptr;
  const DeviceBuffer<float>& b = masks_.at(frame);
  CHECK_GT(b.size(), 0u) << "frame " << frame << " is not a training frame";
  return b.data();
}

}  // namespace cuda
}  // namespace es
