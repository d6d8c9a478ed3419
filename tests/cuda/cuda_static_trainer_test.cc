// The device Stage 1 trainer (solvers/train/cuda/device_static_trainer.h)
// and its render cost against the CPU's from the same start, on a tiny
// synthetic scene with masks: the cost's residual and Jacobians, the same
// frames and losses step by step, parameters
// close after steps that also raise the SH degree (a host round trip), the
// same model after a densify step and an opacity reset, the same skipped
// steps for a NaN frame, and checkpoints that the other trainer resumes.
// Both render in float, in different summation orders, so values agree to
// float precision, not bit for bit. Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/model/gaussian_init.h"
#include "core/render/rasterizer.h"
#include "costs/cuda/device_splat_render_cost.h"
#include "costs/splat_render_cost.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/optim/adam.h"
#include "solvers/train/cuda/device_gaussians.h"
#include "solvers/train/cuda/device_static_trainer.h"
#include "solvers/train/static_trainer.h"
#include "tests/centered_camera.h"
#include "tests/cuda/device_frame.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"
#include "tests/slab_scene.h"
#include "tests/expect_error.h"

namespace es {
namespace cuda {
namespace {

// Tiny, so that the emulated device (a thread per CUDA thread) is quick.
constexpr int kWidth = 16, kHeight = 12;
constexpr int kGaussians = 30;

Camera LookAt(const Eigen::Vector3d& center) {
  return LookingAtOrigin(CenteredCamera(kWidth, kHeight, 16), center);
}

// A slab of Gaussians seen from four cameras on an arc; those with x > 0
// are water and render the masks. The trainers start from noisy points.
struct TinyScene {
  std::vector<Frame> frames;
  std::vector<int> train = {0, 1, 2, 3};
  std::vector<Eigen::Vector3d> points, colors;

  TinyScene() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    GaussianSet truth;
    truth.Resize(kGaussians);
    for (int i = 0; i < kGaussians; ++i) {
      const Eigen::Vector3d color = DrawSlabGaussian(0.2, i, &rng, &truth);
      points.push_back(Eigen::Vector3d::Map(&truth.means[3 * i]) +
                       0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
      colors.push_back(color + 0.1 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
    std::vector<double> water;
    const SplatView view = WaterMarkedView(truth, &water);
    Rasterizer rasterizer;
    RenderResult render;
    for (int k = 0; k < 4; ++k) {
      const double angle = -0.3 + 0.2 * k;
      frames.push_back(RenderedFrame(
          LookAt(4.0 * Eigen::Vector3d(std::sin(angle), 0.1 * u(rng),
                                       -std::cos(angle))),
          view, &rasterizer, &render));
    }
  }

  // Seeded from the points, then made anisotropic and turned: a round
  // Gaussian's rotation gradient is zero up to rounding, which Adam would
  // blow up to a full step of noise on each trainer.
  GaussianSet Initial() const {
    GaussianSet g = InitGaussiansFromPoints(points, colors, 0);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    for (double& v : g.log_scales) v += 0.4 * u(rng);
    for (int i = 0; i < g.size(); ++i)
      for (int a = 0; a < 4; ++a) g.quats[4 * i + a] = (a == 0) + 0.5 * u(rng);
    return g;
  }
};

// SSIM's kernels are most of an emulated step: only the first test, which
// checks the whole loss, keeps them; the others train on L1 and the mask.
StaticTrainerOptions Options(double ssim_weight = 0) {
  StaticTrainerOptions o;
  o.ssim_weight = ssim_weight;
  o.iterations = 100;
  o.max_sh_degree = 2;
  o.sh_degree_interval = 1;  // raised before steps 1 and 2
  o.densify = false;
  o.densify_options.opacity_reset_interval = 0;
  return o;
}

// Largest |a - b| over two arrays of the same size.
double MaxDiff(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double m = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

void ExpectSameStep(const IterationStats& cpu, const IterationStats& device,
                    int step) {
  EXPECT_EQ(cpu.frame, device.frame) << "step " << step;
  EXPECT_EQ(cpu.skipped, device.skipped) << "step " << step;
  if (cpu.skipped) return;
  EXPECT_NEAR(device.loss, cpu.loss, 2e-5 * cpu.loss) << "step " << step;
  EXPECT_NEAR(device.photometric, cpu.photometric, 2e-5 * cpu.photometric)
      << "step " << step;
  EXPECT_NEAR(device.mask, cpu.mask, 2e-5 * cpu.mask) << "step " << step;
}

// The cost on its own: residual and every Jacobian block against
// SplatRenderCost's on the same model and frame (SSIM and mask on), and
// the trainers' direct call, which must leave dl/dtheta (Adam would not
// notice a gradient off by a constant factor).
TEST(CudaStaticTrainerTest, RenderCostMatchesTheCpuCost) {
  ES_REQUIRE_GPU("device render cost");
  const TinyScene scene;
  GaussianSet g = scene.Initial();
  g.SetShDegree(1);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (double& v : g.sh) v += 0.3 * noise(rng);
  for (double& v : g.dynamic_logits) v = noise(rng);
  const Frame& frame = scene.frames[2];
  const int n = g.size();
  const StaticTrainerOptions o = Options(0.2);
  const ImageLossTerms terms = StaticLossTerms(o, true);
  SplatRenderCost cpu(&frame, n, g.sh_degree, terms, StaticRenderOptions(o));
  GaussianSet cpu_grad = ZeroGaussians(n, g.sh_degree);
  std::vector<double*> cpu_params = SplatRenderCost::Blocks(&g);
  std::vector<double*> cpu_jac = SplatRenderCost::Blocks(&cpu_grad);
  double cpu_r = 0;
  ASSERT_TRUE(cpu.Evaluate(cpu_params.data(), &cpu_r, cpu_jac.data()));

  const DeviceFrame uploaded(frame);
  DeviceRasterizer rasterizer;
  DeviceSplatRenderCost device(terms, o.background, &rasterizer);
  device.Reset(frame.camera, uploaded.image.data(), uploaded.mask.data(), n,
               g.sh_degree);
  ASSERT_EQ(device.parameter_block_sizes(), cpu.parameter_block_sizes());
  DeviceGaussians params, jac;
  params.Upload(g);
  jac.ResizeZero(n, g.sh_degree);
  std::vector<double*> device_params = params.BlockPointers();
  std::vector<double*> device_jac = jac.BlockPointers();
  double device_r = 0;
  ASSERT_TRUE(device.Evaluate(device_params.data(), &device_r,
                              device_jac.data()));
  EXPECT_NEAR(device_r, cpu_r, 1e-5 * cpu_r);
  EXPECT_NEAR(device.last_photometric(), cpu.last_photometric(),
              2e-5 * cpu.last_photometric());
  EXPECT_NEAR(device.last_mask(), cpu.last_mask(), 2e-5 * cpu.last_mask());
  GaussianSet device_grad;
  jac.Download(&device_grad);
  auto expect_block = [](const std::vector<double>& c,
                         const std::vector<double>& d, const char* what) {
    double scale = 0;
    for (double v : c) scale = std::max(scale, std::abs(v));
    ASSERT_GT(scale, 0) << what;
    EXPECT_LE(MaxDiff(c, d), 2e-3 * scale) << what;
  };
  expect_block(cpu_grad.means, device_grad.means, "means");
  expect_block(cpu_grad.log_scales, device_grad.log_scales, "log_scales");
  expect_block(cpu_grad.quats, device_grad.quats, "quats");
  expect_block(cpu_grad.opacity_logits, device_grad.opacity_logits,
               "opacity");
  expect_block(cpu_grad.sh, device_grad.sh, "sh");
  expect_block(cpu_grad.dynamic_logits, device_grad.dynamic_logits,
               "dynamic");

  // Without Jacobians: the same residual.
  double again = 0;
  ASSERT_TRUE(device.Evaluate(device_params.data(), &again, nullptr));
  EXPECT_EQ(again, device_r);
  // The direct call: the Jacobian rows times r.
  const double loss = EvaluateDeviceScalarLossGradient(
      device, device_params.data(), device_jac.data());
  EXPECT_NEAR(loss, 0.5 * cpu_r * cpu_r, 2e-5 * loss);
  GaussianSet dl;
  jac.Download(&dl);
  for (size_t i = 0; i < dl.means.size(); ++i)
    EXPECT_NEAR(dl.means[i], device_grad.means[i] * device_r,
                1e-12 * std::abs(dl.means[i]) + 1e-300);
}

TEST(CudaStaticTrainerTest, StepsMatchTheCpuTrainer) {
  ES_REQUIRE_GPU("device Stage 1 trainer");
  const TinyScene scene;
  const StaticTrainerOptions o = Options(0.2);
  StaticTrainer cpu(&scene.frames, scene.train, o, scene.Initial());
  DeviceStaticTrainer device(&scene.frames, scene.train, o, scene.Initial());
  ASSERT_TRUE(device.uses_masks());
  EXPECT_EQ(device.scene_extent(), cpu.scene_extent());
  constexpr int kSteps = 3;
  for (int i = 0; i < kSteps; ++i) {
    const IterationStats c = cpu.Step();
    const IterationStats d = device.Step();
    ExpectSameStep(c, d, i);
    ASSERT_GT(c.mask, 0);
  }
  EXPECT_EQ(device.iteration(), kSteps);
  EXPECT_EQ(device.gaussians().sh_degree, 2);
  ExpectGaussiansWithinAdamSteps(cpu.gaussians(), device.gaussians(), kSteps,
                                 o.splat_lr, cpu.scene_extent());
  // The parameters moved: a trainer that did nothing would not pass.
  EXPECT_GT(MaxDiff(device.gaussians().means, scene.Initial().means), 0);
}

// A clone / split / prune step and an opacity reset after three steps: the
// same Gaussians, in the same order, with the same statistics before.
TEST(CudaStaticTrainerTest, DensifyStepGivesTheCpuModel) {
  ES_REQUIRE_GPU("device densification");
  const TinyScene scene;
  StaticTrainerOptions o = Options();
  o.densify = true;
  DensifyOptions& d = o.densify_options;
  d.from_iteration = 0;
  d.interval = 3;
  d.until_iteration = 100;
  d.opacity_reset_interval = 3;
  d.percent_dense = 0.5;  // both clones and splits
  // A threshold in the widest gap of the CPU's mean gradients after three
  // views, so float rounding cannot move a Gaussian across it.
  {
    StaticTrainerOptions probe = o;
    probe.densify_options.interval = 1000;
    StaticTrainer cpu(&scene.frames, scene.train, probe, scene.Initial());
    for (int i = 0; i < 3; ++i) cpu.Step();
    const Checkpoint c = cpu.Save();
    std::vector<double> mean;
    for (size_t i = 0; i < c.grad_sum.size(); ++i)
      if (c.grad_count[i] > 0) mean.push_back(c.grad_sum[i] / c.grad_count[i]);
    std::sort(mean.begin(), mean.end());
    ASSERT_GT(mean.size(), 10u);
    double best = 0;
    for (size_t i = mean.size() / 4; i + 1 < 3 * mean.size() / 4; ++i) {
      if (mean[i + 1] / mean[i] > best) {
        best = mean[i + 1] / mean[i];
        d.grad_threshold = std::sqrt(mean[i] * mean[i + 1]);
      }
    }
    ASSERT_GT(best, 1.01);
  }
  StaticTrainer cpu(&scene.frames, scene.train, o, scene.Initial());
  DeviceStaticTrainer device(&scene.frames, scene.train, o, scene.Initial());
  for (int i = 0; i < 2; ++i) ExpectSameStep(cpu.Step(), device.Step(), i);
  const Checkpoint before_cpu = cpu.Save(), before_device = device.Save();
  EXPECT_EQ(before_device.grad_count, before_cpu.grad_count);
  EXPECT_EQ(before_device.max_radius, before_cpu.max_radius);
  ASSERT_EQ(before_device.grad_sum.size(), before_cpu.grad_sum.size());
  double worst = 0;  // relative difference of the gradient sums
  for (size_t i = 0; i < before_cpu.grad_sum.size(); ++i)
    worst = std::max(worst, std::abs(before_device.grad_sum[i] -
                                     before_cpu.grad_sum[i]) /
                                (before_cpu.grad_sum[i] + 1e-12));
  EXPECT_LE(worst, 1e-4);

  ExpectSameStep(cpu.Step(), device.Step(), 2);  // densifies, resets
  const GaussianSet& c = cpu.gaussians();
  const GaussianSet& g = device.gaussians();
  EXPECT_GT(c.size(), kGaussians);  // the step added Gaussians
  ASSERT_EQ(g.size(), c.size());
  for (double logit : g.opacity_logits) EXPECT_LE(Sigmoid(logit), 0.01 + 1e-12);
  ExpectGaussiansWithinAdamSteps(c, g, 3, o.splat_lr, cpu.scene_extent());
  // Moments and statistics followed the Gaussians.
  const Checkpoint after = device.Save();
  EXPECT_EQ(after.adam.m.size(), c.size());
  EXPECT_EQ(after.grad_sum, std::vector<double>(c.size(), 0.0));
  // And training goes on from there on both.
  ExpectSameStep(cpu.Step(), device.Step(), 3);
}

// One NaN pixel in a training frame: its steps are skipped on both, and
// the others train on.
TEST(CudaStaticTrainerTest, NonFiniteStepsAreSkippedAsOnTheCpu) {
  ES_REQUIRE_GPU("device divergence guard");
  TinyScene scene;
  scene.frames[1].image.at<cv::Vec3f>(3, 5)[0] = NAN;
  const StaticTrainerOptions o = Options();
  StaticTrainer cpu(&scene.frames, scene.train, o, scene.Initial());
  DeviceStaticTrainer device(&scene.frames, scene.train, o, scene.Initial());
  for (int i = 0; i < 4; ++i) ExpectSameStep(cpu.Step(), device.Step(), i);
  EXPECT_EQ(device.skipped_steps(), 1);  // one epoch of four frames
  EXPECT_EQ(device.skipped_steps(), cpu.skipped_steps());
  EXPECT_TRUE(AllFinite(device.gaussians()));
}

// The device's block magnitudes (one reduction kernel per array) are the
// CPU's, a NaN or an infinity anywhere reading as infinity.
TEST(CudaStaticTrainerTest, MaxMagnitudesMatchTheCpu) {
  ES_REQUIRE_GPU("device block magnitudes");
  const TinyScene scene;
  const GaussianSet initial = scene.Initial();
  GaussianSet g = initial;
  // Beyond one block of 256 threads: the per-block maxima must combine.
  while (g.size() < 700) g.AppendFrom(initial, g.size() % initial.size());
  g.means[3 * 650 + 1] = -7.5e29;
  g.sh[g.sh.size() - 1] = 123.0;
  DeviceGaussians device;
  device.Upload(g);
  EXPECT_EQ(device.MaxMagnitudes(), SplatMagnitudes(g));
  for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    GaussianSet b = g;
    b.opacity_logits[333] = bad;
    device.Upload(b);
    const std::vector<double> m = device.MaxMagnitudes();
    EXPECT_EQ(m, SplatMagnitudes(b)) << bad;
    EXPECT_EQ(m[3], HUGE_VAL) << bad;
  }
}

// A runaway learning rate (--lr_position 1e30) stops both trainers at the
// first step, naming the flag.
TEST(CudaStaticTrainerTest, RunawayLearningRateStopsAsOnTheCpu) {
  ES_REQUIRE_GPU("device divergence guard");
  const TinyScene scene;
  StaticTrainerOptions o = Options();
  o.splat_lr.means_initial = o.splat_lr.means_final = 1e30;
  StaticTrainer cpu(&scene.frames, scene.train, o, scene.Initial());
  DeviceStaticTrainer device(&scene.frames, scene.train, o, scene.Initial());
  for (StaticStageTrainer* trainer :
       std::vector<StaticStageTrainer*>{&cpu, &device}) {
    ExpectErrorNaming<TrainingDiverged>([trainer] { trainer->Step(); },
                                        {"--lr_position 1e+30"});
  }
}

// A checkpoint of the device trainer, through a file, resumes on the CPU,
// and one of the CPU resumes on the device: both continue as the trainer
// that saved it does.
TEST(CudaStaticTrainerTest, CheckpointsResumeOnTheOtherTrainer) {
  ES_REQUIRE_GPU("device trainer checkpoints");
  const TinyScene scene;
  const StaticTrainerOptions o = Options();
  const std::string path = ::testing::TempDir() + "/cuda_static_trainer.ckpt";

  DeviceStaticTrainer device(&scene.frames, scene.train, o, scene.Initial());
  for (int i = 0; i < 3; ++i) device.Step();
  WriteCheckpoint(device.Save(), path);
  StaticTrainer cpu(&scene.frames, scene.train, o, scene.Initial());
  cpu.Restore(ReadCheckpoint(path));
  std::remove(path.c_str());
  EXPECT_EQ(cpu.iteration(), 3);
  EXPECT_EQ(cpu.gaussians().means, device.gaussians().means);
  for (int i = 3; i < 5; ++i) ExpectSameStep(cpu.Step(), device.Step(), i);
  ExpectGaussiansWithinAdamSteps(cpu.gaussians(), device.gaussians(), 2,
                                 o.splat_lr, cpu.scene_extent());

  DeviceStaticTrainer resumed(&scene.frames, scene.train, o, scene.Initial());
  resumed.Restore(cpu.Save());
  EXPECT_EQ(resumed.iteration(), 5);
  EXPECT_EQ(resumed.gaussians().sh, cpu.gaussians().sh);
  const Checkpoint back = resumed.Save();
  EXPECT_EQ(back.adam.step, 5);
  EXPECT_EQ(back.adam.v.sh, cpu.Save().adam.v.sh);
  for (int i = 5; i < 7; ++i) ExpectSameStep(cpu.Step(), resumed.Step(), i);
}

}  // namespace
}  // namespace cuda
}  // namespace es
