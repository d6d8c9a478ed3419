// es_export's outputs without a browser: the frame PLY is a state the
// animation really shows, and the loop file holds exactly the animation.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "core/base/input_error.h"
#include "core/io/ply_io.h"
#include "core/loop/loop_file.h"
#include "core/loop/loop_frame.h"
#include "core/loop/loop_renderer.h"
#include "core/viz/web_player.h"
#include "tests/temp_dir_test.h"
#include "tests/water_loop_fixture.h"
#include "tests/web_tools.h"

using ::testing::HasSubstr;
using ::testing::Not;

namespace es {
namespace {

class WebExportTest : public TempDirTest {};

std::vector<double> RenderSplats(const GaussianSet& g) {
  Rasterizer rasterizer;
  RenderResult r;
  rasterizer.Forward(WaterLoopCamera(), SplatView::Of(g), RenderOptions(), &r);
  return r.rgb;
}

TEST_F(WebExportTest, FramePlyRendersAsTheAnimationFrame) {
  const LoopModel model = WaterLoopModel();
  LoopRenderer player(&model, RenderOptions());
  player.Start(0);
  for (int frame = 0; frame < 2 * kWaterLoopLength; ++frame) {
    if (frame > 0) player.Advance();
    const GaussianSet splats = LoopFrameSplats(model, frame);
    const std::vector<double> animated = player.Render(WaterLoopCamera()).rgb;
    ASSERT_EQ(RenderSplats(splats), animated) << "frame " << frame;
  }
  // Not the canonical state, and through the PLY (float32) the same image.
  const GaussianSet frame3 = LoopFrameSplats(model, 3);
  EXPECT_NE(frame3.means, model.gaussians.means);
  WritePly(frame3, Path("frame3.ply"));
  const std::vector<double> a = RenderSplats(frame3),
                            b = RenderSplats(ReadPly(Path("frame3.ply")));
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, std::abs(a[i] - b[i]));
  EXPECT_LT(worst, 1e-4);
}

float Half(const uint16_t* p) {
  return static_cast<float>(cv::float16_t::fromBits(*p));
}

TEST_F(WebExportTest, LoopFileHoldsEveryFrameOfTheWater) {
  const LoopModel model = WaterLoopModel();
  LoopFileOptions options;
  options.fps = 12;
  options.background = {1, 1, 1};
  const int64_t size = WriteLoopFile(model, options, Path("a.esloop"));
  const std::string bytes = ReadWholeFile(Path("a.esloop"));
  ASSERT_EQ(static_cast<int64_t>(bytes.size()), size);
  ASSERT_EQ(std::memcmp(bytes.data(), kLoopFileMagic, 8), 0);
  auto u32 = [&bytes](int offset) {
    uint32_t v;
    std::memcpy(&v, &bytes[offset], 4);
    return v;
  };
  auto f32 = [&bytes](int offset) {
    float v;
    std::memcpy(&v, &bytes[offset], 4);
    return v;
  };
  const int n = model.gaussians.size(), w = model.num_dynamic();
  const int l = kWaterLoopLength;
  EXPECT_EQ(u32(8), 1u);
  EXPECT_EQ(u32(12), static_cast<uint32_t>(n));
  EXPECT_EQ(u32(16), static_cast<uint32_t>(w));
  EXPECT_EQ(u32(20), static_cast<uint32_t>(l));
  EXPECT_EQ(f32(24), 12.0f);
  EXPECT_EQ(f32(28), 1.0f);
  const uint32_t ply_offset = u32(40), ply_size = u32(44);
  EXPECT_EQ(ply_offset, 48u);

  // The PLY: frame 0, water splats first.
  WriteWholeFile(Path("part.ply"), bytes.substr(ply_offset, ply_size));
  const GaussianSet part = ReadPly(Path("part.ply"));
  const GaussianSet frame0 = LoopFrameSplats(model, 0);
  ASSERT_EQ(part.size(), n);
  EXPECT_EQ(part.sh_degree, model.gaussians.sh_degree);
  std::vector<int> order = model.dynamic_index;
  for (int g = 0; g < n; ++g)
    if (model.gaussians.dynamic_logits[g] < 0) order.push_back(g);
  for (int row = 0; row < n; ++row)
    for (int a = 0; a < 3; ++a)
      ASSERT_FLOAT_EQ(part.means[3 * row + a],
                      frame0.means[3 * order[row] + a]);

  // The table: every frame's water positions, colors and opacities.
  const size_t table = (ply_offset + ply_size + 3) / 4 * 4;
  ASSERT_EQ(bytes.size(), table + 2 * 7 * static_cast<size_t>(l) * w);
  const uint16_t* v = reinterpret_cast<const uint16_t*>(&bytes[table]);
  const int k_count = model.gaussians.sh_coeffs();
  double moved = 0;
  for (int f = 0; f < l; ++f) {
    const GaussianSet s = LoopFrameSplats(model, f);
    for (int k = 0; k < w; ++k, v += 7) {
      const int g = model.dynamic_index[k];
      for (int a = 0; a < 3; ++a) {
        ASSERT_NEAR(Half(v + a), s.means[3 * g + a], 1e-3) << f << " " << k;
        ASSERT_NEAR(Half(v + 3 + a), 0.5 + kShC0 * s.sh[3 * k_count * g + a],
                    2e-3);
        moved += std::abs(s.means[3 * g + a] - frame0.means[3 * g + a]);
      }
      ASSERT_NEAR(Half(v + 6), Sigmoid(s.opacity_logits[g]), 1e-3);
    }
  }
  EXPECT_GT(moved / (l * w), 0.01);  // the water does move
}

TEST_F(WebExportTest, PageFolderIsCompleteOrNamesWhatIsMissing) {
  const LoopModel model = WaterLoopModel();
  WebPlayerOptions options;
  options.page_dir = std::string(ES_SOURCE_DIR) + "/web/player";
  options.modules_dir = Path("no_modules");
  try {
    ExportWebPlayer(model, {WaterLoopCamera()}, options, Path("page"));
    FAIL() << "no error without the npm packages";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("setup.sh")) << e.what();
  }
  if (!HaveWebModule("@sparkjsdev/spark/dist/spark.module.js"))
    GTEST_SKIP() << "npm packages not installed (scripts/setup.sh)";
  options.modules_dir = WebModulePath("");
  ExportWebPlayer(model, {WaterLoopCamera()}, options, Path("page"));
  for (const char* file :
       {"index.html", "player.js", "view.json", "scene.esloop", "poster.png",
        "lib/spark/spark.module.js", "lib/three/build/three.module.js",
        "lib/three/build/three.core.js",
        "lib/three/examples/jsm/controls/OrbitControls.js"})
    EXPECT_TRUE(std::filesystem::exists(Path("page/") + file)) << file;
  // The page imports nothing from outside its folder.
  const std::string html = ReadWholeFile(Path("page/index.html")) +
                           ReadWholeFile(Path("page/player.js"));
  EXPECT_THAT(html, Not(HasSubstr("http://")));
  EXPECT_THAT(html, Not(HasSubstr("https://")));
}

// A page that has not run its player yet (a screenshot taken early, a slow
// machine, no WebGL) shows the poster: the page's first element is an
// image of poster.png, and poster.png is loop frame 0 from the start
// camera exactly as es_animate renders it, on the model's background.
TEST_F(WebExportTest, PosterIsLoopFrameZeroFromTheStartCamera) {
  if (!HaveWebModule("@sparkjsdev/spark/dist/spark.module.js"))
    GTEST_SKIP() << "npm packages not installed (scripts/setup.sh)";
  const LoopModel model = WaterLoopModel();
  Camera other = WaterLoopCamera();
  other.width = 64;  // a second camera the poster must not use
  WebPlayerOptions options;
  options.page_dir = std::string(ES_SOURCE_DIR) + "/web/player";
  options.modules_dir = WebModulePath("");
  options.background = Eigen::Vector3d(1, 1, 1);
  ExportWebPlayer(model, {WaterLoopCamera(), other}, options, Path("page"));

  const std::string html = ReadWholeFile(Path("page/index.html"));
  const size_t body = html.find("<body>");
  ASSERT_NE(body, std::string::npos);
  EXPECT_EQ(html.find("<", body + 6),
            html.find("<img id=\"poster\" src=\"poster.png\"", body))
      << html.substr(body);
  // The player takes it away once it has drawn.
  EXPECT_THAT(ReadWholeFile(Path("page/player.js")),
              HasSubstr("getElementById(\"poster\")?.remove()"));

  const cv::Mat poster = cv::imread(Path("page/poster.png"), cv::IMREAD_COLOR);
  ASSERT_FALSE(poster.empty());
  RenderOptions render;
  render.background = options.background;
  LoopRenderer player(&model, render);
  player.Start(0);
  const RenderResult& r = player.Render(WaterLoopCamera());
  ASSERT_EQ(poster.cols, r.width);
  ASSERT_EQ(poster.rows, r.height);
  for (int i = 0; i < r.height; ++i)
    for (int j = 0; j < r.width; ++j)
      for (int c = 0; c < 3; ++c) {
        const double v = r.rgb[3 * (i * r.width + j) + c];
        ASSERT_EQ(poster.at<cv::Vec3b>(i, j)[2 - c],
                  std::lround(std::clamp(v, 0.0, 1.0) * 255))
            << "pixel " << i << "," << j;
      }
  // The scene fills much of the view: not a blank page.
  const long covered = std::count_if(r.alpha.begin(), r.alpha.end(),
                                     [](double a) { return a > 0.5; });
  EXPECT_GT(covered, r.width * r.height / 4);
}

}  // namespace
}  // namespace es
