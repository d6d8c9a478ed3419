// Helpers es_render uses: COLMAP camera conversion, flag parsing, PNG output.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "apps/common/parse_color.h"
#include "core/base/input_error.h"
#include "core/io/pinhole_camera.h"
#include "core/viz/render_png.h"

using ::testing::HasSubstr;

namespace es {
namespace {

TEST(RasterIo, PinholeModelsBecomeCameras) {
  ColmapImage image;
  image.q_cw = Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5);
  image.t_cw = Eigen::Vector3d(1, 2, 3);
  image.name = "a.jpg";
  ColmapCamera pinhole{1, "PINHOLE", 640, 480, {500, 510, 320, 241}};
  const Camera c = PinholeCameraFromColmap(pinhole, image, "dir");
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 480);
  EXPECT_DOUBLE_EQ(c.fy, 510);
  EXPECT_DOUBLE_EQ(c.cy, 241);
  EXPECT_DOUBLE_EQ(c.t_cw.z(), 3);
  EXPECT_EQ(c.image_name, "a.jpg");
  ColmapCamera simple{2, "SIMPLE_PINHOLE", 64, 48, {70, 32, 24}};
  const Camera s = PinholeCameraFromColmap(simple, image, "dir");
  EXPECT_DOUBLE_EQ(s.fx, 70);
  EXPECT_DOUBLE_EQ(s.fy, 70);
  EXPECT_DOUBLE_EQ(s.cx, 32);
}

TEST(RasterIo, DistortedModelsAreRejectedWithTheirName) {
  ColmapCamera radial{3, "SIMPLE_RADIAL", 64, 48, {70, 32, 24, 0.1}};
  try {
    PinholeCameraFromColmap(radial, ColmapImage(), "scene/sparse/0");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("SIMPLE_RADIAL"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("scene/sparse/0"));
  }
}

TEST(RasterIo, ParsesColorsAndRejectsBadOnes) {
  const Eigen::Vector3d c = ParseColor("0.1,1,0.25", "background");
  EXPECT_DOUBLE_EQ(c.x(), 0.1);
  EXPECT_DOUBLE_EQ(c.z(), 0.25);
  for (const char* bad : {"", "1,1", "1,1,1,1", "1,x,1", "1,,1", "1,1,",
                          "1,1,nan", "1 1 1"}) {
    EXPECT_THROW(ParseColor(bad, "background"), InputError) << bad;
  }
}

TEST(RasterIo, WritesRgbAndDepthPngs) {
  RenderResult r;
  r.width = 2;
  r.height = 1;
  r.rgb = {1.2, 0.5, -0.1, 0.0, 0.25, 1.0};
  r.alpha = {0.5, 0.0};
  r.depth = {1.0, 0.0};  // expected depth 2.0 at pixel 0
  const std::string rgb_path = std::string(ES_BINARY_DIR) + "/raster_io.png";
  const std::string depth_path =
      std::string(ES_BINARY_DIR) + "/raster_io_depth.png";
  WriteRgbPng(r, rgb_path);
  WriteDepthPng(r, 1000, depth_path);
  const cv::Mat rgb = cv::imread(rgb_path, cv::IMREAD_UNCHANGED);
  const cv::Mat depth = cv::imread(depth_path, cv::IMREAD_UNCHANGED);
  std::remove(rgb_path.c_str());
  std::remove(depth_path.c_str());
  ASSERT_EQ(rgb.type(), CV_8UC3);
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 128, 255));  // BGR
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 1), cv::Vec3b(255, 64, 0));
  ASSERT_EQ(depth.type(), CV_16UC1);
  EXPECT_EQ(depth.at<uint16_t>(0, 0), 2000);
  EXPECT_EQ(depth.at<uint16_t>(0, 1), 0);
  EXPECT_THROW(WriteRgbPng(r, "/nonexistent_dir/x.png"), InputError);
}

}  // namespace
}  // namespace es
