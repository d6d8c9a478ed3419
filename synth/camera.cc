#include "synth/camera.h"

#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>
#include <glog/logging.h>

#include "synth/random.h"

namespace es {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// A smooth random 1D signal with unit amplitude: a few sinusoids with
// periods of 25 to 90 frames, like a breathing, walking operator.
class Wobble {
 public:
  explicit Wobble(SynthRandom* r) {
    for (int k = 0; k < kTerms; ++k) {
      frequency_[k] = 2.0 * M_PI / r->Uniform(25.0, 90.0);
      phase_[k] = r->Uniform(0.0, 2.0 * M_PI);
    }
  }
  double operator()(double frame) const {
    double sum = 0.0;
    for (int k = 0; k < kTerms; ++k)
      sum += std::sin(frequency_[k] * frame + phase_[k]);
    return sum / kTerms;
  }

 private:
  static constexpr int kTerms = 3;
  double frequency_[kTerms];
  double phase_[kTerms];
};

}  // namespace

Camera LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
              const Eigen::Vector3d& up, double roll) {
  const Eigen::Vector3d z = (target - center).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r_wc;  // columns: camera axes in world coordinates
  r_wc << x, y, z;
  const Eigen::Matrix3d r_cw =
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
      r_wc.transpose();
  Camera camera;
  camera.q_cw = Eigen::Quaterniond(r_cw);
  camera.t_cw = -(r_cw * center);
  return camera;
}

std::vector<Camera> MakeCameraPath(const CameraPathSpec& spec, int frames,
                                   int width, int height, uint64_t seed) {
  CHECK_GT(frames, 0);
  CHECK(width > 0 && height > 0);
  SynthRandom random(seed);
  Wobble position[3] = {Wobble(&random), Wobble(&random), Wobble(&random)};
  Wobble aim[3] = {Wobble(&random), Wobble(&random), Wobble(&random)};
  const Wobble roll(&random);
  const double focal = 0.5 * width / std::tan(0.5 * spec.hfov_deg * kDegToRad);

  std::vector<Camera> cameras;
  for (int f = 0; f < frames; ++f) {
    const double s = frames > 1 ? static_cast<double>(f) / (frames - 1) : 0.5;
    Eigen::Vector3d center = spec.start + s * (spec.end - spec.start);
    Eigen::Vector3d target = spec.target;
    for (int a = 0; a < 3; ++a) {
      center[a] += spec.wobble * position[a](f) + spec.shake * random.Normal();
      target[a] += spec.aim_wobble * aim[a](f);
    }
    Camera c = LookAt(center, target, spec.up,
                      spec.roll_deg * kDegToRad * roll(f));
    // Shake the aim too: a small random rotation in the camera frame.
    const Eigen::Vector3d shake_axis(random.Normal(), random.Normal(),
                                     random.Normal());
    const Eigen::Quaterniond shake(Eigen::AngleAxisd(
        spec.shake_deg * kDegToRad * shake_axis.norm() / std::sqrt(3.0),
        shake_axis.normalized()));
    c.q_cw = (shake * c.q_cw).normalized();
    c.t_cw = shake * c.t_cw;
    c.width = width;
    c.height = height;
    c.fx = c.fy = focal;
    c.cx = 0.5 * width;
    c.cy = 0.5 * height;
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%06d.png", f);
    c.image_name = name;
    c.image_id = f + 1;
    cameras.push_back(c);
  }
  return cameras;
}

}  // namespace es
