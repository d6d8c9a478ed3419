// Device Adam against the CPU's (solvers/optim/adam.h): several steps on
// random gradients, one block (AdamUpdate, including values whose gradient
// and moments are zero, which the CPU skips) and every GaussianSet block
// with its own learning rate (GaussianAdam::Step, SH DC and higher bands
// apart, a zero rate leaving its block alone). Skips when no CUDA device
// is present.

#include <algorithm>
#include <array>
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
  std::array<DeviceBuffer<double>, kNumGaussianArrays> arrays;
  int count = 0, sh_degree = 0;

  void Upload(const GaussianSet& s) {
    count = s.size();
    sh_degree = s.sh_degree;
    for (int k = 0; k < kNumGaussianArrays; ++k)
      arrays[k].Upload(s.*kGaussianArrays[k].values);
  }
  GaussianSet Download() const {
    GaussianSet s;
    s.sh_degree = sh_degree;
    for (int k = 0; k < kNumGaussianArrays; ++k)
      s.*kGaussianArrays[k].values = arrays[k].Download();
    return s;
  }
  DeviceGaussianBlocks Blocks() {
    DeviceGaussianBlocks b{count, sh_degree, {}};
    for (int k = 0; k < kNumGaussianArrays; ++k) b.arrays[k] = arrays[k].data();
    return b;
  }
};

void RandomSet(GaussianSet* s, std::mt19937* rng, double scale) {
  for (const GaussianArray& a : kGaussianArrays)
    Fill(&(s->*a.values), rng, scale);
}

void ExpectSetsClose(const GaussianSet& got, const GaussianSet& want,
                     const std::string& what) {
  ASSERT_EQ(got.sh_degree, want.sh_degree) << what;
  for (const GaussianArray& a : kGaussianArrays)
    ExpectClose(got.*a.values, want.*a.values, what + "." + a.name);
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
  ExpectSetsClose(dparams.Download(), params, "params");
  GaussianSet m, v;
  device.Download(&m, &v);
  ExpectSetsClose(m, cpu.m(), "m");
  ExpectSetsClose(v, cpu.v(), "v");
}

}  // namespace
}  // namespace cuda
}  // namespace es
