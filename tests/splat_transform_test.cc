// Our PLY files against @playcanvas/splat-transform, a widely used converter
// between 3DGS formats (installed by scripts/setup.sh from the npm registry;
// skipped without node or the package).

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "core/io/ply_io.h"
#include "core/model/gaussians.h"
#include "tests/temp_dir_test.h"
#include "tests/web_tools.h"

namespace es {
namespace {

class SplatTransformTest : public TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    if (!HaveProgram("node")) GTEST_SKIP() << "node is not installed";
    if (!HaveWebModule("@playcanvas/splat-transform/bin/cli.mjs"))
      GTEST_SKIP() << "@playcanvas/splat-transform is not installed "
                      "(scripts/setup.sh installs it into web/node_modules)";
  }

  // Converts `in` to `out` (formats from the extensions).
  void Convert(const std::string& in, const std::string& out) {
    const std::string command =
        "node " +
        Quoted(WebModulePath("@playcanvas/splat-transform/bin/cli.mjs")) +
        " -q -w " + Quoted(in) + " " + Quoted(out);
    ASSERT_EQ(RunLogged(command, Path("log.txt")), 0)
        << command << "\n"
        << ReadWholeFile(Path("log.txt"));
  }
};

// Opaque, transparent and in-between splats in a unit box.
GaussianSet Splats(int n) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  GaussianSet g;
  g.sh_degree = 1;
  g.Resize(n);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      g.means[3 * i + a] = u(rng);
      g.log_scales[3 * i + a] = -3 + 0.5 * u(rng);
    }
    for (int a = 0; a < 4; ++a) g.quats[4 * i + a] = u(rng);
    for (int k = 0; k < 3 * g.sh_coeffs(); ++k)
      g.sh[3 * g.sh_coeffs() * i + k] = 0.3 * u(rng);
    g.opacity_logits[i] = i % 3 == 0 ? 9.0 : i % 3 == 1 ? -9.0 : u(rng);
  }
  return g;
}

// splat-transform reads our file and writes one back that we read; its
// compressed format stores opacity in 8 bits, so opacity 1 and 0 come back as
// logits +/-Inf, which ReadPly clamps to the file's finite range.
TEST_F(SplatTransformTest, OurPlyRoundTripsThroughItsCompressedFormat) {
  const GaussianSet g = Splats(600);
  WritePly(g, Path("ours.ply"));
  Convert(Path("ours.ply"), Path("small.compressed.ply"));
  Convert(Path("small.compressed.ply"), Path("back.ply"));
  const GaussianSet read = ReadPly(Path("back.ply"));
  ASSERT_EQ(read.size(), g.size());
  // The opaque and the transparent third came back as +/-Inf.
  EXPECT_GE(std::count(read.opacity_logits.begin(), read.opacity_logits.end(),
                       std::log(9999.0)),
            g.size() / 3);
  // It reorders splats (Morton order): match each to the nearest original.
  // Positions are quantized to ~11 bits per chunk of 256 splats; opacity to
  // 8 bits.
  double worst_position = 0, worst_opacity = 0;
  for (int i = 0; i < read.size(); ++i) {
    ASSERT_TRUE(std::isfinite(read.opacity_logits[i])) << i;
    const Eigen::Map<const Eigen::Vector3d> p(&read.means[3 * i]);
    int nearest = 0;
    double best = 1e30;
    for (int j = 0; j < g.size(); ++j) {
      const double d =
          (p - Eigen::Map<const Eigen::Vector3d>(&g.means[3 * j])).norm();
      if (d < best) best = d, nearest = j;
    }
    worst_position = std::max(worst_position, best);
    worst_opacity =
        std::max(worst_opacity, std::abs(Sigmoid(read.opacity_logits[i]) -
                                          Sigmoid(g.opacity_logits[nearest])));
  }
  EXPECT_LT(worst_position, 0.01);
  EXPECT_LT(worst_opacity, 3.0 / 255);
}

}  // namespace
}  // namespace es
