#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "core/metrics/image_metrics.h"
#include "costs/mask_bce_loss.h"
#include "costs/photometric_loss.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"
#include "tests/loss_gradient.h"
#include "tests/splat_probe_scene.h"

namespace es {
namespace {

using probe_scene::DoubleOptions;
using probe_scene::SixGaussians;
using probe_scene::TinyFrame;
using probe_scene::kHeight;
using probe_scene::kWidth;

bool Probe(const ceres::CostFunction& cost, GaussianSet* g, std::string* log) {
  // Ridders' default first step (1% of the value) moves a splat by a good
  // fraction of a pixel and crosses the rasterizer's discrete cut-offs (alpha
  // threshold, tile binning, depth order); the loss is only piecewise
  // smooth, so start the steps small.
  ceres::NumericDiffOptions nd;
  nd.ridders_relative_initial_step_size = 1e-6;
  const ceres::GradientChecker checker(
      &cost, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr),
      nd);
  const std::vector<double*> blocks = SplatRenderCost::Blocks(g);
  ceres::GradientChecker::ProbeResults results;
  const bool ok = checker.Probe(blocks.data(), 1e-5, &results);
  *log = results.error_log;
  return ok;
}

TEST(CostsTest, PhotometricGradientMatchesFiniteDifferences) {
  const Frame frame = TinyFrame();
  GaussianSet g = SixGaussians();
  std::unique_ptr<ceres::CostFunction> cost(
      CreatePhotometricCost(&frame, 6, 1, 0.2, DoubleOptions()));
  std::string log;
  EXPECT_TRUE(Probe(*cost, &g, &log)) << log;
  // The dynamic block is not touched by this term.
  double loss;
  const auto grad = LossGradient(*cost, SplatRenderCost::Blocks(&g), &loss);
  for (double v : grad[kDynamicBlock]) EXPECT_EQ(v, 0.0);
  for (int b = 0; b < kDynamicBlock; ++b) {
    double norm = 0;
    for (double v : grad[b]) norm += v * v;
    EXPECT_GT(norm, 0.0) << "block " << b;
  }
}

TEST(CostsTest, MaskBceGradientMatchesFiniteDifferences) {
  const Frame frame = TinyFrame();
  GaussianSet g = SixGaussians();
  std::unique_ptr<ceres::CostFunction> cost(
      CreateMaskBceCost(&frame, 6, 1, DoubleOptions()));
  std::string log;
  EXPECT_TRUE(Probe(*cost, &g, &log)) << log;
  double loss;
  const auto grad = LossGradient(*cost, SplatRenderCost::Blocks(&g), &loss);
  for (double v : grad[kShBlock]) EXPECT_EQ(v, 0.0);  // colour not involved
  double geometry = 0;
  for (double v : grad[kMeansBlock]) geometry += v * v;
  EXPECT_GT(geometry, 0.0);  // the mask reaches the geometry
}

TEST(CostsTest, CombinedCostGradientMatchesFiniteDifferences) {
  const Frame frame = TinyFrame();
  GaussianSet g = SixGaussians();
  ImageLossTerms terms;
  terms.mask_weight = 0.5;
  const SplatRenderCost cost(&frame, 6, 1, terms, DoubleOptions());
  std::string log;
  EXPECT_TRUE(Probe(cost, &g, &log)) << log;
}

// Wraps a cost and corrupts one Jacobian entry.
class WrongJacobian : public ceres::CostFunction {
 public:
  explicit WrongJacobian(const ceres::CostFunction* inner) : inner_(inner) {
    set_num_residuals(1);
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    if (!inner_->Evaluate(p, r, j)) return false;
    if (j && j[kMeansBlock]) j[kMeansBlock][4] *= 1.05;
    return true;
  }

 private:
  const ceres::CostFunction* inner_;
};

TEST(CostsTest, GradientCheckerCatchesAWrongJacobian) {
  const Frame frame = TinyFrame();
  GaussianSet g = SixGaussians();
  std::unique_ptr<ceres::CostFunction> cost(
      CreatePhotometricCost(&frame, 6, 1, 0.2, DoubleOptions()));
  const WrongJacobian wrong(cost.get());
  std::string log;
  EXPECT_FALSE(Probe(wrong, &g, &log));
}

// Problem::Evaluate with ScaledLoss returns weight * dl/dtheta, and the
// combined cost equals the sum of its single-term costs.
TEST(CostsTest, ScaledLossWeightsAndCombinedCostAgree) {
  const Frame frame = TinyFrame();
  GaussianSet g = SixGaussians();
  const RenderOptions options = DoubleOptions();
  ImageLossTerms terms;
  terms.mask_weight = 0.5;
  const SplatRenderCost combined(&frame, 6, 1, terms, options);
  double combined_loss;
  const auto combined_grad =
      LossGradient(combined, SplatRenderCost::Blocks(&g), &combined_loss);

  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  const std::vector<double*> blocks = SplatRenderCost::Blocks(&g);
  problem.AddResidualBlock(
      CreatePhotometricCost(&frame, 6, 1, 0.2, options),
      new ceres::ScaledLoss(nullptr, 1.0, ceres::TAKE_OWNERSHIP), blocks);
  problem.AddResidualBlock(
      CreateMaskBceCost(&frame, 6, 1, options),
      new ceres::ScaledLoss(nullptr, 0.5, ceres::TAKE_OWNERSHIP), blocks);
  double cost = 0;
  std::vector<double> gradient;
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = blocks;
  ASSERT_TRUE(problem.Evaluate(eo, &cost, nullptr, &gradient, nullptr));
  EXPECT_NEAR(cost, combined_loss, 1e-9);
  ExpectSameGradient(gradient, combined_grad, 1e-10);
}

TEST(CostsTest, ScaledLossScalesProblemGradient) {
  const Frame frame = TinyFrame();
  GaussianSet g = SixGaussians();
  std::unique_ptr<ceres::CostFunction> direct(
      CreatePhotometricCost(&frame, 6, 1, 0.2, DoubleOptions()));
  double loss;
  const auto grad = LossGradient(*direct, SplatRenderCost::Blocks(&g), &loss);
  const std::vector<double*> blocks = SplatRenderCost::Blocks(&g);
  ceres::ScaledLoss scaled(nullptr, 0.7, ceres::DO_NOT_TAKE_OWNERSHIP);
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  problem.AddResidualBlock(
      CreatePhotometricCost(&frame, 6, 1, 0.2, DoubleOptions()), &scaled,
      blocks);
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = blocks;
  double cost;
  std::vector<double> gradient;
  ASSERT_TRUE(problem.Evaluate(eo, &cost, nullptr, &gradient, nullptr));
  EXPECT_NEAR(cost, 0.7 * (loss + 0.5 * kScalarLossEps), 1e-12);
  size_t offset = 0;
  for (const auto& block : grad)
    for (double v : block) EXPECT_NEAR(gradient[offset++], 0.7 * v, 1e-12);
}

TEST(CostsTest, PhotometricLossIsZeroOnTheTarget) {
  const Frame frame = TinyFrame();
  cv::Mat y;
  frame.image.convertTo(y, CV_64F);
  std::vector<double> d(kWidth * kHeight * 3);
  PhotometricLoss loss(0.2, /*use_double=*/true);
  EXPECT_NEAR(loss.Evaluate(y.ptr<double>(), frame.image, 1.0, d.data()), 0.0,
              1e-12);
  // Off the target: 0.8 L1 + 0.2 (1 - SSIM).
  cv::Mat x = y + 0.1;
  const double expected = 0.8 * L1Loss(x, y) + 0.2 * (1 - Ssim(x, y));
  EXPECT_NEAR(loss.Evaluate(x.ptr<double>(), frame.image, 1.0, d.data()),
              expected, 1e-12);
}

TEST(CostsTest, MaskBceValueGradientAndClamp) {
  const cv::Mat mask = (cv::Mat_<float>(1, 3) << 1.f, 0.f, 1.f);
  const double p[3] = {0.8, 0.3, 0.0};  // the last is clamped
  double d[3];
  const double l = MaskBceLoss(p, mask, 2.0, d);
  EXPECT_NEAR(l, -(std::log(0.8) + std::log(0.7) + std::log(1e-6)) / 3, 1e-12);
  EXPECT_NEAR(d[0], 2.0 * -1 / 0.8 / 3, 1e-12);
  EXPECT_NEAR(d[1], 2.0 * 1 / 0.7 / 3, 1e-12);
  EXPECT_EQ(d[2], 0.0);
}

TEST(CostsTest, MaskBceSoftTargetUsesBothTerms) {
  const cv::Mat mask = (cv::Mat_<double>(1, 2) << 0.25, 1.0);
  const double p[2] = {0.6, 0.9};
  const double l = MaskBceLoss(p, mask, 1.0, nullptr);
  const double soft = -(0.25 * std::log(0.6) + 0.75 * std::log(0.4));
  EXPECT_NEAR(l, (soft - std::log(0.9)) / 2, 1e-12);
}

}  // namespace
}  // namespace es
