// Device Adam against the CPU's (solvers/optim/adam.h): several steps on
// random gradients, one block (AdamUpdate, including values whose gradient
// and moments are zero, which the CPU skips) and every GaussianSet block
// with its own learning rate (GaussianAdam::Step, SH DC and higher bands
// apart, a zero rate leaving its block alone). Skips when no CUDA device
// is present.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/gaussians.h"
#include "core/base/cuda/cuda_error.h"
#include "tests/cuda/require_gpu.h"
#include "core/base/cuda/device_buffer.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/cuda/device_adam.h"

namespace es {
namespace cuda {
namespace {

// Double rounding only (the device may fuse multiply-adds).
constexpr double kTol = 1e-12;

void ExpectClose(const std::vector<double>& got,
                 const std::vector<double>& want, const std::string& name) {
  ASSERT_EQ(got.size(), want.size()) << name;
  for (size_t i = 0; i < want.size(); ++i) {
    ASSERT_NEAR(got[i], want[i], kTol * std::max(1.0, std::abs(want[i])))
        << name << "[" << i << "]";
  }
}

void Fill(std::vector<double>* v, std::mt19937* rng, double scale) {
  std::normal_distribution<double> normal(0, scale);
  for (double& x : *v) x = normal(*rng);
}

TEST(DeviceAdam, UpdateMatchesCpu) {
  ES_REQUIRE_GPU("CUDA Adam");
  const int n = 1000;  // not a multiple of the block size
  std::mt19937 rng(3);
  std::vector<double> x(n), m(n, 0.0), v(n, 0.0), grad(n);
  Fill(&x, &rng, 1.0);
  DeviceBuffer<double> dx, dm, dv, dgrad;
  dx.Upload(x);
  dm.Upload(m);
  dv.Upload(v);
  const AdamOptions options;
  for (int t = 1; t <= 6; ++t) {
    // Gradients over five orders of magnitude; the first 128 values get
    // none in the first steps (zero moments: the CPU skips their chunks).
    Fill(&grad, &rng, std::pow(10.0, -t));
    if (t <= 2) std::fill(grad.begin(), grad.begin() + 128, 0.0);
    const double lr = 0.01 / t;
    AdamUpdate(options, t, lr, n, grad.data(), m.data(), v.data(), x.data());
    dgrad.Upload(grad);
    DeviceAdamUpdate(options, t, lr, n, dgrad.data(), dm.data(), dv.data(),
                     dx.data());
    ExpectClose(dm.Download(), m, "m");
    ExpectClose(dv.Download(), v, "v");
    ExpectClose(dx.Download(), x, "x");
  }
}

// A GaussianSet's arrays on the device.
struct DeviceSet {
  DeviceBuffer<double> means, log_scales, quats, opacity_logits, sh,
      dynamic_logits;
  int count = 0, sh_degree = 0;

  void Upload(const GaussianSet& s) {
    count = s.size();
    sh_degree = s.sh_degree;
    means.Upload(s.means);
    log_scales.Upload(s.log_scales);
    quats.Upload(s.quats);
    opacity_logits.Upload(s.opacity_logits);
    sh.Upload(s.sh);
    dynamic_logits.Upload(s.dynamic_logits);
  }
  DeviceGaussianBlocks Blocks() {
    return {count,      sh_degree,         means.data(),
            log_scales.data(), quats.data(), opacity_logits.data(),
            sh.data(),  dynamic_logits.data()};
  }
};

void RandomSet(GaussianSet* s, std::mt19937* rng, double scale) {
  for (std::vector<double>* a :
       {&s->means, &s->log_scales, &s->quats, &s->opacity_logits, &s->sh,
        &s->dynamic_logits}) {
    Fill(a, rng, scale);
  }
}

void ExpectSetsClose(const GaussianSet& got, const GaussianSet& want,
                     const std::string& what) {
  ExpectClose(got.means, want.means, what + ".means");
  ExpectClose(got.log_scales, want.log_scales, what + ".log_scales");
  ExpectClose(got.quats, want.quats, what + ".quats");
  ExpectClose(got.opacity_logits, want.opacity_logits,
              what + ".opacity_logits");
  ExpectClose(got.sh, want.sh, what + ".sh");
  ExpectClose(got.dynamic_logits, want.dynamic_logits,
              what + ".dynamic_logits");
}

TEST(DeviceAdam, GaussianStepMatchesCpu) {
  ES_REQUIRE_GPU("CUDA Adam");
  const int n = 77, degree = 2;  // 27 SH values per Gaussian
  std::mt19937 rng(11);
  GaussianSet params = ZeroGaussians(n, degree);
  RandomSet(&params, &rng, 1.0);
  GaussianLearningRates lr;
  lr.means = 1.6e-4;
  lr.log_scales = 5e-3;
  lr.quats = 0;  // left alone, moments too
  lr.opacity_logits = 5e-2;
  lr.sh_dc = 2.5e-3;
  lr.sh_rest = 2.5e-3 / 20;
  lr.dynamic_logits = 1e-2;

  GaussianAdam cpu;
  cpu.Reset(params);
  DeviceGaussianAdam device;
  device.Reset(n, degree);
  DeviceSet dparams, dgrad;
  dparams.Upload(params);
  GaussianSet grad = ZeroGaussians(n, degree);
  for (int t = 1; t <= 5; ++t) {
    RandomSet(&grad, &rng, 1e-3 * t);
    cpu.Step(lr, grad, &params);
    dgrad.Upload(grad);
    device.Step(lr, dgrad.Blocks(), dparams.Blocks());
  }
  EXPECT_EQ(device.step(), cpu.step());
  GaussianSet got = ZeroGaussians(n, degree);
  got.means = dparams.means.Download();
  got.log_scales = dparams.log_scales.Download();
  got.quats = dparams.quats.Download();
  got.opacity_logits = dparams.opacity_logits.Download();
  got.sh = dparams.sh.Download();
  got.dynamic_logits = dparams.dynamic_logits.Download();
  ExpectSetsClose(got, params, "params");
  GaussianSet m, v;
  device.Download(&m, &v);
  ExpectSetsClose(m, cpu.m(), "m");
  ExpectSetsClose(v, cpu.v(), "v");
}

}  // namespace
}  // namespace cuda
}  // namespace es
