// A standard 3DGS PLY written byte by byte in this test, read with ReadPly
// and rendered: colors, image orientation (x right, y down) and the
// channel-major order of f_rest must come out as derived by hand.

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/io/ply_io.h"
#include "core/render/rasterizer.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

constexpr double kC1 = 0.4886025119029199;  // degree-1 SH constant

struct PlySplat {
  float x, y, z;
  float f_dc[3];
  float f_rest[9];  // degree 1, channel-major: R k1..k3, G k1..k3, B k1..k3
  float opacity_logit, log_scale;
};

// Writes binary little-endian PLY with the property list 3DGS writes.
void WriteStandardPly(const std::string& path,
                      const std::vector<PlySplat>& splats) {
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  header += "element vertex " + std::to_string(splats.size()) + "\n";
  std::vector<std::string> names = {"x", "y", "z", "nx", "ny", "nz",
                                    "f_dc_0", "f_dc_1", "f_dc_2"};
  for (int i = 0; i < 9; ++i) names.push_back("f_rest_" + std::to_string(i));
  for (const char* n : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0",
                        "rot_1", "rot_2", "rot_3"}) {
    names.push_back(n);
  }
  for (const std::string& n : names) header += "property float " + n + "\n";
  header += "end_header\n";
  std::ofstream out(path, std::ios::binary);
  out << header;
  for (const PlySplat& s : splats) {
    std::vector<float> row = {s.x, s.y, s.z, 0, 0, 0,
                              s.f_dc[0], s.f_dc[1], s.f_dc[2]};
    row.insert(row.end(), s.f_rest, s.f_rest + 9);
    row.insert(row.end(), {s.opacity_logit, s.log_scale, s.log_scale,
                           s.log_scale, 1, 0, 0, 0});
    static_assert(sizeof(float) == 4, "PLY float is 4 bytes");
    out.write(reinterpret_cast<const char*>(row.data()),
              row.size() * sizeof(float));  // x86: already little-endian
  }
}

float Dc(double color) { return static_cast<float>((color - 0.5) / kShC0); }

class RasterizerPlyTest : public TempDirTest {
 protected:
  // Each test writes its own file: ctest runs the tests in parallel.
  void SetUp() override {
    TempDirTest::SetUp();
    path_ = Path("splats.ply");
    const float log_scale = std::log(0.05f);  // 1 px at z = 5, f = 100
    const float logit = std::log(0.9f / 0.1f);
    PlySplat red = {1, 0, 5, {Dc(1), Dc(0), Dc(0)}, {}, logit, log_scale};
    PlySplat green = {0, 1, 5, {Dc(0), Dc(1), Dc(0)}, {}, logit, log_scale};
    // Gray, plus only the red channel's x coefficient (k = 3, basis
    // -C1 * dir.x): f_rest_2 in channel-major order.
    PlySplat sh = {-1, 0, 5, {Dc(0.5), Dc(0.5), Dc(0.5)}, {}, logit,
                   log_scale};
    sh.f_rest[2] = 2.0f;
    WriteStandardPly(path_, {red, green, sh});
  }
  // 64 x 48, f = 100, looking down +z from (cam_x, 0, 0); the principal
  // point puts (0, 0, 5) - (cam_x, 0, 0) at pixel centers.
  static Camera MakeCamera(double cam_x) {
    Camera c;
    c.width = 64;
    c.height = 48;
    c.fx = c.fy = 100;
    c.cx = 32.5;
    c.cy = 24.5;
    c.t_cw = Eigen::Vector3d(-cam_x, 0, 0);
    return c;
  }

  std::string path_;
};

TEST_F(RasterizerPlyTest, RendersColorsOrientationAndShOrder) {
  const GaussianSet g = ReadPly(path_);
  ASSERT_EQ(g.size(), 3);
  ASSERT_EQ(g.sh_degree, 1);
  Rasterizer r;
  RenderResult out;
  r.Forward(MakeCamera(0), SplatView::Of(g), RenderOptions(), &out);
  EXPECT_EQ(r.num_visible(), 3);
  auto rgb = [&out](int j, int i, int c) {
    return out.rgb[3 * (i * out.width + j) + c];
  };
  // At a splat's own pixel center alpha = opacity = 0.9; the other splats
  // are 20 px (20 sigma) away and do not reach it.
  // Red at x = +1: u = 32.5 + 100 / 5 = 52.5, to the right of center.
  EXPECT_NEAR(rgb(52, 24, 0), 0.9, 1e-5);
  EXPECT_NEAR(rgb(52, 24, 1), 0.0, 1e-5);
  EXPECT_NEAR(rgb(52, 24, 2), 0.0, 1e-5);
  EXPECT_NEAR(rgb(12, 24, 1), 0.9 * 0.5, 1e-5);  // not red on the left
  // Green at y = +1: v = 44.5, below center (y down).
  EXPECT_NEAR(rgb(32, 44, 1), 0.9, 1e-5);
  EXPECT_NEAR(rgb(32, 44, 0), 0.0, 1e-5);
  EXPECT_NEAR(rgb(32, 4, 1), 0.0, 1e-5);  // nothing above
  // SH splat at x = -1, seen along dir = (-1, 0, 5) / sqrt(26):
  // red = 0.5 + (-C1 * dir.x) * 2; green and blue stay 0.5.
  const double red_left = 0.5 + kC1 / std::sqrt(26.0) * 2;
  EXPECT_NEAR(rgb(12, 24, 0), 0.9 * red_left, 1e-5);
  EXPECT_NEAR(rgb(12, 24, 2), 0.9 * 0.5, 1e-5);
  // The background is black and nothing lies at the image center.
  EXPECT_NEAR(rgb(32, 24, 0) + rgb(32, 24, 1) + rgb(32, 24, 2), 0, 1e-9);
}

TEST_F(RasterizerPlyTest, ShColorChangesWithViewDirection) {
  const GaussianSet g = ReadPly(path_);
  Rasterizer r;
  RenderResult out;
  // From x = -2 the SH splat at x = -1 is seen along (1, 0, 5) / sqrt(26),
  // and it projects to u = 32.5 + 100 * 1 / 5 = 52.5.
  r.Forward(MakeCamera(-2), SplatView::Of(g), RenderOptions(), &out);
  const int p = 24 * out.width + 52;
  const double red_right = 0.5 - kC1 / std::sqrt(26.0) * 2;
  EXPECT_NEAR(out.rgb[3 * p + 0], 0.9 * red_right, 1e-5);
  EXPECT_NEAR(out.rgb[3 * p + 1], 0.9 * 0.5, 1e-5);
  EXPECT_NEAR(out.rgb[3 * p + 2], 0.9 * 0.5, 1e-5);
}

}  // namespace
}  // namespace es
