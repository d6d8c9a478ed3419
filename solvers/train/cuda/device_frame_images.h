#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_FRAME_IMAGES_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_FRAME_IMAGES_H_

// The training frames' images (and masks) in device memory, uploaded once
// so that a device trainer's steps read them there. No CUDA types.

#include <vector>

#include "core/io/scene.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

class DeviceFrameImages {
 public:
  // Uploads the image of every frame listed in `train` (H W 3 floats, RGB
  // in [0, 1]) and, with `masks`, its mask (H W floats): 12 (+ 4) bytes
  // per pixel per frame.
  DeviceFrameImages(const std::vector<Frame>& frames,
                    const std::vector<int>& train, bool masks);

  // By frame index; the frame must be one of `train`.
  const float* image(int frame) const;
  // nullptr when the masks were not uploaded.
  const float* mask(int frame) const;

 private:
  std::vector<DeviceBuffer<float>> images_, masks_;
  bool masks_on_ = false;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_FRAME_IMAGES_H_
