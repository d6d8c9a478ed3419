// The web page es_export writes, in a real browser: Debian's headless
// Chromium driven by puppeteer-core (web/test/screenshot_loop.mjs). Skipped
// where Chromium, node or the npm packages are not installed
// (scripts/setup.sh installs them).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/loop/loop_renderer.h"
#include "core/viz/video_writer.h"
#include "core/viz/web_player.h"
#include "tests/temp_dir_test.h"
#include "tests/water_loop_fixture.h"
#include "tests/web_tools.h"

namespace es {
namespace {

constexpr char kChromium[] = "/usr/bin/chromium";

class BrowserTest : public TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    if (!std::filesystem::exists(kChromium))
      GTEST_SKIP() << kChromium << " is not installed (apt-get install "
                   << "chromium; scripts/setup.sh does)";
    if (!HaveProgram("node")) GTEST_SKIP() << "node is not installed";
    for (const char* module : {"puppeteer-core/package.json",
                               "@sparkjsdev/spark/dist/spark.module.js"})
      if (!HaveWebModule(module))
        GTEST_SKIP() << module << " is not installed in web/node_modules "
                     << "(scripts/setup.sh installs it)";
  }
};

// An 8-bit RGB image as es_animate writes it, or as a screenshot.
using Image = cv::Mat;  // CV_8UC3, BGR

Image Animated(const LoopModel& model, int frame, std::vector<double>* alpha) {
  LoopRenderer player(&model, RenderOptions());
  player.Start(frame);
  const RenderResult& r = player.Render(WaterLoopCamera());
  if (alpha) *alpha = r.alpha;
  return RgbToBgr8(r.rgb.data(), r.width, r.height).clone();
}

// Mean squared difference (8-bit levels / 255) over the pixels of `mask`.
double Mse(const Image& a, const Image& b, const std::vector<bool>& mask) {
  double sum = 0;
  int count = 0;
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < a.cols; ++j) {
      if (!mask[i * a.cols + j]) continue;
      const cv::Vec3b pa = a.at<cv::Vec3b>(i, j), pb = b.at<cv::Vec3b>(i, j);
      for (int c = 0; c < 3; ++c) {
        const double d = (pa[c] - pb[c]) / 255.0;
        sum += d * d;
      }
      count += 3;
    }
  return count ? sum / count : 0;
}

double Psnr(double mse) { return 10 * std::log10(1 / std::max(mse, 1e-10)); }

TEST_F(BrowserTest, PagePlaysTheLoopAsEsAnimateRendersIt) {
  const LoopModel model = WaterLoopModel();
  const Camera camera = WaterLoopCamera();
  WebPlayerOptions options;
  options.page_dir = std::string(ES_SOURCE_DIR) + "/web/player";
  options.modules_dir = WebModulePath("");
  ExportWebPlayer(model, {camera}, options, Path("page"));

  const int a = 0, b = kWaterLoopLength / 2;
  const std::string command =
      "node " + Quoted(std::string(ES_SOURCE_DIR) +
                       "/web/test/screenshot_loop.mjs") +
      " --page " + Quoted(Path("page")) + " --out " + Quoted(dir_.string()) +
      " --frames " + std::to_string(a) + "," + std::to_string(b) +
      " --chromium " + kChromium;
  const int status = RunLogged(command, Path("node.txt"));
  std::printf("%s", ReadWholeFile(Path("node.txt")).c_str());
  ASSERT_EQ(status, 0)
      << command << "\n" << ReadWholeFile(Path("node.txt"))
      << ReadWholeFile(Path("console.txt"));
  const Image page_a = cv::imread(Path("frame_0.png"), cv::IMREAD_COLOR);
  const Image page_b =
      cv::imread(Path("frame_" + std::to_string(b) + ".png"), cv::IMREAD_COLOR);
  ASSERT_EQ(page_a.cols, camera.width);
  ASSERT_EQ(page_a.rows, camera.height);
  ASSERT_EQ(page_b.size(), page_a.size());

  // Regions from our own renders: water where any water splat covers a
  // pixel in some frame, static where none ever does and the wall is
  // opaque.
  LoopModel water_only = model, static_only = model;
  for (int g = 0; g < model.gaussians.size(); ++g) {
    const bool water = model.gaussians.dynamic_logits[g] > 0;
    (water ? static_only : water_only).gaussians.opacity_logits[g] = -30;
  }
  std::vector<double> water_alpha(camera.width * camera.height, 0), alpha;
  for (int f = 0; f < kWaterLoopLength; ++f) {
    Animated(water_only, f, &alpha);
    for (size_t p = 0; p < alpha.size(); ++p)
      water_alpha[p] = std::max(water_alpha[p], alpha[p]);
  }
  Animated(static_only, 0, &alpha);
  std::vector<bool> water(alpha.size()), still(alpha.size()),
      all(alpha.size(), true);
  int water_pixels = 0, still_pixels = 0;
  for (size_t p = 0; p < alpha.size(); ++p) {
    water[p] = water_alpha[p] > 0.05;
    still[p] = water_alpha[p] < 1e-3 && alpha[p] > 0.9;
    water_pixels += water[p];
    still_pixels += still[p];
  }
  ASSERT_GT(water_pixels, 500);
  ASSERT_GT(still_pixels, 500);

  const Image ours_a = Animated(model, a, nullptr);
  const Image ours_b = Animated(model, b, nullptr);
  const double page_water_change = Mse(page_a, page_b, water);
  const double page_still_change = Mse(page_a, page_b, still);
  const double ours_water_change = Mse(ours_a, ours_b, water);
  const double psnr_a = Psnr(Mse(page_a, ours_a, all));
  const double psnr_b = Psnr(Mse(page_b, ours_b, all));
  const double same_time = Mse(page_b, ours_b, water);
  const double other_time = Mse(page_b, ours_a, water);
  std::printf("page vs es_animate PSNR: frame %d %.2f dB, frame %d %.2f dB\n"
              "water MSE frame %d vs %d: page %.5f, es_animate %.5f; static "
              "region: page %.6f\n"
              "page frame %d against es_animate (water): same time %.5f, "
              "other time %.5f\n",
              a, psnr_a, b, psnr_b, a, b, page_water_change,
              ours_water_change, page_still_change, b, same_time, other_time);
  if (const char* keep = std::getenv("ES_BROWSER_TEST_KEEP")) {
    cv::imwrite(std::string(keep) + "/page.png", page_a);
    cv::imwrite(std::string(keep) + "/es_animate.png", ours_a);
  }

  // Two loop times differ where the water is (as much as es_animate's
  // frames do; measured 0.98 of it) and agree where it is not (measured 0).
  EXPECT_GT(page_water_change, 0.5 * ours_water_change);
  EXPECT_LT(page_still_change, 1e-4);
  // The view from a training camera resembles es_animate's frame for the
  // same camera and time: PSNR over the whole image of 8-bit frames above
  // 30 dB (measured 31.7-32.4 dB; the viewer stores colors in 8 bits and
  // positions in half floats, sorts by its own depth, and blurs splats
  // its own way). In the water the same time is far closer than another
  // time (measured a 50x smaller squared error), so the page plays the
  // right frame, not just a plausible one.
  EXPECT_GT(psnr_a, 30.0);
  EXPECT_GT(psnr_b, 30.0);
  EXPECT_LT(same_time, 0.1 * other_time);
}

// A plain headless screenshot (no puppeteer, no waiting for the player):
// the page used to show only "loading…"; it shows the poster es_export
// drew, at the camera's image size when the window has it. Opened as a
// file, where the player never starts: what a slow machine or a browser
// without WebGL shows.
class PlainScreenshotTest : public TempDirTest {};

TEST_F(PlainScreenshotTest, PageShowsThePosterBeforeThePlayerRuns) {
  if (!std::filesystem::exists(kChromium))
    GTEST_SKIP() << kChromium << " is not installed";
  if (!HaveWebModule("@sparkjsdev/spark/dist/spark.module.js"))
    GTEST_SKIP() << "npm packages not installed (scripts/setup.sh)";
  const LoopModel model = WaterLoopModel();
  // Headless Chromium's windows are at least 500 pixels wide: the camera
  // at 4x its size, 768 x 512, so the window shows the poster at 1:1.
  Camera camera = WaterLoopCamera();
  camera.width *= 4;
  camera.height *= 4;
  camera.fx *= 4;
  camera.fy *= 4;
  camera.cx *= 4;
  camera.cy *= 4;
  WebPlayerOptions options;
  options.page_dir = std::string(ES_SOURCE_DIR) + "/web/player";
  options.modules_dir = WebModulePath("");
  ExportWebPlayer(model, {camera}, options, Path("page"));

  const std::string shot = Path("shot.png");
  const std::string command =
      std::string(kChromium) +
      " --headless=new --no-sandbox --disable-gpu --hide-scrollbars"
      " --user-data-dir=" + Quoted(Path("profile")) +
      " --window-size=" + std::to_string(camera.width) + "," +
      std::to_string(camera.height) + " --screenshot=" + Quoted(shot) +
      " " + Quoted("file://" + Path("page") + "/index.html");
  ASSERT_EQ(RunLogged(command, Path("chromium.txt")), 0)
      << command << "\n" << ReadWholeFile(Path("chromium.txt"));
  const Image page = cv::imread(shot, cv::IMREAD_COLOR);
  const Image poster = cv::imread(Path("page/poster.png"), cv::IMREAD_COLOR);
  ASSERT_EQ(page.size(), poster.size());
  if (const char* keep = std::getenv("ES_BROWSER_TEST_KEEP"))
    cv::imwrite(std::string(keep) + "/plain_screenshot.png", page);
  // Below the info lines (top left), the screenshot is the poster, and
  // the poster is the scene, not a blank page.
  const int top = 48;
  const std::vector<bool> below = [&] {
    std::vector<bool> m(page.rows * page.cols, false);
    for (int p = top * page.cols; p < page.rows * page.cols; ++p) m[p] = true;
    return m;
  }();
  const Image black(page.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  const double psnr = Psnr(Mse(page, poster, below));
  std::printf("plain screenshot vs poster: %.2f dB; poster vs black %.2f dB\n",
              psnr, Psnr(Mse(poster, black, below)));
  EXPECT_GT(psnr, 40.0);
  EXPECT_LT(Psnr(Mse(poster, black, below)), 20.0);
}

}  // namespace
}  // namespace es
