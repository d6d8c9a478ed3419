#ifndef EULERSPLAT_TESTS_CUDA_EXPECT_TWINS_NEAR_H_
#define EULERSPLAT_TESTS_CUDA_EXPECT_TWINS_NEAR_H_

// Device result against its CPU twin's, value by value, for the double
// device code that sums in another order than the CPU (fields, Euler
// chain): |got - want| <= tolerance * max(1, |want|); a NaN or an infinity
// must be matched by the same on the other side.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/model/gaussians.h"
#include "solvers/train/splat_training.h"

namespace es {
namespace cuda {

inline void ExpectTwinsNear(const std::vector<double>& got,
                            const std::vector<double>& want, double tolerance,
                            const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  int reported = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    const bool same_kind = std::isnan(got[i]) == std::isnan(want[i]) &&
                           std::isinf(got[i]) == std::isinf(want[i]);
    const bool near =
        std::isfinite(want[i])
            ? std::abs(got[i] - want[i]) <=
                  tolerance * std::max(1.0, std::abs(want[i]))
            : !std::isfinite(got[i]) &&
                  (std::isnan(want[i]) || got[i] == want[i]);
    if ((same_kind && near) || reported >= 10) continue;
    ++reported;
    ADD_FAILURE() << what << "[" << i << "]: device " << got[i] << ", CPU "
                  << want[i];
  }
}

// A device field's parameter gradients against the CPU twin's blocks.
inline void ExpectFieldGradientsNear(const DeviceFieldBlocks& got,
                                     const std::vector<double>& triplane,
                                     const std::vector<double>& mlp,
                                     double tolerance) {
  ExpectTwinsNear(got.triplane.Download(), triplane, tolerance, "d_triplane");
  ExpectTwinsNear(got.mlp.Download(), mlp, tolerance, "d_mlp");
}

// Fails when every value is (near) zero: a check that compared zeros with
// zeros would pass whatever the device computed.
inline void ExpectSomeNonZero(const std::vector<double>& v,
                              const char* what) {
  double largest = 0;
  for (double x : v) {
    if (std::isfinite(x)) largest = std::max(largest, std::abs(x));
  }
  EXPECT_GT(largest, 1e-6) << what << " is all zero: nothing was checked";
}

// Adam moves a value by at most about its rate per step, whatever the
// gradient's size, so where float rounding flips a tiny gradient's sign
// the two trainers part by up to twice that, and elsewhere by the
// gradients' relative float error times the rate: every value must agree
// within `tolerance` (twice the rate times the steps), and a share of
// them (95% unless told; 0: no such check) within a tenth of it.
inline void ExpectWithinAdamSteps(const std::vector<double>& cpu,
                                  const std::vector<double>& device,
                                  double tolerance, const char* what,
                                  double tenth_share = 0.95) {
  ASSERT_EQ(cpu.size(), device.size()) << what;
  std::vector<double> diff(cpu.size());
  for (size_t i = 0; i < cpu.size(); ++i)
    diff[i] = std::abs(cpu[i] - device[i]);
  std::sort(diff.begin(), diff.end());
  const double p50 = diff[diff.size() / 2];
  const double p95 = diff[diff.size() * 95 / 100];
  const double share =
      diff[std::min(diff.size() - 1,
                    static_cast<size_t>(diff.size() * tenth_share))];
  const std::string quantiles = std::string(what) + ": median " +
                                std::to_string(p50 / tolerance) + ", 95% " +
                                std::to_string(p95 / tolerance) + ", max " +
                                std::to_string(diff.back() / tolerance) +
                                " of the tolerance";
  EXPECT_LE(diff.back(), tolerance) << quantiles;
  if (tenth_share > 0) {
    EXPECT_LE(share, 0.1 * tolerance) << quantiles;
  }
}

// What ExpectGaussiansWithinAdamSteps allows beyond the Adam-step rule.
struct AdamStepSlack {
  // ExpectWithinAdamSteps' tenth_share, for the rotations and the rest.
  double tenth_share = 0.95;
  double quats_tenth_share = 0.95;
  // Added to the means' tolerance: a densified child sits at its parent's
  // position plus the parent's scaled and rotated draw, so it inherits
  // the parents' scale and rotation differences.
  double means = 0;
};

// Two trainers' Gaussians after `steps` Adam steps from the same start:
// each block within ExpectWithinAdamSteps of twice its rate per step (the
// positions' rate times the scene extent).
inline void ExpectGaussiansWithinAdamSteps(const GaussianSet& cpu,
                                           const GaussianSet& device,
                                           int steps,
                                           const SplatLearningRateOptions& lr,
                                           double extent,
                                           const AdamStepSlack& slack = {}) {
  ASSERT_EQ(cpu.size(), device.size());
  ASSERT_EQ(cpu.sh_degree, device.sh_degree);
  const double k = 2.0 * steps;
  const double share = slack.tenth_share;
  ExpectWithinAdamSteps(cpu.means, device.means,
                        k * lr.means_initial * extent + slack.means, "means",
                        share);
  ExpectWithinAdamSteps(cpu.log_scales, device.log_scales, k * lr.log_scales,
                        "scales", share);
  ExpectWithinAdamSteps(cpu.quats, device.quats, k * lr.quats, "quats",
                        slack.quats_tenth_share);
  ExpectWithinAdamSteps(cpu.opacity_logits, device.opacity_logits,
                        k * lr.opacity, "opacity", share);
  ExpectWithinAdamSteps(cpu.sh, device.sh, k * lr.sh_dc, "sh", share);
  ExpectWithinAdamSteps(cpu.dynamic_logits, device.dynamic_logits,
                        k * lr.dynamic, "dynamic", share);
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_TESTS_CUDA_EXPECT_TWINS_NEAR_H_
