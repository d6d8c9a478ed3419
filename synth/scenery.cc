#include "synth/scenery.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <Eigen/Geometry>
#include <glog/logging.h>

#include "synth/noise.h"
#include "synth/random.h"

namespace es {
namespace {

constexpr double kStaticDynamicLogit = -6.0;
// Disc radius relative to spacing: enough overlap to leave no holes.
constexpr double kDiscScale = 0.7;
// Disc thickness relative to its radius.
constexpr double kDiscFlatness = 0.15;

// A surface point with the surface normal there.
struct SurfacePoint {
  Eigen::Vector3d position;
  Eigen::Vector3d normal;
};

class SceneryBuilder {
 public:
  SceneryBuilder(const SceneryLayout& layout, uint64_t seed)
      : layout_(layout),
        seed_(seed),
        random_(seed),
        light_(layout.light_direction.normalized()) {}

  // Samples a parametric surface on a jittered ns x nt grid.
  void AddSurface(int ns, int nt,
                  const std::function<SurfacePoint(double, double)>& at,
                  const SceneryMaterial& material) {
    for (int i = 0; i < ns; ++i) {
      for (int j = 0; j < nt; ++j) {
        const double s = (i + random_.Uniform(0.15, 0.85)) / ns;
        const double t = (j + random_.Uniform(0.15, 0.85)) / nt;
        AddDisc(at(s, t), material);
      }
    }
  }

  GaussianSet Take() { return std::move(out_); }

 private:
  Eigen::Vector3d Color(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                        const SceneryMaterial& m) {
    const Eigen::Vector3d q = p * m.frequency;
    const double mix = std::clamp(
        1.6 * (FractalNoise(q, 4, seed_ + 11) - 0.5) + 0.5, 0.0, 1.0);
    Eigen::Vector3d c = m.color_a + mix * (m.color_b - m.color_a);
    // Mid-scale blotches (lichen, stains) and thin dark cracks.
    c *= 0.6 + 0.8 * FractalNoise(q * 4.0, 3, seed_ + 23);
    const double crack = std::abs(ValueNoise(q * 2.5, seed_ + 37) - 0.5);
    if (crack < 0.035) c *= 0.45;
    if (m.board_width > 0) c *= Boards(p, m.board_width);
    c *= 1.0 + m.speckle * random_.Normal();
    c *= 0.55 + 0.45 * std::max(0.0, n.dot(light_));
    return c.cwiseMax(0.02).cwiseMin(1.0);
  }

  // Brightness of vertical boards at p: a shade per board, grain along
  // it, a dark seam over the board's last quarter.
  double Boards(const Eigen::Vector3d& p, double width) const {
    const double at = p.x() / width;
    const double board = std::floor(at);
    if (at - board > 0.75) return 0.2;
    const double shade =
        0.7 + 0.6 * ValueNoise(Eigen::Vector3d(board * 7.31, 0.5, 0.5),
                               seed_ + 41);
    const double grain = 0.85 + 0.3 * ValueNoise(
        Eigen::Vector3d(p.x() * 60.0, p.y() * 3.0, p.z() * 60.0), seed_ + 43);
    return shade * grain;
  }

  void AddDisc(const SurfacePoint& sp, const SceneryMaterial& material) {
    const int k = out_.size();
    out_.Resize(k + 1);
    const Eigen::Vector3d n = sp.normal.normalized();
    Eigen::Vector3d t1 = n.unitOrthogonal();
    const double spin = random_.Uniform(0.0, 2.0 * M_PI);
    t1 = Eigen::AngleAxisd(spin, n) * t1;
    Eigen::Matrix3d frame;
    frame << t1, n.cross(t1), n;
    const Eigen::Quaterniond q(frame);
    const double radius = kDiscScale * layout_.spacing *
                          random_.Uniform(0.8, 1.3);
    for (int a = 0; a < 3; ++a) out_.means[3 * k + a] = sp.position[a];
    out_.log_scales[3 * k] = std::log(radius);
    out_.log_scales[3 * k + 1] =
        std::log(radius * random_.Uniform(0.6, 1.0));
    out_.log_scales[3 * k + 2] = std::log(radius * kDiscFlatness);
    out_.quats[4 * k] = q.w();
    out_.quats[4 * k + 1] = q.x();
    out_.quats[4 * k + 2] = q.y();
    out_.quats[4 * k + 3] = q.z();
    out_.opacity_logits[k] = Logit(random_.Uniform(0.9, 0.98));
    const Eigen::Vector3d c = Color(sp.position, n, material);
    for (int a = 0; a < 3; ++a) out_.sh[3 * k + a] = (c[a] - 0.5) / kShC0;
    out_.dynamic_logits[k] = kStaticDynamicLogit;
  }

  const SceneryLayout& layout_;
  uint64_t seed_;
  SynthRandom random_;
  Eigen::Vector3d light_;
  GaussianSet out_;
};

// Normal of a parametric surface by central differences.
Eigen::Vector3d NumericNormal(
    const std::function<Eigen::Vector3d(double, double)>& f, double s,
    double t, double step) {
  const Eigen::Vector3d ds = f(s + step, t) - f(s - step, t);
  const Eigen::Vector3d dt = f(s, t + step) - f(s, t - step);
  return ds.cross(dt).normalized();
}

}  // namespace

GaussianSet BuildScenery(const SceneryLayout& layout, uint64_t seed) {
  CHECK_GT(layout.spacing, 0.0);
  SceneryBuilder builder(layout, seed);
  uint64_t part = 0;
  for (const SceneryPlane& plane : layout.planes) {
    const uint64_t bump_seed = SynthRandom::Derive(seed, 1000 + part++);
    const Eigen::Vector3d n = plane.u.cross(plane.v).normalized();
    auto surface = [&plane, n, bump_seed](double s, double t) {
      const Eigen::Vector3d p = plane.origin + s * plane.u + t * plane.v;
      const double d = FractalNoise(p * 1.2, 4, bump_seed) - 0.5;
      return Eigen::Vector3d(p + 2.0 * plane.bump * d * n);
    };
    const int ns = std::max(1, static_cast<int>(
                                   std::ceil(plane.u.norm() / layout.spacing)));
    const int nt = std::max(1, static_cast<int>(
                                   std::ceil(plane.v.norm() / layout.spacing)));
    builder.AddSurface(
        ns, nt,
        [&surface](double s, double t) {
          return SurfacePoint{surface(s, t),
                              NumericNormal(surface, s, t, 1e-4)};
        },
        plane.material);
  }
  for (const SceneryRock& rock : layout.rocks) {
    const uint64_t shape_seed = SynthRandom::Derive(seed, 1000 + part++);
    // (s, t) -> azimuth, polar angle on the unit sphere.
    auto surface = [&rock, shape_seed](double s, double t) {
      const double phi = 2.0 * M_PI * s;
      const double theta = M_PI * std::clamp(t, 1e-6, 1.0 - 1e-6);
      const Eigen::Vector3d d(std::sin(theta) * std::cos(phi),
                              std::cos(theta),
                              std::sin(theta) * std::sin(phi));
      const double r =
          1.0 + rock.roughness * 2.0 *
                    (FractalNoise(d * 1.5 + Eigen::Vector3d::Constant(9.0), 3,
                                  shape_seed) -
                     0.5);
      return Eigen::Vector3d(rock.center + r * rock.radii.cwiseProduct(d));
    };
    const double mean_radius = rock.radii.mean();
    const int nt = std::max(
        2, static_cast<int>(std::ceil(M_PI * mean_radius / layout.spacing)));
    // Rows near the poles are shorter; sample each row by its own length.
    for (int j = 0; j < nt; ++j) {
      const double t = (j + 0.5) / nt;
      const int ns = std::max(
          3, static_cast<int>(std::ceil(2.0 * M_PI * mean_radius *
                                        std::sin(M_PI * t) / layout.spacing)));
      builder.AddSurface(
          ns, 1,
          [&surface, t, nt](double s, double dt) {
            const double tt = t + (dt - 0.5) / nt;
            return SurfacePoint{surface(s, tt),
                                NumericNormal(surface, s, tt, 1e-4)};
          },
          rock.material);
    }
  }
  return builder.Take();
}

}  // namespace es
