#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include "costs/joint_render_cost.h"
#include "costs/residual_l2_cost.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"
#include "tests/loss_gradient.h"
#include "tests/splat_probe_scene.h"
#include "tests/water_loop_fixture.h"

namespace es {
namespace {

using probe_scene::DoubleOptions;
using probe_scene::SixGaussians;
using probe_scene::TinyFrame;

constexpr int kCycle = 4;
constexpr int kFrameIndex = 6;  // cycle indices 2..., cycle numbers 1, 0

// The probe scene's six Gaussians, four of them dynamic, with small
// fields (R = 8, width 16) whose outputs are far from zero: V moves a point
// by ~2% of the box per step, D offsets everything.
LoopModel TinyModel() {
  LoopModel m;
  m.cycle_length = kCycle;
  m.gaussians = SixGaussians();
  m.dynamic_index = {0, 2, 3, 5};
  m.start_times = {0, 3, 1, 2};
  const Eigen::Vector3d lo(-0.8, -0.7, 2.2), hi(0.8, 0.7, 3.8);
  m.motion.emplace(SmallMotionFieldOptions(0.02));
  m.motion->SetBox(lo, hi);
  ResidualFieldOptions ro = SmallResidualFieldOptions(kCycle);
  ro.position_scale = 0.02;
  m.residual.emplace(ro);
  m.residual->SetBox(lo, hi);
  return m;
}

// Central differences (Ridders) with small steps: the loss is only
// piecewise smooth (alpha threshold, tile binning, depth order, texel
// borders).
ceres::GradientChecker::ProbeResults NumericJacobians(
    const ceres::CostFunction& cost, std::vector<double*> blocks,
    double tolerance, bool* ok) {
  ceres::NumericDiffOptions nd;
  nd.ridders_relative_initial_step_size = 1e-6;
  const ceres::GradientChecker checker(
      &cost, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr),
      nd);
  ceres::GradientChecker::ProbeResults results;
  *ok = checker.Probe(blocks.data(), tolerance, &results);
  return results;
}

// Per-entry relative error (GradientChecker's own test).
bool Probe(const ceres::CostFunction& cost, std::vector<double*> blocks,
           double tolerance, std::string* log) {
  bool ok = false;
  *log = NumericJacobians(cost, blocks, tolerance, &ok).error_log;
  return ok;
}

// Error relative to each block's largest entry. The chain has thousands of
// entries near 1e-8 whose numeric derivatives carry ~1e-11 of rounding
// noise, so a per-entry relative test of 1e-4 would only measure that
// noise; this one still catches any wrong term of relevant size.
bool ProbeBlockwise(const ceres::CostFunction& cost,
                    std::vector<double*> blocks, double tolerance,
                    std::string* log) {
  bool unused;
  const ceres::GradientChecker::ProbeResults r =
      NumericJacobians(cost, blocks, 1.0, &unused);
  bool ok = true;
  for (size_t b = 0; b < r.jacobians.size(); ++b) {
    const double scale = r.numeric_jacobians[b].cwiseAbs().maxCoeff();
    const double error =
        (r.jacobians[b] - r.numeric_jacobians[b]).cwiseAbs().maxCoeff();
    if (!(error <= tolerance * scale)) {
      ok = false;
      *log += "block " + std::to_string(b) + ": max error " +
              std::to_string(error) + " vs largest entry " +
              std::to_string(scale) + "\n";
    }
  }
  return ok;
}

double Norm(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

TEST(JointCostTest, FullChainGradientMatchesFiniteDifferences) {
  const Frame frame = TinyFrame();
  LoopModel m = TinyModel();
  JointRenderTerms terms;
  terms.mask_weight = 0.5;
  terms.residual_weight = 0.1;
  const JointRenderCost cost(&frame, kFrameIndex, LoopStructure::Of(m), terms,
                             DoubleOptions());
  ASSERT_EQ(cost.layout().num_blocks(), 10);
  std::string log;
  EXPECT_TRUE(ProbeBlockwise(cost, JointBlocks(&m), 1e-4, &log)) << log;
  // Every block gets a gradient: the chain reaches V, D and the splats.
  double loss;
  const auto grad = LossGradient(cost, JointBlocks(&m), &loss);
  for (size_t b = 0; b < grad.size(); ++b)
    EXPECT_GT(Norm(grad[b]), 0.0) << "block " << b;
  EXPECT_GT(cost.last_euler_stats().velocity_evaluations, 0);
}

TEST(JointCostTest, AblatedStructuresMatchFiniteDifferences) {
  const Frame frame = TinyFrame();
  for (int variant = 0; variant < 2; ++variant) {
    LoopModel m = TinyModel();
    if (variant == 0) m.motion.reset();   // --no_motion_field
    if (variant == 1) m.residual.reset(); // --no_residual
    const std::unique_ptr<ceres::CostFunction> cost(CreateJointPhotometricCost(
        &frame, kFrameIndex, LoopStructure::Of(m), 0.2, DoubleOptions()));
    ASSERT_EQ(cost->parameter_block_sizes().size(), 8u);
    std::string log;
    EXPECT_TRUE(ProbeBlockwise(*cost, JointBlocks(&m), 1e-4, &log))
        << "variant " << variant << "\n" << log;
  }
}

// With no fields and no dynamic Gaussians the joint cost is the Stage-1
// cost: same loss, same gradient.
TEST(JointCostTest, StaticStructureEqualsSplatRenderCost) {
  const Frame frame = TinyFrame();
  LoopModel m = TinyModel();
  m.motion.reset();
  m.residual.reset();
  m.dynamic_index.clear();
  m.start_times.clear();
  JointRenderTerms joint_terms;
  joint_terms.mask_weight = 0.5;
  const JointRenderCost joint(&frame, kFrameIndex, LoopStructure::Of(m),
                              joint_terms, DoubleOptions());
  ImageLossTerms terms;
  terms.mask_weight = 0.5;
  const SplatRenderCost stage1(&frame, 6, 1, terms, DoubleOptions());
  double l_joint, l_stage1;
  const auto g_joint = LossGradient(joint, JointBlocks(&m), &l_joint);
  const auto g_stage1 =
      LossGradient(stage1, SplatRenderCost::Blocks(&m.gaussians), &l_stage1);
  EXPECT_NEAR(l_joint, l_stage1, 1e-12);
  ASSERT_EQ(g_joint.size(), g_stage1.size());
  for (size_t b = 0; b < g_joint.size(); ++b)
    for (size_t i = 0; i < g_joint[b].size(); ++i)
      EXPECT_NEAR(g_joint[b][i], g_stage1[b][i], 1e-12);
}

TEST(JointCostTest, ResidualL2CostMatchesFiniteDifferences) {
  LoopModel m = TinyModel();
  const ResidualL2Cost cost(&*m.residual, 6, &m.dynamic_index, &m.start_times,
                            kCycle, kFrameIndex);
  std::vector<double*> blocks = {m.gaussians.means.data(),
                                 m.residual->triplane_params().data(),
                                 m.residual->mlp_params().data()};
  std::string log;
  EXPECT_TRUE(Probe(cost, blocks, 1e-6, &log)) << log;
  // Static Gaussians' positions do not enter D.
  double loss;
  const auto grad = LossGradient(cost, blocks, &loss);
  EXPECT_GT(loss, 0.0);
  for (int n : {1, 4})
    for (int j = 0; j < 3; ++j) EXPECT_EQ(grad[0][3 * n + j], 0.0);
  EXPECT_GT(Norm(grad[2]), 0.0);
}

// Wraps a cost and corrupts one entry of V's MLP Jacobian.
class WrongJacobian : public ceres::CostFunction {
 public:
  WrongJacobian(const ceres::CostFunction* inner, int block)
      : inner_(inner), block_(block) {
    set_num_residuals(1);
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* p, double* r,
                double** j) const override {
    if (!inner_->Evaluate(p, r, j)) return false;
    if (j && j[block_]) {
      // The largest entry, so the corruption is well above noise.
      double* e = j[block_];
      const int size = parameter_block_sizes()[block_];
      for (int i = 1; i < size; ++i)
        if (std::abs(j[block_][i]) > std::abs(*e)) e = &j[block_][i];
      *e *= 1.01;
    }
    return true;
  }

 private:
  const ceres::CostFunction* inner_;
  int block_;
};

TEST(JointCostTest, GradientCheckerCatchesAWrongFieldJacobian) {
  const Frame frame = TinyFrame();
  LoopModel m = TinyModel();
  const JointRenderCost cost(&frame, kFrameIndex, LoopStructure::Of(m),
                             JointRenderTerms(), DoubleOptions());
  const WrongJacobian wrong(&cost, cost.layout().motion_mlp());
  std::string log;
  EXPECT_FALSE(ProbeBlockwise(wrong, JointBlocks(&m), 1e-4, &log));
}

// <w, image> of a JointRenderCost's render, with the gradient that
// BackwardWithImageGradient passes back from w alone: the trainer's path
// for a loss on renders that the cost does not know (the loop's energy).
class ImageFunctional : public ceres::CostFunction {
 public:
  ImageFunctional(const JointRenderCost* cost, std::vector<double> w)
      : cost_(cost), w_(std::move(w)) {
    set_num_residuals(1);
    *mutable_parameter_block_sizes() = cost->parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    cost_->RenderForGradient(parameters);
    const std::vector<double>& rgb = cost_->render().rgb;
    EXPECT_EQ(rgb.size(), w_.size());
    residuals[0] = 0;
    for (size_t i = 0; i < rgb.size(); ++i) residuals[0] += w_[i] * rgb[i];
    if (jacobians != nullptr)
      cost_->BackwardWithImageGradient(parameters, w_.data(), jacobians);
    return true;
  }

 private:
  const JointRenderCost* cost_;
  std::vector<double> w_;
};

// With every term off and all water at cycle number 0 (the loop as
// es_animate plays frame 6, whose own cycle numbers are 1 and 0), an image
// gradient alone reaches every block through D and the Euler chain, and
// the render is not the video's frame 6.
TEST(JointCostTest, LoopFrameImageGradientMatchesFiniteDifferences) {
  const Frame frame = TinyFrame();
  LoopModel m = TinyModel();
  JointRenderTerms none;
  none.photometric_weight = 0;
  JointRenderCost loop(&frame, kFrameIndex, LoopStructure::Of(m), none,
                       DoubleOptions());
  loop.set_cycle_number(0);
  const std::vector<double*> blocks = JointBlocks(&m);
  EXPECT_NEAR(loop.RenderForGradient(blocks.data()), 0.5 * kScalarLossEps,
              1e-15);
  const std::vector<double> loop_rgb = loop.render().rgb;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> w(loop_rgb.size());
  for (double& x : w) x = u(rng);
  const ImageFunctional functional(&loop, w);
  std::string log;
  EXPECT_TRUE(ProbeBlockwise(functional, blocks, 1e-4, &log)) << log;

  const JointRenderCost video(&frame, kFrameIndex, LoopStructure::Of(m), none,
                              DoubleOptions());
  video.RenderForGradient(blocks.data());
  double gap = 0;
  for (size_t i = 0; i < loop_rgb.size(); ++i)
    gap = std::max(gap, std::abs(loop_rgb[i] - video.render().rgb[i]));
  EXPECT_GT(gap, 1e-4);
}

// Problem::Evaluate with ScaledLoss over the single-term costs gives the
// combined cost's loss and gradient.
TEST(JointCostTest, SingleTermCostsSumToTheCombinedCost) {
  const Frame frame = TinyFrame();
  LoopModel m = TinyModel();
  const LoopStructure s = LoopStructure::Of(m);
  const RenderOptions options = DoubleOptions();
  JointRenderTerms terms;
  terms.mask_weight = 0.5;
  terms.residual_weight = 0.001;
  const JointRenderCost combined(&frame, kFrameIndex, s, terms, options);
  double combined_loss;
  const auto combined_grad =
      LossGradient(combined, JointBlocks(&m), &combined_loss);

  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  const std::vector<double*> blocks = JointBlocks(&m);
  problem.AddResidualBlock(
      CreateJointPhotometricCost(&frame, kFrameIndex, s, 0.2, options),
      new ceres::ScaledLoss(nullptr, 1.0, ceres::TAKE_OWNERSHIP), blocks);
  problem.AddResidualBlock(
      CreateJointMaskBceCost(&frame, kFrameIndex, s, options),
      new ceres::ScaledLoss(nullptr, 0.5, ceres::TAKE_OWNERSHIP), blocks);
  const std::vector<double*> residual_blocks = {
      blocks[kMeansBlock], blocks[s.motion ? 8 : 6], blocks[s.motion ? 9 : 7]};
  problem.AddResidualBlock(
      new ResidualL2Cost(s.residual, 6, s.dynamic_index, s.start_times,
                         kCycle, kFrameIndex),
      new ceres::ScaledLoss(nullptr, 0.001, ceres::TAKE_OWNERSHIP),
      residual_blocks);
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = blocks;
  double cost = 0;
  std::vector<double> gradient;
  ASSERT_TRUE(problem.Evaluate(eo, &cost, nullptr, &gradient, nullptr));
  EXPECT_NEAR(cost, combined_loss, 1e-9);
  ExpectSameGradient(gradient, combined_grad, 1e-9);
}

}  // namespace
}  // namespace es
