// The device joint-training loss (costs/cuda/device_joint_render_cost.h)
// against its CPU twin, JointRenderCost, on a tiny looping model (24
// Gaussians, 10 dynamic with random start times, small V and D): at frames
// in several cycles (cycle numbers from -1 to 3) the residual, every term,
// the Euler chain's counts and every gradient block (the splat blocks, V's
// and D's triplane and MLP, the dynamic logits); the trainers' paths:
// EvaluateDeviceScalarLossGradient, AddLossGradient adding onto non-zero
// rows, and the two-half path with another loss's image gradient; models
// without V or without D, the mask term off; one cost following a change
// of structure. Both sides render in float in different summation orders
// (the fields, the chain and D's L2 are double on both), so values agree
// to float precision. Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/loop/cycle_time.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "costs/cuda/device_joint_render_cost.h"
#include "costs/cuda/device_splat_render_cost.h"
#include "costs/joint_render_cost.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"
#include "tests/centered_camera.h"
#include "tests/cuda/device_frame.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"
#include "tests/cuda/tiny_loop_model.h"

namespace es {
namespace cuda {
namespace {

// Tiny, so that the emulated device (a thread per CUDA thread) is quick.
constexpr int kWidth = 32, kHeight = 24;
constexpr int kCycle = 4;
// Frames with cycle numbers -1 and 0, 1 and 0, 3 and 2.
constexpr int kFrames[] = {1, 6, 13};
// Float renders in different orders: a gradient block within this much of
// its largest entry, the loss and its terms within kLossTolerance of
// themselves (emulated, the largest errors were 6e-7 and 8e-9); D's L2 is
// double on both sides.
constexpr double kGradientTolerance = 2e-4;
constexpr double kLossTolerance = 1e-6;
constexpr double kResidualTolerance = 1e-9;

struct JointCase {
  const char* name;
  int sh_degree;
  bool motion, residual, mask;
  double ssim_weight;
  bool every_frame = false;  // all of kFrames, else the last one only
};

Camera TinyCamera() { return CenteredCamera(kWidth, kHeight, 40); }

// TinyLoopModel with random start times and dynamic logits.
LoopModel Model(const JointCase& c) {
  LoopModel m = TinyLoopModel({c.name, c.sh_degree, c.motion, c.residual},
                              kCycle, 0.05);
  m.start_times = RandomStartTimes(m.num_dynamic(), kCycle, 11);
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (double& v : m.gaussians.dynamic_logits) v = noise(rng);
  return m;
}

// A target image and mask of noise.
Frame NoiseFrame() {
  Frame f;
  f.camera = TinyCamera();
  f.image.create(kHeight, kWidth, CV_32FC3);
  f.mask.create(kHeight, kWidth, CV_32FC1);
  cv::randu(f.image, 0.0f, 1.0f);
  cv::randu(f.mask, 0.0f, 1.0f);
  return f;
}

JointRenderTerms Terms(const JointCase& c) {
  JointRenderTerms t;
  t.ssim_weight = c.ssim_weight;
  t.mask_weight = c.mask ? 0.5 : 0.0;
  t.residual_weight = 0.3;
  return t;
}

RenderOptions Options() {
  RenderOptions o;
  o.background = Eigen::Vector3d(0.1, 0.2, 0.3);
  return o;
}

// A model's blocks (JointBlocks order) as host rows and device copies.
struct Blocks {
  std::vector<std::vector<double>> host;
  std::vector<DeviceBuffer<double>> device;

  explicit Blocks(LoopModel* m) {
    const LoopStructure s = LoopStructure::Of(*m);
    const JointBlockLayout layout(s);
    const std::vector<double*> rows = JointBlocks(m);
    device.resize(rows.size());
    for (size_t b = 0; b < rows.size(); ++b) {
      host.emplace_back(rows[b], rows[b] + layout.sizes()[b]);
      device[b].Upload(host[b]);
    }
  }
  // Rows of the same sizes, every value `value`, or the given ones.
  static Blocks Like(const Blocks& shape, double value) {
    Blocks g;
    g.host = shape.host;
    for (std::vector<double>& row : g.host)
      std::fill(row.begin(), row.end(), value);
    g.Upload();
    return g;
  }
  void Upload() {
    device.resize(host.size());
    for (size_t b = 0; b < host.size(); ++b) device[b].Upload(host[b]);
  }
  std::vector<double*> HostPointers() {
    std::vector<double*> p;
    for (std::vector<double>& row : host) p.push_back(row.data());
    return p;
  }
  std::vector<double*> DevicePointers() {
    std::vector<double*> p;
    for (DeviceBuffer<double>& row : device) p.push_back(row.data());
    return p;
  }
  std::vector<std::vector<double>> Download() const {
    std::vector<std::vector<double>> out;
    for (const DeviceBuffer<double>& row : device)
      out.push_back(row.Download());
    return out;
  }

 private:
  Blocks() = default;
};

const char* BlockName(const JointBlockLayout& layout, int b) {
  static const char* kSplat[] = {"means",   "log_scales", "quats",
                                 "opacity", "sh",         "dynamic_logits"};
  if (b < kNumSplatBlocks) return kSplat[b];
  if (b == layout.motion_triplane()) return "V triplane";
  if (b == layout.motion_mlp()) return "V MLP";
  if (b == layout.residual_triplane()) return "D triplane";
  return "D MLP";
}

// Each block within kGradientTolerance of its largest CPU entry; blocks
// the terms reach must not be all zero.
void ExpectBlocksNear(const std::vector<std::vector<double>>& device,
                      const std::vector<std::vector<double>>& cpu,
                      const JointBlockLayout& layout, bool mask_on) {
  ASSERT_EQ(device.size(), cpu.size());
  for (size_t b = 0; b < cpu.size(); ++b) {
    const char* what = BlockName(layout, static_cast<int>(b));
    ASSERT_EQ(device[b].size(), cpu[b].size()) << what;
    double scale = 0, error = 0;
    for (size_t i = 0; i < cpu[b].size(); ++i) {
      scale = std::max(scale, std::abs(cpu[b][i]));
      error = std::max(error, std::abs(device[b][i] - cpu[b][i]));
    }
    if (b != kDynamicBlock || mask_on) ExpectSomeNonZero(cpu[b], what);
    EXPECT_LE(error, kGradientTolerance * scale)
        << what << ": largest error " << error << ", largest entry " << scale;
  }
}

class DeviceJointRenderCostTest : public ::testing::TestWithParam<JointCase> {};

// Evaluate at frames in several cycles (the variants, to keep the emulated
// run short, at the last one only), one device cost Reset per frame as a
// trainer does.
TEST_P(DeviceJointRenderCostTest, EvaluateMatchesTheCpuCost) {
  ES_REQUIRE_GPU("device joint render cost");
  const JointCase& c = GetParam();
  LoopModel model = Model(c);
  const LoopStructure structure = LoopStructure::Of(model);
  const Frame frame = NoiseFrame();
  const JointRenderTerms terms = Terms(c);
  const DeviceFrame uploaded(frame);
  DeviceRasterizer rasterizer;
  DeviceJointRenderCost device(terms, Options().background, &rasterizer);
  Blocks params(&model);
  for (int i : kFrames) {
    if (!c.every_frame && i != kFrames[std::size(kFrames) - 1]) continue;
    SCOPED_TRACE("frame " + std::to_string(i));
    JointRenderCost cpu(&frame, i, structure, terms, Options());
    Blocks cpu_jac = Blocks::Like(params, 0.0);
    double cpu_r = 0;
    ASSERT_TRUE(cpu.Evaluate(params.HostPointers().data(), &cpu_r,
                             cpu_jac.HostPointers().data()));

    device.Reset(frame.camera, uploaded.image.data(),
                 c.mask ? uploaded.mask.data() : nullptr, i, structure);
    ASSERT_EQ(device.parameter_block_sizes(), cpu.parameter_block_sizes());
    Blocks jac = Blocks::Like(params, 7.0);  // Evaluate overwrites
    double r = 0;
    ASSERT_TRUE(device.Evaluate(params.DevicePointers().data(), &r,
                                jac.DevicePointers().data()));
    EXPECT_NEAR(r, cpu_r, kLossTolerance * cpu_r);
    EXPECT_NEAR(device.last_photometric(), cpu.last_photometric(),
                kLossTolerance * cpu.last_photometric());
    EXPECT_NEAR(device.last_mask(), cpu.last_mask(),
                kLossTolerance * cpu.last_mask());
    EXPECT_NEAR(device.last_residual(), cpu.last_residual(),
                kResidualTolerance * cpu.last_residual());
    EXPECT_EQ(device.last_mask() > 0, c.mask);
    EXPECT_EQ(device.last_residual() > 0, c.residual);
    const EulerStats& a = device.last_euler_stats();
    const EulerStats& b = cpu.last_euler_stats();
    EXPECT_EQ(a.velocity_evaluations, b.velocity_evaluations);
    EXPECT_EQ(a.clamped_steps, b.clamped_steps);
    EXPECT_EQ(a.nonfinite_velocities, b.nonfinite_velocities);
    ExpectBlocksNear(jac.Download(), cpu_jac.host, cpu.layout(), c.mask);

    // Without Jacobians: the same residual.
    if (!c.every_frame) continue;
    double again = 0;
    ASSERT_TRUE(device.Evaluate(params.DevicePointers().data(), &again,
                                nullptr));
    EXPECT_EQ(again, r);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Models, DeviceJointRenderCostTest,
    ::testing::Values(JointCase{"Full", 1, true, true, true, 0.2, true},
                      JointCase{"Degree3L1", 3, true, true, true, 0.0},
                      JointCase{"NoMotionField", 1, false, true, true, 0.0},
                      JointCase{"NoResidualField", 1, true, false, true, 0.0},
                      JointCase{"MaskOff", 0, true, true, false, 0.0}),
    [](const auto& info) { return std::string(info.param.name); });

// The trainers' paths at frame 6: the direct call (dl/dtheta), adding onto
// rows that hold other gradients, and the two halves with another loss's
// image gradient in between.
TEST(DeviceJointRenderCostPathsTest, GradientPathsMatchTheCpuCost) {
  ES_REQUIRE_GPU("device joint render cost");
  const JointCase c{"Full", 1, true, true, true, 0.0};
  LoopModel model = Model(c);
  const LoopStructure structure = LoopStructure::Of(model);
  const Frame frame = NoiseFrame();
  const JointRenderTerms terms = Terms(c);
  const int i = 6;
  const DeviceFrame uploaded(frame);
  DeviceRasterizer rasterizer;
  DeviceJointRenderCost device(terms, Options().background, &rasterizer);
  device.Reset(frame.camera, uploaded.image.data(), uploaded.mask.data(), i,
               structure);
  JointRenderCost cpu(&frame, i, structure, terms, Options());
  Blocks params(&model);
  const JointBlockLayout& layout = cpu.layout();

  // dl/dtheta, as EvaluateScalarLossGradient leaves it.
  Blocks cpu_dl = Blocks::Like(params, 0.0);
  const double cpu_loss = EvaluateScalarLossGradient(
      cpu, params.HostPointers().data(), cpu_dl.HostPointers().data());
  Blocks dl = Blocks::Like(params, 0.0);
  const double loss = EvaluateDeviceScalarLossGradient(
      device, params.DevicePointers().data(), dl.DevicePointers().data());
  EXPECT_NEAR(loss, cpu_loss, kLossTolerance * cpu_loss);
  ExpectBlocksNear(dl.Download(), cpu_dl.host, layout, true);

  // += onto rows that already hold a gradient (here 0.5 dl/dtheta).
  Blocks cpu_sum = Blocks::Like(params, 0.0), sum = Blocks::Like(params, 0.0);
  cpu_sum.host = cpu_dl.host;
  for (std::vector<double>& row : cpu_sum.host)
    for (double& v : row) v *= 0.5;
  sum.host = cpu_sum.host;
  sum.Upload();
  const double cpu_added =
      cpu.AddLossGradient(params.HostPointers().data(),
                          cpu_sum.HostPointers().data());
  const double added = device.AddLossGradient(params.DevicePointers().data(),
                                              sum.DevicePointers().data());
  EXPECT_NEAR(added, cpu_added, kLossTolerance * cpu_added);
  ExpectBlocksNear(sum.Download(), cpu_sum.host, layout, true);

  // The two halves: the same render, then another loss's image gradient.
  const double cpu_half = cpu.RenderForGradient(params.HostPointers().data());
  const double half = device.RenderForGradient(params.DevicePointers().data());
  EXPECT_NEAR(half, cpu_half, kLossTolerance * cpu_half);
  const DeviceImages& render = device.render();
  ASSERT_EQ(render.width, kWidth);
  ASSERT_EQ(render.height, kHeight);
  std::vector<float> rgb(3 * kWidth * kHeight);
  CopyToHost(rgb.data(), render.rgb, rgb.size() * sizeof(float));
  ExpectTwinsNear(std::vector<double>(rgb.begin(), rgb.end()),
                  cpu.render().rgb, 1e-5, "rgb");
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-0.01f, 0.01f);
  std::vector<float> extra(rgb.size());
  for (float& v : extra) v = u(rng);
  const std::vector<double> cpu_extra(extra.begin(), extra.end());
  DeviceBuffer<float> device_extra;
  device_extra.Upload(extra);
  Blocks cpu_two = Blocks::Like(params, 1.0), two = Blocks::Like(params, 1.0);
  cpu.BackwardWithImageGradient(params.HostPointers().data(),
                                cpu_extra.data(),
                                cpu_two.HostPointers().data(), false);
  device.BackwardWithImageGradient(params.DevicePointers().data(),
                                   device_extra.data(),
                                   two.DevicePointers().data(), false);
  ExpectBlocksNear(two.Download(), cpu_two.host, layout, true);
  // The extra gradient changed the result: it was not dropped.
  const std::vector<double> with_extra = two.Download()[kShBlock];
  const std::vector<double> without = dl.Download()[kShBlock];
  double moved = 0;
  for (size_t k = 0; k < without.size(); ++k)
    moved = std::max(moved, std::abs(with_extra[k] - without[k]));
  EXPECT_GT(moved, 1e-6);
}

// One cost, Reset from one structure to another as a trainer may do: the
// same model with new field boxes and another dynamic set (same objects,
// new contents), a model without V, and back: each evaluation matches a
// fresh CPU cost of that structure.
TEST(DeviceJointRenderCostPathsTest, FollowsStructureChanges) {
  ES_REQUIRE_GPU("device joint render cost");
  const JointCase full{"Full", 1, true, true, true, 0.0};
  LoopModel a = Model(full);
  LoopModel b = Model({"NoMotionField", 1, false, true, true, 0.0});
  const Frame frame = NoiseFrame();
  const JointRenderTerms terms = Terms(full);
  const DeviceFrame uploaded(frame);
  DeviceRasterizer rasterizer;
  DeviceJointRenderCost device(terms, Options().background, &rasterizer);
  auto expect_twins = [&](LoopModel* m, const char* what) {
    SCOPED_TRACE(what);
    const LoopStructure structure = LoopStructure::Of(*m);
    JointRenderCost cpu(&frame, 6, structure, terms, Options());
    Blocks params(m);
    Blocks cpu_jac = Blocks::Like(params, 0.0);
    Blocks jac = Blocks::Like(params, 0.0);
    double cpu_r = 0, r = 0;
    ASSERT_TRUE(cpu.Evaluate(params.HostPointers().data(), &cpu_r,
                             cpu_jac.HostPointers().data()));
    device.Reset(frame.camera, uploaded.image.data(), uploaded.mask.data(), 6,
                 structure);
    ASSERT_TRUE(device.Evaluate(params.DevicePointers().data(), &r,
                                jac.DevicePointers().data()));
    EXPECT_NEAR(r, cpu_r, kLossTolerance * cpu_r);
    ExpectBlocksNear(jac.Download(), cpu_jac.host, cpu.layout(), true);
  };
  expect_twins(&a, "first model");
  a.motion->SetBox(Eigen::Vector3d(-1.5, -1, 3), Eigen::Vector3d(1, 1.5, 5));
  a.residual->SetBox(Eigen::Vector3d(-1, -1.5, 3), Eigen::Vector3d(1.5, 1, 5));
  a.dynamic_index = {0, 2, 4, 5, 9, 12, 15, 17, 21, 22};
  expect_twins(&a, "new boxes and dynamic set");
  expect_twins(&b, "no motion field");
  expect_twins(&a, "back to the first");
}

}  // namespace
}  // namespace cuda
}  // namespace es
