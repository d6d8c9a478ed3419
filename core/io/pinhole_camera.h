#ifndef EULERSPLAT_CORE_IO_PINHOLE_CAMERA_H_
#define EULERSPLAT_CORE_IO_PINHOLE_CAMERA_H_

#include <string>

#include "core/io/colmap_io.h"
#include "core/model/camera.h"

namespace es {

// The camera of a registered COLMAP image. Only PINHOLE (fx fy cx cy) and
// SIMPLE_PINHOLE (f cx cy) are accepted: rendering does not undistort.
// Throws InputError naming `source` and the model otherwise.
Camera PinholeCameraFromColmap(const ColmapCamera& camera,
                               const ColmapImage& image,
                               const std::string& source);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_PINHOLE_CAMERA_H_
