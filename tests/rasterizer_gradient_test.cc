// Analytic backward of the fast rasterizer against central differences of
// its own forward, in double (RenderOptions::use_double).
//
// Rule for thresholds: the rendered image is piecewise smooth (alpha and
// transmittance cut-offs, tile membership, the 0.99 alpha clamp, the color
// clamp and the FOV clamp make jumps or kinks). A component fails only if
// it disagrees with the central difference AND the two one-sided differences
// agree, i.e. the probe is in a smooth region; otherwise it is counted as
// "at a threshold" and skipped. Tests require almost every component to be
// smooth and checked.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/render/rasterizer.h"
#include "tests/reference_rasterizer.h"

namespace es {
namespace {

using reference::RandomScene;
using reference::TestScene;

// loss = sum of fixed random weights * every output.
struct Loss {
  std::vector<double> rgb, alpha, depth, extra;

  Loss(const TestScene& s, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    const int pixels = s.camera.width * s.camera.height;
    auto fill = [&](std::vector<double>* v, int n, double scale) {
      v->resize(n);
      for (double& x : *v) x = scale * uni(rng);
    };
    fill(&rgb, 3 * pixels, 1.0);
    fill(&alpha, pixels, 1.0);
    fill(&depth, pixels, 0.2);
    fill(&extra, pixels * s.num_extra, 1.0);
  }
  double operator()(const RenderResult& r) const {
    double sum = 0;
    for (size_t i = 0; i < rgb.size(); ++i) sum += rgb[i] * r.rgb[i];
    for (size_t i = 0; i < alpha.size(); ++i) sum += alpha[i] * r.alpha[i];
    for (size_t i = 0; i < depth.size(); ++i) sum += depth[i] * r.depth[i];
    for (size_t i = 0; i < extra.size(); ++i) sum += extra[i] * r.extra[i];
    return sum;
  }
  RenderGradients Gradients() const {
    return {rgb.data(), alpha.data(), depth.data(), extra.data()};
  }
};

RenderOptions DoubleOptions() {
  RenderOptions o;
  o.use_double = true;
  o.background = Eigen::Vector3d(0.2, 0.5, 0.9);
  return o;
}

double Evaluate(const TestScene& s, const Loss& loss) {
  static Rasterizer* rasterizer = new Rasterizer;  // buffers reused
  RenderResult out;
  rasterizer->Forward(s.camera, s.View(), DoubleOptions(), &out);
  return loss(out);
}

struct CheckResult {
  int checked = 0, at_threshold = 0, failed = 0;
  std::string log;
};

// Compares `analytic` with central differences of every entry of `param`
// (one of the arrays of *scene).
void CheckParam(TestScene* scene, std::vector<double>* param,
                const std::vector<double>& analytic, const Loss& loss,
                const std::string& name, CheckResult* result) {
  ASSERT_EQ(param->size(), analytic.size()) << name;
  for (size_t i = 0; i < param->size(); ++i) {
    const double x = (*param)[i];
    const double h = 1e-6 * std::max(1.0, std::abs(x));
    (*param)[i] = x + h;
    const double f_plus = Evaluate(*scene, loss);
    (*param)[i] = x - h;
    const double f_minus = Evaluate(*scene, loss);
    (*param)[i] = x;
    const double f0 = Evaluate(*scene, loss);
    const double central = (f_plus - f_minus) / (2 * h);
    const double forward = (f_plus - f0) / h, backward = (f0 - f_minus) / h;
    // Rounding error of the difference quotient, with a wide margin.
    const double noise = 1e-12 * (std::abs(f0) + 1) / h;
    const double err = std::abs(analytic[i] - central);
    if (err <= 1e-4 * std::max(std::abs(central), std::abs(analytic[i])) +
                   noise) {
      ++result->checked;
    } else if (std::abs(forward - backward) >
               1e-2 * std::max(std::abs(forward), std::abs(backward)) +
                   noise) {
      ++result->at_threshold;
    } else {
      ++result->failed;
      result->log += name + "[" + std::to_string(i) +
                     "]: analytic " + std::to_string(analytic[i]) +
                     " numeric " + std::to_string(central) + "\n";
    }
  }
}

CheckResult CheckScene(TestScene scene, unsigned seed) {
  const Loss loss(scene, seed);
  Rasterizer r;
  RenderResult out;
  r.Forward(scene.camera, scene.View(), DoubleOptions(), &out);
  SplatGradients g;
  r.Backward(loss.Gradients(), &g);
  CheckResult result;
  CheckParam(&scene, &scene.means, g.means, loss, "means", &result);
  CheckParam(&scene, &scene.log_scales, g.log_scales, loss, "log_scales",
             &result);
  CheckParam(&scene, &scene.quats, g.quats, loss, "quats", &result);
  CheckParam(&scene, &scene.opacity_logits, g.opacity_logits, loss,
             "opacity_logits", &result);
  CheckParam(&scene, &scene.sh, g.sh, loss, "sh", &result);
  CheckParam(&scene, &scene.extra, g.extra, loss, "extra", &result);
  return result;
}

void ExpectMostlyChecked(const CheckResult& r) {
  EXPECT_EQ(r.failed, 0) << r.log;
  EXPECT_GT(r.checked, 0);
  EXPECT_LE(r.at_threshold, std::max(1, r.checked / 50))
      << "too many probes at thresholds: " << r.at_threshold << " of "
      << r.checked + r.at_threshold;
}

class RasterizerGradientTest : public ::testing::TestWithParam<int> {};

TEST_P(RasterizerGradientTest, MatchesCentralDifferences) {
  const int degree = GetParam();
  for (unsigned seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const TestScene scene = RandomScene(100 * degree + seed, 12, degree, 2);
    ExpectMostlyChecked(CheckScene(scene, seed));
  }
}

INSTANTIATE_TEST_SUITE_P(ShDegrees, RasterizerGradientTest,
                         ::testing::Values(0, 1, 2, 3));

TEST(RasterizerGradient, FovClampedGaussianHasNoGradientAlongClampedAxis) {
  TestScene s;
  s.camera = reference::TestCamera(48, 40);
  s.num_extra = 0;
  // x/z = 1.0 is past the clamp 1.3 * 0.5 * 48 / fx ~ 0.59, but the blob is
  // big enough to reach the screen.
  s.Add(Eigen::Vector3d(3.0, 0.1, 3.0), Eigen::Vector3d(1.0, 0.6, 0.8),
        Eigen::Vector4d(0.9, 0.2, -0.3, 0.1), 2.0);
  s.sh[0] = 1.0;
  const CheckResult r = CheckScene(s, 7);
  ExpectMostlyChecked(r);
}

TEST(RasterizerGradient, CheckerCatchesAWrongGradient) {
  TestScene scene = RandomScene(5, 8, 1, 1);
  const Loss loss(scene, 3);
  Rasterizer r;
  RenderResult out;
  r.Forward(scene.camera, scene.View(), DoubleOptions(), &out);
  SplatGradients g;
  r.Backward(loss.Gradients(), &g);
  for (double& v : g.log_scales) v *= 1.001;
  CheckResult result;
  CheckParam(&scene, &scene.log_scales, g.log_scales, loss, "log_scales",
             &result);
  EXPECT_GT(result.failed, 0);
}

}  // namespace
}  // namespace es
