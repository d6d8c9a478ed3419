#include "core/model/camera.h"

#include <cmath>

namespace es {

Camera Camera::Scaled(double factor) const {
  Camera c = *this;
  c.width = static_cast<int>(std::lround(width * factor));
  c.height = static_cast<int>(std::lround(height * factor));
  const double sx = static_cast<double>(c.width) / width;
  const double sy = static_cast<double>(c.height) / height;
  c.fx *= sx;
  c.cx *= sx;
  c.fy *= sy;
  c.cy *= sy;
  return c;
}

}  // namespace es
