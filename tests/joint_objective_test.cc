#include "costs/joint_objective.h"

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "costs/splat_render_cost.h"
#include "solvers/train/joint_training_steps.h"
#include "tests/tiny_loop_scene.h"

namespace es {
namespace {

using namespace tiny_loop;

// The tiny scene's model with fresh fields, and an objective with every
// water term on, rendering in double so finite differences are clean.
struct Fixture {
  std::vector<Frame> frames = TrueFrames();
  LoopModel model;
  JointObjectiveOptions options;

  Fixture() {
    JointTrainerOptions o = TinyOptions();
    o.residual_weight = 0.1;
    std::mt19937_64 rng(1);
    // Away from the frames' own model: at an exact fit the L1 term has a
    // kink at every pixel.
    GaussianSet g = TrueCanonical();
    std::normal_distribution<double> noise(0, 1);
    for (double& x : g.sh) x += 0.2 * noise(rng);
    for (double& x : g.means) x += 0.02 * noise(rng);
    model = InitialLoopModel(o, kFrames, std::move(g), std::nullopt, &rng);
    options = JointObjectiveOptionsOf(o, /*use_masks=*/false,
                                      /*water_masks=*/true);
    options.render.use_double = true;
    options.water_energy.motion_weight = 1;
    options.water_energy.detail_weight = 1;
    options.water_texture.weight = 0.5;
    options.loop_texture_weight = 0.3;
  }

  // The objective's loss and gradient rows (layout order) of frame 5
  // paired with frame 6.
  double Evaluate(JointObjective* objective, double water_scale,
                  std::vector<std::vector<double>>* grad,
                  int64_t iteration = 3,
                  JointObjectiveTerms* terms_out = nullptr) {
    const JointBlockLayout& layout = objective->layout();
    grad->assign(layout.num_blocks(), {});
    std::vector<double*> rows;
    for (int b = 0; b < layout.num_blocks(); ++b) {
      (*grad)[b].assign(layout.sizes()[b], 0.0);
      rows.push_back((*grad)[b].data());
    }
    std::vector<double*> params = JointBlocks(&model);
    JointObjectiveTerms terms;
    return objective->Evaluate(LoopStructure::Of(model), params.data(),
                               frames[5], &frames[6], water_scale, iteration,
                               rows.data(), nullptr,
                               terms_out ? terms_out : &terms);
  }
};

double MaxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Stage 3 runs each field's MLP in the options' precision (double unless
// set).
TEST(JointObjectiveTest, InitialModelRunsItsFieldsInTheOptionsPrecision) {
  const MlpPrecision kDouble = MlpPrecision::kDouble;
  const MlpPrecision kFloat = MlpPrecision::kFloat;
  EXPECT_EQ(JointTrainerOptions().motion_precision, kDouble);
  EXPECT_EQ(JointTrainerOptions().residual_precision, kDouble);
  for (const auto& [motion, residual] :
       {std::pair{kFloat, kDouble}, std::pair{kDouble, kFloat}}) {
    JointTrainerOptions o = TinyOptions();
    o.motion_precision = motion;
    o.residual_precision = residual;
    std::mt19937_64 rng(1);
    const LoopModel model =
        InitialLoopModel(o, kFrames, TrueCanonical(), std::nullopt, &rng);
    ASSERT_TRUE(model.motion && model.residual);
    EXPECT_EQ(model.motion->mlp().precision(), motion);
    EXPECT_EQ(model.residual->mlp().precision(), residual);
  }
}

// With every term on, float fields give double's loss and gradient to
// float's rounding, block by block: within 1e-5 of the block's largest
// entry (they agree to 3e-7), or 1e-12 for a block whose gradient is
// rounding noise near 0. Checks the float path's conversions, buffers and
// gradient sums.
TEST(JointObjectiveTest, FloatFieldsGiveDoublesGradient) {
  Fixture f;
  double loss[2];
  std::vector<std::vector<double>> grad[2];
  for (const MlpPrecision precision :
       {MlpPrecision::kDouble, MlpPrecision::kFloat}) {
    f.model.motion->set_mlp_precision(precision);
    f.model.residual->set_mlp_precision(precision);
    JointObjective objective(&f.frames[0], LoopStructure::Of(f.model),
                             f.options);
    const int i = precision == MlpPrecision::kFloat;
    loss[i] = f.Evaluate(&objective, 1.0, &grad[i]);
  }
  EXPECT_NEAR(loss[1], loss[0], 1e-6 * std::abs(loss[0]));
  for (size_t b = 0; b < grad[0].size(); ++b) {
    double worst = 0;
    for (size_t k = 0; k < grad[0][b].size(); ++k)
      worst = std::max(worst, std::abs(grad[1][b][k] - grad[0][b][k]));
    EXPECT_LE(worst, 1e-5 * MaxAbs(grad[0][b]) + 1e-12)
        << "block " << b << " of " << grad[0].size();
  }
}

// With the water terms ramped to 0 the pair's step is the mean of both
// frames' fits, each as JointRenderCost scores it alone.
TEST(JointObjectiveTest, PairWithoutWaterTermsIsTheMeanOfBothFits) {
  Fixture f;
  f.options.loop_texture_weight = 0;
  JointObjective objective(&f.frames[0], LoopStructure::Of(f.model),
                           f.options);
  std::vector<std::vector<double>> grad;
  const double loss = f.Evaluate(&objective, 0.0, &grad);

  std::vector<double*> params = JointBlocks(&f.model);
  std::vector<std::vector<double>> mean(grad.size());
  double mean_loss = 0;
  for (int i : {5, 6}) {
    const JointRenderCost cost(&f.frames[i], i, LoopStructure::Of(f.model),
                               f.options.terms, f.options.render);
    std::vector<std::vector<double>> g(grad.size());
    std::vector<double*> rows;
    for (size_t b = 0; b < g.size(); ++b) {
      g[b].assign(grad[b].size(), 0.0);
      mean[b].resize(grad[b].size(), 0.0);
      rows.push_back(g[b].data());
    }
    mean_loss += 0.5 * cost.LossGradient(params.data(), rows.data());
    for (size_t b = 0; b < g.size(); ++b)
      for (size_t k = 0; k < g[b].size(); ++k) mean[b][k] += 0.5 * g[b][k];
  }
  EXPECT_NEAR(loss, mean_loss, 1e-12 * mean_loss);
  for (size_t b = 0; b < grad.size(); ++b) {
    const double scale = MaxAbs(mean[b]);
    // The dynamic logits' is zero with the mask term off.
    if (b != kDynamicBlock) {
      EXPECT_GT(scale, 0) << "block " << b;
    }
    for (size_t k = 0; k < grad[b].size(); ++k)
      ASSERT_NEAR(grad[b][k], mean[b][k], 1e-9 * scale) << "block " << b;
  }
}

// Every term on (fits, energy, texture, the loop's texture): the gradient
// along a random direction of each block matches central differences of
// the loss.
TEST(JointObjectiveTest, GradientMatchesCentralDifferences) {
  Fixture f;
  JointObjective objective(&f.frames[0], LoopStructure::Of(f.model),
                           f.options);
  std::vector<std::vector<double>> grad, scratch;
  const double loss = f.Evaluate(&objective, 1.0, &grad);
  ASSERT_TRUE(std::isfinite(loss));
  std::vector<double*> params = JointBlocks(&f.model);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  // The splats' means and SH colours, V's and D's MLPs: the Euler chain,
  // D and the image terms all enter.
  const JointBlockLayout& layout = objective.layout();
  for (int b : {static_cast<int>(kMeansBlock), static_cast<int>(kShBlock),
                layout.motion_mlp(), layout.residual_mlp()}) {
    ASSERT_GE(b, 0);
    std::vector<double> d(layout.sizes()[b]);
    for (double& x : d) x = normal(rng);
    double analytic = 0;
    for (size_t k = 0; k < d.size(); ++k) analytic += grad[b][k] * d[k];
    const double h = 1e-6;
    auto at = [&](double t) {
      std::vector<double> saved(params[b], params[b] + d.size());
      for (size_t k = 0; k < d.size(); ++k) params[b][k] += t * d[k];
      const double value = f.Evaluate(&objective, 1.0, &scratch);
      std::copy(saved.begin(), saved.end(), params[b]);
      return value;
    };
    const double numeric = (at(h) - at(-h)) / (2 * h);
    EXPECT_NEAR(analytic, numeric, 1e-4 * std::abs(numeric) + 1e-10)
        << "block " << b;
  }
}

// With loop_texture_interval K the loop texture term enters exactly the
// iterations that are multiples of K, at K times its weight: those steps
// are K = 1's at weight K w, the others those without the term.
TEST(JointObjectiveTest, LoopTextureIntervalScoresEveryKthIterationAtKTimes) {
  constexpr int kInterval = 3;
  Fixture f;
  const double w = f.options.loop_texture_weight;
  JointObjectiveOptions every = f.options;
  every.loop_texture_interval = kInterval;
  JointObjectiveOptions scaled = f.options;
  scaled.loop_texture_weight = kInterval * w;
  JointObjectiveOptions off = f.options;
  off.loop_texture_weight = 0;
  const LoopStructure structure = LoopStructure::Of(f.model);
  JointObjective interval(&f.frames[0], structure, every);
  JointObjective at_k_times(&f.frames[0], structure, scaled);
  JointObjective without(&f.frames[0], structure, off);
  JointObjective each(&f.frames[0], structure, f.options);
  int scored = 0;
  for (int64_t it = 0; it < 2 * kInterval + 1; ++it) {
    const bool due = it % kInterval == 0;
    EXPECT_EQ(every.loop_texture_due(it), due) << "iteration " << it;
    std::vector<std::vector<double>> grad, expected, k1_grad;
    JointObjectiveTerms terms, k1_terms;
    const double loss = f.Evaluate(&interval, 0.7, &grad, it, &terms);
    const double expected_loss =
        f.Evaluate(due ? &at_k_times : &without, 0.7, &expected, it);
    EXPECT_EQ(loss, expected_loss) << "iteration " << it;
    ASSERT_EQ(grad.size(), expected.size());
    for (size_t b = 0; b < grad.size(); ++b)
      ASSERT_EQ(grad[b], expected[b]) << "iteration " << it << " block " << b;
    // The reported term stays unweighted: K = 1's where it runs.
    f.Evaluate(&each, 0.7, &k1_grad, it, &k1_terms);
    ASSERT_GT(k1_terms.loop_texture, 0);
    EXPECT_NEAR(terms.loop_texture, due ? k1_terms.loop_texture : 0.0,
                1e-12 * k1_terms.loop_texture)
        << "iteration " << it;
    if (due) ++scored;
  }
  EXPECT_EQ(scored, 3);  // iterations 0, 3 and 6
}

// The trainer's options carry the interval to the objective.
TEST(JointObjectiveTest, LoopTextureDueFollowsTheTrainerInterval) {
  JointTrainerOptions o = TinyOptions();
  o.loop_texture_weight = 3;
  o.loop_texture_interval = 4;
  for (int64_t it = 0; it < 9; ++it)
    EXPECT_EQ(LoopTextureDue(o, it), it % 4 == 0) << "iteration " << it;
  o.loop_texture_weight = 0;
  EXPECT_FALSE(LoopTextureDue(o, 0));
}

// Once set, the scene-flow prior adds its own loss and gradient on V's
// blocks, as SceneFlowPrior scores V at full displacement, and nothing
// elsewhere.
TEST(JointObjectiveTest, SceneFlowPriorAddsItsTermOnVOnly) {
  Fixture f;
  ASSERT_TRUE(f.model.motion);
  // A warmed-up V: the prior must still score V itself.
  f.model.motion->SetDisplacementFactor(0.5);
  std::vector<SceneFlowSample> samples;
  std::mt19937 rng(9);
  std::normal_distribution<double> normal;
  const std::vector<double>& means = f.model.gaussians.means;
  for (size_t i = 0; i + 2 < means.size(); i += 3) {
    SceneFlowSample s;
    s.x = Eigen::Vector3d(means[i], means[i + 1], means[i + 2]);
    s.v = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    samples.push_back(s);
  }
  FlowPriorOptions prior_options;
  prior_options.weight = 2;
  prior_options.batch_size = 16;
  const int64_t iterations = 10;
  const uint64_t seed = 7;

  JointObjective without(&f.frames[0], LoopStructure::Of(f.model), f.options);
  JointObjective with(&f.frames[0], LoopStructure::Of(f.model), f.options);
  with.SetSceneFlowPrior(*f.model.motion, samples, prior_options, iterations,
                         seed);
  ASSERT_TRUE(with.has_scene_flow_prior());
  std::vector<std::vector<double>> grad_without, grad_with;
  const double loss_without = f.Evaluate(&without, 1.0, &grad_without);
  const double loss_with = f.Evaluate(&with, 1.0, &grad_with);

  MotionField unramped = *f.model.motion;
  unramped.SetDisplacementFactor(1.0);
  SceneFlowPrior prior(&unramped, samples, prior_options);
  const JointBlockLayout& layout = with.layout();
  const int v = layout.motion_triplane();
  std::vector<double> prior_triplane(layout.sizes()[v], 0.0);
  std::vector<double> prior_mlp(layout.sizes()[v + 1], 0.0);
  const double prior_loss = prior.AddLossAndGradient(
      unramped.params(), /*iteration=*/3, iterations, seed,
      {prior_triplane.data(), prior_mlp.data(), nullptr});
  ASSERT_GT(prior_loss, 0);
  EXPECT_NEAR(loss_with - loss_without, prior_loss, 1e-9 * prior_loss);
  for (int b = 0; b < layout.num_blocks(); ++b) {
    const std::vector<double>* added =
        b == v ? &prior_triplane : b == v + 1 ? &prior_mlp : nullptr;
    const double scale =
        std::max(MaxAbs(grad_without[b]), added ? MaxAbs(*added) : 0.0);
    for (size_t k = 0; k < grad_with[b].size(); ++k) {
      const double expected =
          grad_without[b][k] + (added ? (*added)[k] : 0.0);
      ASSERT_NEAR(grad_with[b][k], expected, 1e-9 * scale) << "block " << b;
    }
  }
}

}  // namespace
}  // namespace es
