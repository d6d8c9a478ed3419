#include "core/io/pinhole_camera.h"

#include <cmath>
#include <vector>

#include "core/base/input_error.h"

namespace es {

Camera PinholeCameraFromColmap(const ColmapCamera& camera,
                               const ColmapImage& image,
                               const std::string& source) {
  Camera c;
  const std::vector<double>& p = camera.params;
  if (camera.model == "PINHOLE" && p.size() == 4) {
    c.fx = p[0];
    c.fy = p[1];
    c.cx = p[2];
    c.cy = p[3];
  } else if (camera.model == "SIMPLE_PINHOLE" && p.size() == 3) {
    c.fx = c.fy = p[0];
    c.cx = p[1];
    c.cy = p[2];
  } else {
    throw InputError(source + ": camera " + std::to_string(camera.id) +
                     " has model " + camera.model + " with " +
                     std::to_string(p.size()) +
                     " parameters; rendering supports only PINHOLE and "
                     "SIMPLE_PINHOLE (undistort the images first)");
  }
  if (camera.width <= 0 || camera.height <= 0 || !(c.fx > 0) ||
      !(c.fy > 0) || !std::isfinite(c.fx) || !std::isfinite(c.fy) ||
      !std::isfinite(c.cx) || !std::isfinite(c.cy)) {
    throw InputError(source + ": camera " + std::to_string(camera.id) +
                     " has an invalid size or focal length");
  }
  c.width = camera.width;
  c.height = camera.height;
  c.q_cw = image.q_cw;
  c.t_cw = image.t_cw;
  c.image_name = image.name;
  c.image_id = image.id;
  return c;
}

}  // namespace es
