// The device frame composer (core/loop/cuda/device_frame_composer.h)
// against its CPU twin, FrameComposer's training path, on the tiny loop
// model with random start times, at frames in several cycles (cycle
// numbers -1 to 3): the composed means, opacities and SH, D's outputs and
// the Euler chain's counts; then the backward of random composed-splat
// gradients plus a random gradient of D's outputs, added onto non-zero
// accumulators, to every canonical block and V's and D's parameters. SH
// degrees below and at D's 16 coefficients, models without V or without D.
// Double on both sides, summed in other orders: within 1e-9 relative.
// Skips when no CUDA device is present.

#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/loop/cuda/device_frame_composer.h"
#include "core/loop/cycle_time.h"
#include "core/loop/frame_composer.h"
#include "core/model/gaussians.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_splats.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/host_arrays.h"
#include "tests/cuda/require_gpu.h"
#include "tests/cuda/tiny_loop_model.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 4;
constexpr double kTolerance = 1e-9;
constexpr int kFrames[] = {1, 6, 13};

std::vector<double> Random(size_t count, double scale, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<double> v(count);
  for (double& x : v) x = u(*rng);
  return v;
}

// Host accumulators and their device copies, starting at the same
// non-zero values (Backward adds).
struct Accumulator {
  std::vector<double> host;
  DeviceBuffer<double> device;
  Accumulator(size_t count, std::mt19937* rng) : host(Random(count, 1, rng)) {
    device.Upload(host);
  }
  void Expect(const char* what) const {
    ExpectTwinsNear(device.Download(), host, kTolerance, what);
  }
};

class DeviceFrameComposerTest
    : public ::testing::TestWithParam<TinyLoopModelCase> {};

TEST_P(DeviceFrameComposerTest, ComposesAndDifferentiatesAsCpuTwin) {
  ES_REQUIRE_GPU("CUDA frame composer");
  const TinyLoopModelCase& c = GetParam();
  LoopModel model = TinyLoopModel(c, kCycle, 0.05);
  model.start_times = RandomStartTimes(model.num_dynamic(), kCycle, 11);
  const LoopModelView cpu_view = LoopModelView::Of(model);
  const int n = model.gaussians.size();
  const int m = model.num_dynamic();
  const size_t sh = 3 * model.gaussians.sh_coeffs() * n;

  DeviceSplats canonical;
  canonical.Upload(cpu_view.canonical);
  DeviceLoopModelView view;
  view.canonical = canonical.View();
  DeviceFieldBlocks motion, residual;
  if (model.motion) {
    motion.Upload(model.motion->params(), model.motion->triplane().num_params(),
                  model.motion->mlp().num_params());
    view.motion_params = motion.params();
  }
  if (model.residual) {
    residual.Upload(model.residual->params(),
                    model.residual->triplane().num_params(),
                    model.residual->mlp().num_params());
    view.residual_params = residual.params();
  }
  FrameComposer cpu;
  DeviceFrameComposer device;
  device.SetStructure(cpu_view.structure);
  std::mt19937 rng(3);
  for (int frame : kFrames) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const SplatView& want = cpu.Compose(cpu_view, frame);
    const DeviceSplatView& got = device.Compose(view, frame);
    ASSERT_EQ(got.count, n);
    ExpectTwinsNear(Fetch(got.means, 3 * n), Copy(want.means, 3 * n),
                    kTolerance, "means");
    ExpectTwinsNear(Fetch(got.opacity_logits, n), Copy(want.opacity_logits, n),
                    kTolerance, "opacity_logits");
    ExpectTwinsNear(Fetch(got.sh, sh), Copy(want.sh, sh), kTolerance, "sh");
    EXPECT_EQ(got.log_scales, view.canonical.log_scales);
    EXPECT_EQ(got.quats, view.canonical.quats);
    if (model.residual) {
      ExpectTwinsNear(Fetch(device.residuals(), cpu.residuals().size()),
                      cpu.residuals(), kTolerance, "residuals");
    } else {
      EXPECT_EQ(device.residuals(), nullptr);
    }
    EXPECT_EQ(device.euler_stats().velocity_evaluations,
              cpu.euler_stats().velocity_evaluations);
    EXPECT_EQ(device.euler_stats().clamped_steps,
              cpu.euler_stats().clamped_steps);

    // Backward of random gradients onto non-zero accumulators.
    SplatGradients grads;
    grads.means = Random(3 * n, 1, &rng);
    grads.log_scales = Random(3 * n, 1, &rng);
    grads.quats = Random(4 * n, 1, &rng);
    grads.opacity_logits = Random(n, 1, &rng);
    grads.sh = Random(sh, 1, &rng);
    DeviceBuffer<double> g_means, g_scales, g_quats, g_opacity, g_sh;
    g_means.Upload(grads.means);
    g_scales.Upload(grads.log_scales);
    g_quats.Upload(grads.quats);
    g_opacity.Upload(grads.opacity_logits);
    g_sh.Upload(grads.sh);
    const DeviceSplatGradients device_g{
        {g_means.data(), g_scales.data(), g_quats.data(), g_opacity.data(),
         g_sh.data()},
        nullptr};
    const std::vector<double> d_residuals =
        Random(static_cast<size_t>(m) * kResidualDim, 0.1, &rng);
    DeviceBuffer<double> device_d_residuals;
    device_d_residuals.Upload(d_residuals);

    Accumulator means(3 * n, &rng), log_scales(3 * n, &rng),
        quats(4 * n, &rng), opacity(n, &rng), sh_grad(sh, &rng);
    const size_t vt = model.motion ? model.motion->triplane().num_params() : 0;
    const size_t vm = model.motion ? model.motion->mlp().num_params() : 0;
    const size_t dt =
        model.residual ? model.residual->triplane().num_params() : 0;
    const size_t dm = model.residual ? model.residual->mlp().num_params() : 0;
    Accumulator v_tri(vt, &rng), v_mlp(vm, &rng), d_tri(dt, &rng),
        d_mlp(dm, &rng);
    LoopModelGradients cpu_out{
        {means.host.data(), log_scales.host.data(), quats.host.data(),
         opacity.host.data(), sh_grad.host.data()},
        {},
        {}};
    LoopModelGradients out{
        {means.device.data(), log_scales.device.data(), quats.device.data(),
         opacity.device.data(), sh_grad.device.data()},
        {},
        {}};
    if (model.motion) {
      cpu_out.motion = {v_tri.host.data(), v_mlp.host.data()};
      out.motion = {v_tri.device.data(), v_mlp.device.data()};
    }
    if (model.residual) {
      cpu_out.residual = {d_tri.host.data(), d_mlp.host.data()};
      out.residual = {d_tri.device.data(), d_mlp.device.data()};
    }
    cpu.Backward(cpu_view, grads, d_residuals.data(), cpu_out);
    device.Backward(view, device_g, device_d_residuals.data(), out);
    means.Expect("d means");
    log_scales.Expect("d log_scales");
    quats.Expect("d quats");
    opacity.Expect("d opacity_logits");
    sh_grad.Expect("d sh");
    v_tri.Expect("d V triplane");
    v_mlp.Expect("d V MLP");
    d_tri.Expect("d D triplane");
    d_mlp.Expect("d D MLP");
  }
}

INSTANTIATE_TEST_SUITE_P(
    Models, DeviceFrameComposerTest,
    ::testing::Values(TinyLoopModelCase{"Degree3", 3, true, true},
                      TinyLoopModelCase{"Degree0", 0, true, true},
                      TinyLoopModelCase{"NoMotionField", 1, false, true},
                      TinyLoopModelCase{"NoResidualField", 1, true, false},
                      TinyLoopModelCase{"NoFields", 1, false, false}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace cuda
}  // namespace es
