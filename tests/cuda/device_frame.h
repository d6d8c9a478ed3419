#ifndef EULERSPLAT_TESTS_CUDA_DEVICE_FRAME_H_
#define EULERSPLAT_TESTS_CUDA_DEVICE_FRAME_H_

// A frame's image and mask uploaded as the device render costs read them,
// for the cost twin tests.

#include "core/base/cuda/device_buffer.h"
#include "core/io/scene.h"

namespace es {
namespace cuda {

struct DeviceFrame {
  explicit DeviceFrame(const Frame& frame) {
    image.Upload(frame.image.ptr<float>(), frame.image.total() * 3);
    mask.Upload(frame.mask.ptr<float>(), frame.mask.total());
  }

  DeviceBuffer<float> image;  // H W 3 floats, RGB
  DeviceBuffer<float> mask;   // H W floats
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_TESTS_CUDA_DEVICE_FRAME_H_
