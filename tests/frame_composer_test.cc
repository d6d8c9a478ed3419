#include "core/loop/frame_composer.h"

#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "core/fields/gradient_chunks.h"
#include "core/loop/cycle_time.h"
#include "core/loop/euler_chain.h"
#include "core/loop/loop_animator.h"
#include "tests/small_fields.h"

namespace es {
namespace {

constexpr int kCycle = 4;

// Small fields whose outputs are far from zero, so every path matters.
MotionFieldOptions TinyMotion() {
  MotionFieldOptions o = SmallMotionFieldOptions(0.05);
  o.seed = 5;
  return o;
}

ResidualFieldOptions TinyResidual() {
  ResidualFieldOptions o = SmallResidualFieldOptions(kCycle);
  o.last_layer_init_scale = 1.0;
  o.seed = 7;
  return o;
}

LoopModel TinyModel(int sh_degree) {
  LoopModel m;
  m.cycle_length = kCycle;
  GaussianSet& g = m.gaussians;
  g.sh_degree = sh_degree;
  g.Resize(7);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double& v : g.means) v = 0.8 * u(rng);
  for (double& v : g.log_scales) v = -2 + 0.2 * u(rng);
  for (double& v : g.opacity_logits) v = u(rng);
  for (double& v : g.sh) v = 0.5 * u(rng);
  m.dynamic_index = {1, 2, 4, 6};
  m.start_times = {0, 3, 1, 2};
  m.motion.emplace(TinyMotion());
  m.motion->SetBox(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
  m.residual.emplace(TinyResidual());
  m.residual->SetBox(Eigen::Vector3d::Constant(-1),
                     Eigen::Vector3d::Constant(1));
  return m;
}

// Naive twin of Alg. 1 for one point (steps well below the clamp).
Eigen::Vector3d NaiveAdvect(const MotionField& field, Eigen::Vector3d x,
                            int steps) {
  FieldWorkspace ws;
  for (int s = 0; s < steps; ++s) {
    double v[3];
    field.Evaluate(field.params(), 1, x.data(), v, &ws);
    x += Eigen::Vector3d(v);
  }
  return x;
}

TEST(FrameComposerTest, ComposesAdvectedPositionsAndResidualOffsets) {
  for (int degree : {0, 3}) {
    const LoopModel m = TinyModel(degree);
    const int coeffs = NumShCoeffs(degree);
    const int offset_coeffs = std::min(coeffs, 16);
    FrameComposer composer;
    const int frame = 6;
    const SplatView& v = composer.Compose(LoopModelView::Of(m), frame);
    const GaussianSet& g = m.gaussians;
    EXPECT_EQ(v.log_scales, g.log_scales.data());
    EXPECT_EQ(v.quats, g.quats.data());
    std::vector<bool> dynamic(g.size(), false);
    for (int n : m.dynamic_index) dynamic[n] = true;
    for (int n = 0; n < g.size(); ++n) {
      if (dynamic[n]) continue;
      for (int j = 0; j < 3; ++j)
        EXPECT_EQ(v.means[3 * n + j], g.means[3 * n + j]);
      EXPECT_EQ(v.opacity_logits[n], g.opacity_logits[n]);
      for (int i = 0; i < 3 * coeffs; ++i)
        EXPECT_EQ(v.sh[3 * coeffs * n + i], g.sh[3 * coeffs * n + i]);
    }
    ASSERT_EQ(composer.residuals().size(), 4u * kResidualDim);
    for (int k = 0; k < m.num_dynamic(); ++k) {
      const int n = m.dynamic_index[k];
      const int t = CycleIndex(frame, m.start_times[k], kCycle);
      const int p = CycleNumber(frame, m.start_times[k], kCycle);
      EXPECT_EQ(composer.cycle_indices()[k], t);
      EXPECT_EQ(composer.cycle_numbers()[k], p);
      double d[kResidualDim];
      FieldWorkspace ws;
      m.residual->Evaluate(m.residual->params(), 1, &g.means[3 * n], &t, &p,
                           d, &ws);
      const Eigen::Vector3d x =
          NaiveAdvect(*m.motion, Eigen::Vector3d(&g.means[3 * n]), t);
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(v.means[3 * n + j], x[j] + d[j], 1e-12);
      EXPECT_NEAR(v.opacity_logits[n], g.opacity_logits[n] + d[3], 1e-12);
      for (int i = 0; i < 3 * coeffs; ++i) {
        const double offset = i < 3 * offset_coeffs ? d[4 + i] : 0.0;
        EXPECT_NEAR(v.sh[3 * coeffs * n + i], g.sh[3 * coeffs * n + i] + offset,
                    1e-12);
      }
    }
  }
}

TEST(FrameComposerTest, WithoutFieldsTheModelIsRenderedAsIs) {
  LoopModel m = TinyModel(1);
  m.motion.reset();
  m.residual.reset();
  FrameComposer composer;
  const SplatView& v = composer.Compose(LoopModelView::Of(m), 9);
  for (size_t i = 0; i < m.gaussians.means.size(); ++i)
    EXPECT_EQ(v.means[i], m.gaussians.means[i]);
  EXPECT_EQ(v.opacity_logits, m.gaussians.opacity_logits.data());
  EXPECT_EQ(v.sh, m.gaussians.sh.data());
  EXPECT_TRUE(composer.residuals().empty());
}

// Alg. 2 positions (LoopAnimator, p = 0) give the same splats as Alg. 1 at
// a frame where every Gaussian is in its first cycle.
TEST(FrameComposerTest, AdvectedEntryMatchesComposeInTheFirstCycle) {
  const LoopModel m = TinyModel(2);
  const LoopModelView view = LoopModelView::Of(m);
  std::vector<double> x0;
  for (int n : m.dynamic_index)
    for (int j = 0; j < 3; ++j) x0.push_back(m.gaussians.means[3 * n + j]);
  LoopAnimator animator(&*m.motion, EulerOptions(), kCycle);
  animator.Start(m.motion->params(), m.num_dynamic(), x0.data(),
                 m.start_times, kCycle - 1);
  FrameComposer a, b;
  const SplatView& va = a.Compose(view, kCycle - 1);
  const SplatView& vb = b.ComposeAdvected(view, animator.positions().data(),
                                          animator.cycle_indices().data(), 0);
  const int n = m.gaussians.size();
  for (int i = 0; i < 3 * n; ++i) EXPECT_NEAR(va.means[i], vb.means[i], 1e-12);
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(va.opacity_logits[i], vb.opacity_logits[i], 1e-12);
  for (size_t i = 0; i < m.gaussians.sh.size(); ++i)
    EXPECT_NEAR(va.sh[i], vb.sh[i], 1e-12);
}

// A fixed random linear functional of the composed arrays, as a loss.
struct LinearLoss {
  std::vector<double> w_means, w_opacity, w_sh;
  double Value(const SplatView& v) const {
    double l = 0;
    for (size_t i = 0; i < w_means.size(); ++i) l += w_means[i] * v.means[i];
    for (size_t i = 0; i < w_opacity.size(); ++i)
      l += w_opacity[i] * v.opacity_logits[i];
    for (size_t i = 0; i < w_sh.size(); ++i) l += w_sh[i] * v.sh[i];
    return l;
  }

  // Weights uniform in [-1, 1] for every value of the composed `g`.
  static LinearLoss Random(const GaussianSet& g, std::mt19937* rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    LinearLoss loss;
    loss.w_means.resize(3 * g.size());
    loss.w_opacity.resize(g.size());
    loss.w_sh.resize(g.sh.size());
    for (auto* w : {&loss.w_means, &loss.w_opacity, &loss.w_sh})
      for (double& x : *w) x = u(*rng);
    return loss;
  }
};

// Compose (at the frame's own cycle numbers, or all at `cycle_number`)
// and Backward of a LinearLoss against central differences of every block.
void ExpectBackwardMatchesCentralDifferences(
    std::optional<int> cycle_number) {
  LoopModel m = TinyModel(1);
  const int n = m.gaussians.size();
  const int frame = 9;  // cycle numbers 2, 1, 2, 1
  std::mt19937 rng(4);
  const LinearLoss loss = LinearLoss::Random(m.gaussians, &rng);

  FrameComposer composer;
  const SplatView& v =
      composer.Compose(LoopModelView::Of(m), frame, cycle_number);
  SplatGradients grads;
  grads.Resize(n, 1, 0);
  grads.means = loss.w_means;
  grads.opacity_logits = loss.w_opacity;
  grads.sh = loss.w_sh;
  (void)v;
  std::vector<double> d_means(3 * n, 0.0), d_opacity(n, 0.0),
      d_sh(m.gaussians.sh.size(), 0.0),
      d_vt(m.motion->triplane_params().size(), 0.0),
      d_vm(m.motion->mlp_params().size(), 0.0),
      d_dt(m.residual->triplane_params().size(), 0.0),
      d_dm(m.residual->mlp_params().size(), 0.0);
  LoopModelGradients out;
  out.means = d_means.data();
  out.opacity_logits = d_opacity.data();
  out.sh = d_sh.data();
  out.motion = {d_vt.data(), d_vm.data()};
  out.residual = {d_dt.data(), d_dm.data()};
  composer.Backward(LoopModelView::Of(m), grads, nullptr, out);

  auto check = [&](std::vector<double>* params,
                   const std::vector<double>& analytic, const char* name) {
    double max_abs = 0;
    for (double g : analytic) max_abs = std::max(max_abs, std::abs(g));
    ASSERT_GT(max_abs, 0.0) << name;
    for (size_t i = 0; i < params->size(); ++i) {
      const double saved = (*params)[i];
      const double h = 1e-6;
      FrameComposer c;
      (*params)[i] = saved + h;
      const double plus =
          loss.Value(c.Compose(LoopModelView::Of(m), frame, cycle_number));
      (*params)[i] = saved - h;
      const double minus =
          loss.Value(c.Compose(LoopModelView::Of(m), frame, cycle_number));
      (*params)[i] = saved;
      const double numeric = (plus - minus) / (2 * h);
      EXPECT_NEAR(analytic[i], numeric, 1e-6 * max_abs + 1e-8)
          << name << "[" << i << "]";
    }
  };
  check(&m.gaussians.means, d_means, "means");
  check(&m.gaussians.opacity_logits, d_opacity, "opacity");
  check(&m.gaussians.sh, d_sh, "sh");
  check(&m.motion->mlp_params(), d_vm, "V mlp");
  check(&m.motion->triplane_params(), d_vt, "V triplane");
  check(&m.residual->mlp_params(), d_dm, "D mlp");
  check(&m.residual->triplane_params(), d_dt, "D triplane");
}

TEST(FrameComposerTest, BackwardMatchesCentralDifferences) {
  ExpectBackwardMatchesCentralDifferences(std::nullopt);
}

// The loop's frame (every Gaussian at cycle number 0) takes gradients too:
// training can score the loop as es_animate plays it.
TEST(FrameComposerTest, BackwardAtOneCycleNumberMatchesCentralDifferences) {
  ExpectBackwardMatchesCentralDifferences(0);
}

// Compose at cycle number 0 is the frame Alg. 2 plays (LoopAnimator's
// positions, ComposeAdvected at p = 0), also at a frame where the video's
// own cycle numbers are 1 and 2; at those it differs.
TEST(FrameComposerTest, ComposeAtCycleNumberZeroIsTheLoopAsPlayed) {
  const LoopModel m = TinyModel(2);
  const LoopModelView view = LoopModelView::Of(m);
  const int frame = 9;  // cycle numbers 2, 1, 2, 1
  std::vector<double> x0;
  for (int n : m.dynamic_index)
    for (int j = 0; j < 3; ++j) x0.push_back(m.gaussians.means[3 * n + j]);
  LoopAnimator animator(&*m.motion, EulerOptions(), kCycle);
  animator.Start(m.motion->params(), m.num_dynamic(), x0.data(),
                 m.start_times, frame);
  FrameComposer played, loop, video;
  const SplatView& vp = played.ComposeAdvected(
      view, animator.positions().data(), animator.cycle_indices().data(), 0);
  const SplatView& vl = loop.Compose(view, frame, 0);
  const SplatView& vv = video.Compose(view, frame);
  for (int p : loop.cycle_numbers()) EXPECT_EQ(p, 0);
  const int n = m.gaussians.size();
  double video_gap = 0;
  for (int i = 0; i < 3 * n; ++i) {
    EXPECT_NEAR(vl.means[i], vp.means[i], 1e-12);
    video_gap = std::max(video_gap, std::abs(vv.means[i] - vl.means[i]));
  }
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(vl.opacity_logits[i], vp.opacity_logits[i], 1e-12);
  for (size_t i = 0; i < m.gaussians.sh.size(); ++i)
    EXPECT_NEAR(vl.sh[i], vp.sh[i], 1e-12);
  EXPECT_GT(video_gap, 1e-6);  // D sees the cycle number
}

// Every output of one Compose + Backward, for comparing runs.
struct ComposeResult {
  std::vector<double> means, opacity, sh;
  std::vector<double> d_means, d_opacity, d_sh, d_vt, d_vm, d_dt, d_dm;
  std::vector<char> vt_chunks, dt_chunks;
  int shares = 0;
};

// The composed view `v` of `composer` and its Backward of `loss`.
ComposeResult BackwardOf(const LoopModel& m, const SplatView& v,
                         const LinearLoss& loss, FrameComposer* composer) {
  const int n = m.gaussians.size();
  const LoopModelView view = LoopModelView::Of(m);
  ComposeResult r;
  r.shares = composer->num_shares();
  r.means.assign(v.means, v.means + 3 * n);
  r.opacity.assign(v.opacity_logits, v.opacity_logits + n);
  r.sh.assign(v.sh, v.sh + m.gaussians.sh.size());
  SplatGradients grads;
  grads.Resize(n, m.gaussians.sh_degree, 0);
  grads.means = loss.w_means;
  grads.opacity_logits = loss.w_opacity;
  grads.sh = loss.w_sh;
  r.d_means.assign(3 * n, 0.0);
  r.d_opacity.assign(n, 0.0);
  r.d_sh.assign(m.gaussians.sh.size(), 0.0);
  r.d_vt.assign(m.motion->triplane().num_params(), 0.0);
  r.d_vm.assign(m.motion->mlp().num_params(), 0.0);
  r.d_dt.assign(m.residual->triplane().num_params(), 0.0);
  r.d_dm.assign(m.residual->mlp().num_params(), 0.0);
  r.vt_chunks.assign(NumGradientChunks(r.d_vt.size()), 0);
  r.dt_chunks.assign(NumGradientChunks(r.d_dt.size()), 0);
  LoopModelGradients out;
  out.means = r.d_means.data();
  out.opacity_logits = r.d_opacity.data();
  out.sh = r.d_sh.data();
  out.motion = {r.d_vt.data(), r.d_vm.data(), r.vt_chunks.data()};
  out.residual = {r.d_dt.data(), r.d_dm.data(), r.dt_chunks.data()};
  composer->Backward(view, grads, nullptr, out);
  return r;
}

ComposeResult ComposeAndBackward(const LoopModel& m, int frame,
                                 const LinearLoss& loss,
                                 FrameComposer* composer,
                                 std::optional<int> cycle_number = {}) {
  return BackwardOf(
      m, composer->Compose(LoopModelView::Of(m), frame, cycle_number), loss,
      composer);
}

void ExpectClose(const std::vector<double>& a, const std::vector<double>& b,
                 const char* name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  double max_abs = 0;
  for (double x : a) max_abs = std::max(max_abs, std::abs(x));
  ASSERT_GT(max_abs, 0.0) << name;
  for (size_t i = 0; i < a.size(); ++i)
    ASSERT_NEAR(a[i], b[i], 1e-12 * max_abs) << name << "[" << i << "]";
}

// Every chunk with a non-zero gradient value is flagged.
void ExpectFlagged(const std::vector<double>& grad,
                   const std::vector<char>& chunks, const char* name) {
  for (size_t i = 0; i < grad.size(); ++i) {
    if (grad[i] != 0.0) {
      ASSERT_TRUE(chunks[i / kGradientChunk]) << name << "[" << i << "]";
    }
  }
}

// 400 Gaussians, 300 of them dynamic, on planes of 32^2 with the points
// in a corner of the box (most triplane chunks get no gradient).
LoopModel ManyPointModel(std::mt19937* rng) {
  LoopModel m = TinyModel(1);
  // Finer planes and points in a corner of the box, so that most triplane
  // chunks get no gradient.
  MotionFieldOptions motion = TinyMotion();
  motion.triplane.resolution = 32;
  m.motion.emplace(motion);
  m.motion->SetBox(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
  ResidualFieldOptions residual = TinyResidual();
  residual.triplane.resolution = 32;
  m.residual.emplace(residual);
  m.residual->SetBox(Eigen::Vector3d::Constant(-1),
                     Eigen::Vector3d::Constant(1));
  const int n = 400;
  m.gaussians.Resize(n);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double& v : m.gaussians.means) v = 0.3 * u(*rng) - 0.5;
  for (double& v : m.gaussians.log_scales) v = -2 + 0.2 * u(*rng);
  for (double& v : m.gaussians.opacity_logits) v = u(*rng);
  for (double& v : m.gaussians.sh) v = 0.5 * u(*rng);
  m.dynamic_index.clear();
  m.start_times.clear();
  for (int i = 0; i < n; i += 4) {  // 300 dynamic
    for (int j = i + 1; j < i + 4; ++j) {
      m.dynamic_index.push_back(j);
      m.start_times.push_back(std::uniform_int_distribution<int>(
          0, kCycle - 1)(*rng));
    }
  }
  return m;
}

// The dynamic Gaussians cut into one share per thread (each advected and
// evaluated by its thread, gradients summed at the end) give what one
// share gives, including on a second pass (the shares' gradient buffers
// must come back zero), and flag every triplane chunk they write.
TEST(FrameComposerTest, SharesAcrossThreadsMatchOneShare) {
  std::mt19937 rng(3);
  const LoopModel m = ManyPointModel(&rng);
  const LinearLoss loss = LinearLoss::Random(m.gaussians, &rng);
  const int frame = 6;

  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(4);
  FrameComposer one, split;
  one.set_max_shares(1);
  const ComposeResult a = ComposeAndBackward(m, frame, loss, &one);
  const ComposeResult b = ComposeAndBackward(m, frame, loss, &split);
  const ComposeResult c = ComposeAndBackward(m, frame, loss, &split);
  omp_set_num_threads(saved_threads);
  EXPECT_EQ(a.shares, 1);
  EXPECT_EQ(b.shares, 4);
  for (const ComposeResult* r : {&b, &c}) {
    ExpectClose(a.means, r->means, "means");
    ExpectClose(a.opacity, r->opacity, "opacity");
    ExpectClose(a.sh, r->sh, "sh");
    ExpectClose(a.d_means, r->d_means, "d means");
    ExpectClose(a.d_opacity, r->d_opacity, "d opacity");
    ExpectClose(a.d_sh, r->d_sh, "d sh");
    ExpectClose(a.d_vt, r->d_vt, "V triplane");
    ExpectClose(a.d_vm, r->d_vm, "V mlp");
    ExpectClose(a.d_dt, r->d_dt, "D triplane");
    ExpectClose(a.d_dm, r->d_dm, "D mlp");
  }
  for (const ComposeResult* r : {&a, &b}) {
    ExpectFlagged(r->d_vt, r->vt_chunks, "V triplane");
    ExpectFlagged(r->d_dt, r->dt_chunks, "D triplane");
  }
}

void ExpectSame(const ComposeResult& a, const ComposeResult& b) {
  EXPECT_EQ(a.means, b.means);
  EXPECT_EQ(a.opacity, b.opacity);
  EXPECT_EQ(a.sh, b.sh);
  EXPECT_EQ(a.d_means, b.d_means);
  EXPECT_EQ(a.d_opacity, b.d_opacity);
  EXPECT_EQ(a.d_sh, b.d_sh);
  EXPECT_EQ(a.d_vt, b.d_vt);
  EXPECT_EQ(a.d_vm, b.d_vm);
  EXPECT_EQ(a.d_dt, b.d_dt);
  EXPECT_EQ(a.d_dm, b.d_dm);
  EXPECT_EQ(a.vt_chunks, b.vt_chunks);
  EXPECT_EQ(a.dt_chunks, b.dt_chunks);
}

// Recompose after a Compose + Backward of the same frame (the loop
// texture's render after the fit's) is Compose at that cycle number, bit
// for bit, forward and backward: with shares across threads, with every
// step's activations kept and with none kept (the backward pass
// evaluates V again).
TEST(FrameComposerTest, RecomposeEqualsComposeAtThatCycleNumber) {
  std::mt19937 rng(8);
  const LoopModel m = ManyPointModel(&rng);
  const LinearLoss fit_loss = LinearLoss::Random(m.gaussians, &rng);
  const LinearLoss loop_loss = LinearLoss::Random(m.gaussians, &rng);
  const int frame = 9;  // cycle numbers 1 and 2
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(4);
  for (size_t kept_bytes : {size_t{1} << 30, size_t{0}}) {
    EulerOptions euler;
    euler.max_kept_activation_bytes = kept_bytes;
    FrameComposer reused(euler), fresh(euler);
    const ComposeResult fit = ComposeAndBackward(m, frame, fit_loss, &reused);
    const ComposeResult recomposed = BackwardOf(
        m, reused.Recompose(LoopModelView::Of(m), 0), loop_loss, &reused);
    for (int p : reused.cycle_numbers()) EXPECT_EQ(p, 0);
    EXPECT_EQ(reused.num_shares(), 4);
    const ComposeResult composed =
        ComposeAndBackward(m, frame, loop_loss, &fresh, 0);
    ExpectSame(composed, recomposed);
    EXPECT_NE(fit.opacity, recomposed.opacity);  // D sees the cycle number
  }
  omp_set_num_threads(saved_threads);
}

}  // namespace
}  // namespace es
