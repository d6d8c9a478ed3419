// Every loop over a GaussianSet's arrays goes through kGaussianArrays:
// these tests fill each array with values that name the array, the Gaussian
// and the slot, so an array a loop drops, mixes up or shifts fails here.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/gaussians.h"
#include "costs/splat_render_cost.h"
#include "solvers/checkpoint/checkpoint_io.h"
#include "solvers/optim/adam.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/splat_training.h"
#include "tests/expect_same_gaussians.h"

namespace es {
namespace {

// Value `slot` of Gaussian i in array k: distinct across the whole set.
double Tag(int k, int i, int slot) { return 1e6 * (k + 1) + 1e3 * i + slot; }

GaussianSet Tagged(int n, int sh_degree) {
  GaussianSet g;
  g.sh_degree = sh_degree;
  g.Resize(n);
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    std::vector<double>& v = g.*kGaussianArrays[k].values;
    const int width = kGaussianArrays[k].Width(g.sh_coeffs());
    for (int i = 0; i < n; ++i)
      for (int s = 0; s < width; ++s) v[i * width + s] = Tag(k, i, s);
  }
  return g;
}

// Gaussian `i` of g holds the tags of Gaussian `source` in every array.
void ExpectTagsOf(const GaussianSet& g, int i, int source) {
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    const int width = kGaussianArrays[k].Width(g.sh_coeffs());
    for (int s = 0; s < width; ++s)
      EXPECT_EQ((g.*kGaussianArrays[k].values)[i * width + s],
                Tag(k, source, s))
          << kGaussianArrays[k].name << " of Gaussian " << i;
  }
}

TEST(GaussianArraysTest, TableNamesEachMemberOnceInBlockOrder) {
  const GaussianSet g = Tagged(2, 1);
  std::vector<const std::vector<double>*> seen;
  for (const GaussianArray& a : kGaussianArrays) {
    for (const std::vector<double>* s : seen) EXPECT_NE(s, &(g.*a.values));
    seen.push_back(&(g.*a.values));
  }
  EXPECT_EQ(&(g.*kGaussianArrays[kOpacityArray].values), &g.opacity_logits);
  EXPECT_EQ(&(g.*kGaussianArrays[kShArray].values), &g.sh);
  EXPECT_EQ(&(g.*kGaussianArrays[kDynamicArray].values), &g.dynamic_logits);
}

TEST(GaussianArraysTest, ResizeStartsEveryArrayAtItsFirstValue) {
  GaussianSet g = Tagged(2, 2);
  g.Resize(4);
  g.CheckConsistent();
  for (int i = 0; i < 2; ++i) ExpectTagsOf(g, i, i);
  for (const GaussianArray& a : kGaussianArrays) {
    const int width = a.Width(g.sh_coeffs());
    for (int i = 2; i < 4; ++i)
      for (int s = 0; s < width; ++s)
        EXPECT_EQ((g.*a.values)[i * width + s], s == 0 ? a.first_value : 0.0)
            << a.name;
  }
}

TEST(GaussianArraysTest, AppendAndFilterCarryEveryArray) {
  const GaussianSet source = Tagged(5, 3);
  GaussianSet g;
  g.sh_degree = 3;
  for (int i : {4, 1, 3, 0}) g.AppendFrom(source, i);
  g.CheckConsistent();
  g.Filter({true, false, true, true});
  g.CheckConsistent();
  ASSERT_EQ(g.size(), 3);
  ExpectTagsOf(g, 0, 4);
  ExpectTagsOf(g, 1, 3);
  ExpectTagsOf(g, 2, 0);
}

TEST(GaussianArraysTest, CheckpointRoundTripKeepsEveryArray) {
  const std::string path = testing::TempDir() + "/gaussian_arrays.ckpt";
  const CheckpointMagic magic = "ESGATST";
  const GaussianSet g = Tagged(3, 2);
  GaussianAdamState adam{Tagged(3, 2), Tagged(3, 2), 17};
  for (const GaussianArray& a : kGaussianArrays)
    for (double& x : adam.v.*a.values) x = -x;
  WriteCheckpointFile(path, magic, [&](CheckpointWriter& w) {
    w.Gaussians(g);
    w.Adam(adam);
  });
  ReadCheckpointFile(path, "test checkpoint", magic, [&](CheckpointReader& r) {
    ExpectSameGaussians(r.Gaussians(), g);
    const GaussianAdamState read = r.Adam();
    ExpectSameGaussians(read.m, adam.m);
    ExpectSameGaussians(read.v, adam.v);
    EXPECT_EQ(read.step, 17);
    return 0;
  });
}

TEST(GaussianArraysTest, GuardsSeeEveryArray) {
  const GaussianSet g = Tagged(3, 1);
  EXPECT_TRUE(AllFinite(g));
  const std::vector<double> magnitudes = SplatMagnitudes(g);
  ASSERT_EQ(magnitudes.size(), static_cast<size_t>(kNumGaussianArrays));
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    const int width = kGaussianArrays[k].Width(g.sh_coeffs());
    EXPECT_EQ(magnitudes[k], Tag(k, 2, width - 1)) << kGaussianArrays[k].name;
    GaussianSet bad = g;
    (bad.*kGaussianArrays[k].values)[width] =  // Gaussian 1's first value
        std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(AllFinite(bad)) << kGaussianArrays[k].name;
    EXPECT_TRUE(std::isinf(SplatMagnitudes(bad)[k])) << kGaussianArrays[k].name;
  }
  const std::vector<GuardedBlock> guarded = GuardedSplatBlocks(
      g, 1.0, SplatLearningRateOptions(), SplatLearningRateFlags());
  EXPECT_EQ(guarded.size(), static_cast<size_t>(kNumGaussianArrays));
}

TEST(GaussianArraysTest, AdamStepsEachArrayWithItsOwnRate) {
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    GaussianSet params = Tagged(2, 1);
    const GaussianSet before = params;
    GaussianSet grad = ZeroGaussians(2, 1);
    for (const GaussianArray& a : kGaussianArrays)
      std::fill((grad.*a.values).begin(), (grad.*a.values).end(), 1.0);
    GaussianLearningRates lr;
    lr.*kArrayLearningRates[k] = 0.5;
    if (k == kShArray) lr.sh_rest = 0.25;
    GaussianAdam adam;
    adam.Reset(params);
    adam.Step(lr, grad, &params);
    for (int j = 0; j < kNumGaussianArrays; ++j) {
      const std::vector<double>& x = params.*kGaussianArrays[j].values;
      const std::vector<double>& x0 = before.*kGaussianArrays[j].values;
      const int width = kGaussianArrays[j].Width(params.sh_coeffs());
      for (size_t i = 0; i < x.size(); ++i) {
        // Adam's first step moves each value by its rate.
        const double rate = j != k                              ? 0.0
                            : (j == kShArray && i % width >= 3) ? 0.25
                                                                : 0.5;
        EXPECT_NEAR(x0[i] - x[i], rate, 1e-9)
            << "rate of " << kGaussianArrays[k].name << " moved "
            << kGaussianArrays[j].name << "[" << i << "]";
      }
    }
  }
}

TEST(GaussianArraysTest, SplatBlocksAreTheArraysInTableOrder) {
  GaussianSet g = Tagged(3, 2);
  const std::vector<double*> blocks = SplatRenderCost::Blocks(&g);
  const std::vector<int32_t> sizes = SplatBlockSizes(3, 2);
  ASSERT_EQ(blocks.size(), static_cast<size_t>(kNumGaussianArrays));
  ASSERT_EQ(sizes.size(), static_cast<size_t>(kNumGaussianArrays));
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    EXPECT_EQ(blocks[k], (g.*kGaussianArrays[k].values).data());
    EXPECT_EQ(static_cast<size_t>(sizes[k]),
              (g.*kGaussianArrays[k].values).size());
  }
}

}  // namespace
}  // namespace es
