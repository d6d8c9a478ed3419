#ifndef EULERSPLAT_SYNTH_CAMERA_H_
#define EULERSPLAT_SYNTH_CAMERA_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/model/camera.h"

namespace es {

// A hand-held-like camera move: the center sweeps from `start` to `end`
// (parallax for structure from motion) while looking at `target`, with a
// slow wobble of position, aim and roll and a small per-frame shake.
struct CameraPathSpec {
  Eigen::Vector3d start{-0.5, 1.5, 5.0};
  Eigen::Vector3d end{0.5, 1.6, 5.0};
  Eigen::Vector3d target{0, 1, 0};
  Eigen::Vector3d up{0, 1, 0};  // world up
  double hfov_deg = 60.0;
  double wobble = 0.04;         // position wobble amplitude (world units)
  double aim_wobble = 0.04;     // target wobble amplitude (world units)
  double roll_deg = 1.5;        // roll wobble amplitude
  double shake = 0.003;         // per-frame position noise std
  double shake_deg = 0.08;      // per-frame rotation noise std
};

// One PINHOLE camera per frame (image names frame_000000.png, ...; image
// ids from 1). Deterministic for a seed.
std::vector<Camera> MakeCameraPath(const CameraPathSpec& spec, int frames,
                                   int width, int height, uint64_t seed);

// Camera at `center` looking at `target` with the image's up along `up`,
// rolled by `roll` radians about the viewing direction.
Camera LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
              const Eigen::Vector3d& up, double roll);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_CAMERA_H_
