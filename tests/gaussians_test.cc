#include "core/model/gaussians.h"

#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace {

// Gaussian i gets values that encode i and the slot, so any mix-up shows.
GaussianSet Numbered(int n, int degree) {
  GaussianSet g;
  g.sh_degree = degree;
  g.Resize(n);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      g.means[3 * i + a] = 100 * i + a;
      g.log_scales[3 * i + a] = -(100 * i + a);
    }
    for (int a = 0; a < 4; ++a) g.quats[4 * i + a] = 1000 * i + a;
    g.opacity_logits[i] = i + 0.5;
    g.dynamic_logits[i] = -i - 0.25;
    const int k_count = g.sh_coeffs();
    for (int k = 0; k < k_count; ++k)
      for (int c = 0; c < 3; ++c)
        g.sh[(i * k_count + k) * 3 + c] = 10000 * i + 10 * k + c;
  }
  return g;
}

// Expects Gaussian i of `a` to equal Gaussian j of `b` in every attribute.
void ExpectSameGaussian(const GaussianSet& a, int i, const GaussianSet& b,
                        int j) {
  ASSERT_EQ(a.sh_degree, b.sh_degree);
  for (int x = 0; x < 3; ++x) {
    EXPECT_EQ(a.means[3 * i + x], b.means[3 * j + x]);
    EXPECT_EQ(a.log_scales[3 * i + x], b.log_scales[3 * j + x]);
  }
  for (int x = 0; x < 4; ++x) EXPECT_EQ(a.quats[4 * i + x], b.quats[4 * j + x]);
  EXPECT_EQ(a.opacity_logits[i], b.opacity_logits[j]);
  EXPECT_EQ(a.dynamic_logits[i], b.dynamic_logits[j]);
  const int w = 3 * a.sh_coeffs();
  for (int x = 0; x < w; ++x) EXPECT_EQ(a.sh[w * i + x], b.sh[w * j + x]);
}

TEST(GaussianSetTest, ResizeGrowsWithZerosAndIdentityRotations) {
  GaussianSet g = Numbered(2, 1);
  const GaussianSet before = g;
  g.Resize(5);
  g.CheckConsistent();
  ASSERT_EQ(g.size(), 5);
  for (int i = 0; i < 2; ++i) ExpectSameGaussian(g, i, before, i);
  for (int i = 2; i < 5; ++i) {
    EXPECT_EQ(g.quats[4 * i], 1.0);
    for (int x = 1; x < 4; ++x) EXPECT_EQ(g.quats[4 * i + x], 0.0);
    for (int x = 0; x < 3; ++x) {
      EXPECT_EQ(g.means[3 * i + x], 0.0);
      EXPECT_EQ(g.log_scales[3 * i + x], 0.0);
    }
    EXPECT_EQ(g.opacity_logits[i], 0.0);
    EXPECT_EQ(g.dynamic_logits[i], 0.0);
    for (int x = 0; x < 12; ++x) EXPECT_EQ(g.sh[12 * i + x], 0.0);
  }
  g.Resize(1);
  g.CheckConsistent();
  ASSERT_EQ(g.size(), 1);
  ExpectSameGaussian(g, 0, before, 0);
}

TEST(GaussianSetTest, SetShDegreeKeepsLowerOrderCoefficients) {
  const GaussianSet original = Numbered(3, 1);
  GaussianSet g = original;
  g.SetShDegree(3);
  g.CheckConsistent();
  ASSERT_EQ(g.sh_coeffs(), 16);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 16; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(g.sh[(i * 16 + k) * 3 + c],
                  k < 4 ? original.sh[(i * 4 + k) * 3 + c] : 0.0)
            << i << " " << k << " " << c;
  EXPECT_EQ(g.means, original.means);

  g.SetShDegree(0);
  g.CheckConsistent();
  ASSERT_EQ(g.sh.size(), 9u);
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(g.sh[i * 3 + c], original.sh[(i * 4) * 3 + c]);
}

TEST(GaussianSetTest, FilterKeepsSelectedInOrder) {
  const GaussianSet original = Numbered(6, 2);
  GaussianSet g = original;
  g.Filter({true, false, false, true, true, false});
  g.CheckConsistent();
  ASSERT_EQ(g.size(), 3);
  ExpectSameGaussian(g, 0, original, 0);
  ExpectSameGaussian(g, 1, original, 3);
  ExpectSameGaussian(g, 2, original, 4);

  g.Filter({false, false, false});
  g.CheckConsistent();
  EXPECT_EQ(g.size(), 0);
}

TEST(GaussianSetTest, AppendFromCopiesOneGaussian) {
  const GaussianSet source = Numbered(4, 3);
  GaussianSet g = Numbered(1, 3);
  g.AppendFrom(source, 2);
  g.AppendFrom(source, 0);
  g.CheckConsistent();
  ASSERT_EQ(g.size(), 3);
  ExpectSameGaussian(g, 1, source, 2);
  ExpectSameGaussian(g, 2, source, 0);

  GaussianSet empty;
  empty.sh_degree = 3;
  empty.AppendFrom(source, 3);
  ASSERT_EQ(empty.size(), 1);
  ExpectSameGaussian(empty, 0, source, 3);
}

TEST(GaussianSetDeathTest, AppendFromOtherShDegreeDies) {
  const GaussianSet source = Numbered(2, 1);
  GaussianSet g = Numbered(1, 0);
  EXPECT_DEATH(g.AppendFrom(source, 0), "");
}

}  // namespace
}  // namespace es
