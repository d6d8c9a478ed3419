#include "solvers/optim/adam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/base/lr_schedule.h"

namespace es {
namespace {

TEST(AdamTest, FirstStepMatchesHandComputation) {
  // At t = 1 the bias-corrected moments are g and g^2, so the step is
  // lr * g / (|g| + eps).
  const AdamOptions o;
  std::vector<double> x = {1.0, -2.0, 0.5}, g = {0.3, -4.0, 0.0};
  std::vector<double> m(3, 0.0), v(3, 0.0);
  AdamUpdate(o, 1, 0.1, 3, g.data(), m.data(), v.data(), x.data());
  EXPECT_NEAR(x[0], 1.0 - 0.1 * 0.3 / (0.3 + 1e-15), 1e-15);
  EXPECT_NEAR(x[1], -2.0 + 0.1, 1e-15);
  EXPECT_EQ(x[2], 0.5);
  EXPECT_NEAR(m[0], 0.1 * 0.3, 1e-15);
  EXPECT_NEAR(v[1], 0.001 * 16.0, 1e-15);
}

TEST(AdamTest, SecondStepMatchesHandComputation) {
  const AdamOptions o;
  double x = 0.0, m = 0.0, v = 0.0;
  double g = 1.0;
  AdamUpdate(o, 1, 0.01, 1, &g, &m, &v, &x);
  g = 3.0;
  AdamUpdate(o, 2, 0.01, 1, &g, &m, &v, &x);
  const double m2 = 0.9 * 0.1 + 0.1 * 3.0;
  const double v2 = 0.999 * 0.001 + 0.001 * 9.0;
  const double m_hat = m2 / (1 - 0.81), v_hat = v2 / (1 - 0.999 * 0.999);
  EXPECT_NEAR(x, -0.01 - 0.01 * m_hat / std::sqrt(v_hat), 1e-13);
}

// AdamUpdate skips runs of parameters whose gradient and moments are all
// zero; every other parameter, a zero-gradient one with momentum left
// included, must take the textbook step, in any position of a run.
TEST(AdamTest, SkippingUntouchedParametersChangesNothing) {
  const AdamOptions o;
  const int n = 1000;
  std::vector<double> x(n), g(n, 0.0), m(n, 0.0), v(n, 0.0);
  for (int i = 0; i < n; ++i) x[i] = 0.001 * i - 0.3;
  for (int i : {3, 130, 131, 640, 999}) g[i] = 0.01 * (i % 7) - 0.02;
  m[300] = 0.05, v[300] = 0.002;  // momentum, no gradient this step
  std::vector<double> ex = x, em = m, ev = v;
  const double lr = 0.01;
  const int t = 5;
  const double bc1 = 1 - std::pow(o.beta1, t), bc2 = 1 - std::pow(o.beta2, t);
  for (int i = 0; i < n; ++i) {
    em[i] = o.beta1 * em[i] + (1 - o.beta1) * g[i];
    ev[i] = o.beta2 * ev[i] + (1 - o.beta2) * g[i] * g[i];
    ex[i] -= lr / bc1 * em[i] / (std::sqrt(ev[i]) / std::sqrt(bc2) + o.eps);
  }
  AdamUpdate(o, t, lr, n, g.data(), m.data(), v.data(), x.data());
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(x[i], ex[i], 1e-15) << i;
    EXPECT_EQ(m[i], em[i]) << i;
    EXPECT_EQ(v[i], ev[i]) << i;
  }
  EXPECT_NE(x[300], 0.001 * 300 - 0.3);  // the momentum moved it
}

TEST(AdamTest, ConvergesOnAQuadratic) {
  // f(x) = sum_i a_i (x_i - c_i)^2 with very different curvatures.
  const std::vector<double> a = {1e-3, 1.0, 1e3}, c = {2.0, -1.0, 0.25};
  std::vector<double> x(3, 0.0), m(3, 0.0), v(3, 0.0), g(3);
  for (int t = 1; t <= 3000; ++t) {
    for (int i = 0; i < 3; ++i) g[i] = 2 * a[i] * (x[i] - c[i]);
    AdamUpdate(AdamOptions(), t, LogLinearLr(0.05, 1e-4, t, 3000), 3, g.data(),
               m.data(), v.data(), x.data());
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(x[i], c[i], 1e-3) << i;
}

TEST(AdamTest, GaussianAdamUsesPerBlockRatesAndShBands) {
  GaussianSet params = ZeroGaussians(2, 1);
  GaussianSet grad = ZeroGaussians(2, 1);
  for (double* v :
       {grad.means.data(), grad.log_scales.data(), grad.quats.data(),
        grad.opacity_logits.data(), grad.sh.data(), grad.dynamic_logits.data()})
    v[0] = 1.0;
  grad.sh[3] = 1.0;  // first higher-band coefficient of Gaussian 0
  GaussianLearningRates lr;
  lr.means = 1, lr.log_scales = 2, lr.quats = 3, lr.opacity_logits = 4;
  lr.sh_dc = 5, lr.sh_rest = 6, lr.dynamic_logits = 7;
  GaussianAdam adam;
  adam.Reset(params);
  adam.Step(lr, grad, &params);
  EXPECT_NEAR(params.means[0], -1, 1e-12);
  EXPECT_NEAR(params.log_scales[0], -2, 1e-12);
  EXPECT_NEAR(params.quats[0], -3, 1e-12);
  EXPECT_NEAR(params.opacity_logits[0], -4, 1e-12);
  EXPECT_NEAR(params.sh[0], -5, 1e-12);
  EXPECT_NEAR(params.sh[3], -6, 1e-12);
  EXPECT_NEAR(params.dynamic_logits[0], -7, 1e-12);
  EXPECT_EQ(params.means[1], 0.0);  // zero gradient: no move
  EXPECT_EQ(adam.step(), 1);
}

TEST(AdamTest, MomentsFollowFilterAppendAndShDegree) {
  GaussianSet params = ZeroGaussians(3, 0);
  GaussianAdam adam;
  adam.Reset(params);
  adam.m().means = {0, 0, 0, 1, 1, 1, 2, 2, 2};
  adam.Filter({true, false, true});
  adam.AppendZeros(1);
  adam.SetShDegree(2);
  EXPECT_EQ(adam.m().size(), 3);
  EXPECT_EQ(adam.v().sh_degree, 2);
  EXPECT_EQ(adam.m().means, (std::vector<double>{0, 0, 0, 2, 2, 2, 0, 0, 0}));
  EXPECT_EQ(adam.m().quats[8], 0.0);  // new moments are zero, not identity
}

TEST(LrScheduleTest, LogLinearEndpointsAndMidpoint) {
  EXPECT_DOUBLE_EQ(LogLinearLr(1e-2, 1e-4, 0, 100), 1e-2);
  EXPECT_NEAR(LogLinearLr(1e-2, 1e-4, 50, 100), 1e-3, 1e-15);
  EXPECT_NEAR(LogLinearLr(1e-2, 1e-4, 100, 100), 1e-4, 1e-18);
  EXPECT_NEAR(LogLinearLr(1e-2, 1e-4, 500, 100), 1e-4, 1e-18);
}

}  // namespace
}  // namespace es
