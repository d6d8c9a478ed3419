#include "core/io/scene.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "core/io/colmap_io.h"
#include "core/base/input_error.h"
#include "core/io/split.h"
#include "tests/expect_error.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 32;
constexpr int kHeight = 24;

std::string FrameName(int f) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%03d.png", f);
  return name;
}

// Frame f's pixel (j, i) in BGR; every frame and pixel differs.
cv::Vec3b FramePixel(int f, int i, int j) {
  return cv::Vec3b(10 * f, 5 * i, 7 * j);
}

// Mask of frame f: left third 0, middle third 128, right third 255.
uint8_t MaskPixel(int f, int i, int j) {
  return j < kWidth / 3 ? 0 : j < 2 * kWidth / 3 ? 128 : 255;
}

class SceneTest : public TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    fs::create_directories(dir_ / "images");
  }

  // A PINHOLE scene of n frames whose image ids run opposite to name order,
  // with masks and two 3D points.
  void WriteScene(int n, bool masks = true) {
    model_ = ColmapModel();
    model_.cameras[2] = {2, "PINHOLE", kWidth, kHeight, {30, 31, 16.5, 11.5}};
    for (int f = 0; f < n; ++f) {
      ColmapImage im;
      im.id = 100 - f;
      im.camera_id = 2;
      im.name = FrameName(f);
      im.q_cw = Eigen::Quaterniond(
          Eigen::AngleAxisd(0.1 * f, Eigen::Vector3d::UnitY()));
      im.t_cw = {0.5 * f, -0.25, 1.0 + f};
      model_.images[im.id] = im;
      cv::Mat image(kHeight, kWidth, CV_8UC3);
      cv::Mat mask(kHeight, kWidth, CV_8UC1);
      for (int i = 0; i < kHeight; ++i)
        for (int j = 0; j < kWidth; ++j) {
          image.at<cv::Vec3b>(i, j) = FramePixel(f, i, j);
          mask.at<uint8_t>(i, j) = MaskPixel(f, i, j);
        }
      ASSERT_TRUE(cv::imwrite((dir_ / "images" / im.name).string(), image));
      if (masks) {
        fs::create_directories(dir_ / "masks");
        ASSERT_TRUE(cv::imwrite((dir_ / "masks" / im.name).string(), mask));
      }
    }
    ColmapPoint3D a, b;
    a.id = 5;
    a.xyz = {1, 2, 3};
    a.rgb << 255, 0, 51;
    b.id = 9;
    b.xyz = {-1, 0.5, 4};
    model_.points = {a, b};
    SaveModel();
  }

  void SaveModel() { WriteColmapText(model_, (dir_ / "sparse/0").string()); }

  ColmapImage& ImageNamed(const std::string& name) {
    for (auto& entry : model_.images)
      if (entry.second.name == name) return entry.second;
    throw std::runtime_error("no image " + name);
  }

  // Loads dir_ and expects an InputError mentioning every one of `parts`.
  void ExpectLoadError(const std::vector<std::string>& parts,
                       const SceneOptions& options = {}) {
    ExpectErrorNaming<InputError>([&] { LoadScene(dir_.string(), options); },
                                  parts);
  }

  ColmapModel model_;
};

TEST_F(SceneTest, LoadsFramesInNameOrderWithTheirCameras) {
  WriteScene(5);
  const Scene scene = LoadScene(dir_.string());
  ASSERT_EQ(scene.frames.size(), 5u);
  for (int f = 0; f < 5; ++f) {
    const Frame& frame = scene.frames[f];
    const ColmapImage& im = ImageNamed(FrameName(f));
    EXPECT_EQ(frame.camera.image_name, FrameName(f));
    EXPECT_EQ(frame.camera.image_id, im.id);
    EXPECT_EQ(frame.camera.width, kWidth);
    EXPECT_EQ(frame.camera.height, kHeight);
    EXPECT_EQ(frame.camera.fx, 30);
    EXPECT_EQ(frame.camera.fy, 31);
    EXPECT_EQ(frame.camera.cx, 16.5);
    EXPECT_EQ(frame.camera.cy, 11.5);
    EXPECT_TRUE(frame.camera.q_cw.coeffs().isApprox(im.q_cw.coeffs()));
    EXPECT_EQ(frame.camera.t_cw, im.t_cw);
    ASSERT_EQ(frame.image.type(), CV_32FC3);
    ASSERT_EQ(frame.image.size(), cv::Size(kWidth, kHeight));
    for (int i = 0; i < kHeight; i += 5)
      for (int j = 0; j < kWidth; j += 3) {
        const cv::Vec3b bgr = FramePixel(f, i, j);
        const cv::Vec3f rgb = frame.image.at<cv::Vec3f>(i, j);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(rgb[c], bgr[2 - c] / 255.0, 1e-6) << i << "," << j;
      }
  }
  ASSERT_EQ(scene.points.size(), 2u);
  EXPECT_EQ(scene.points[1], Eigen::Vector3d(-1, 0.5, 4));
  EXPECT_NEAR(scene.point_colors[0].x(), 1.0, 1e-12);
  EXPECT_NEAR(scene.point_colors[0].z(), 0.2, 1e-12);
}

TEST_F(SceneTest, UnregisteredFramesKeepTheirPlaceInTime) {
  WriteScene(6);
  model_.images.erase(ImageNamed(FrameName(1)).id);
  model_.images.erase(ImageNamed(FrameName(4)).id);
  SaveModel();
  const Scene scene = LoadScene(dir_.string());
  ASSERT_EQ(scene.frames.size(), 4u);
  const int expected_times[] = {0, 2, 3, 5};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(scene.frames[k].camera.image_name,
              FrameName(expected_times[k]));
    EXPECT_EQ(scene.frames[k].time_index, expected_times[k]);
  }
}

TEST_F(SceneTest, LoadsMasksAsWaterProbability) {
  WriteScene(3);
  const Scene scene = LoadScene(dir_.string());
  ASSERT_TRUE(scene.has_masks);
  for (const Frame& frame : scene.frames) {
    ASSERT_EQ(frame.mask.type(), CV_32FC1);
    ASSERT_EQ(frame.mask.size(), cv::Size(kWidth, kHeight));
    EXPECT_EQ(frame.mask.at<float>(3, 0), 0.0f);
    EXPECT_NEAR(frame.mask.at<float>(3, kWidth / 2), 128 / 255.0, 1e-6);
    EXPECT_EQ(frame.mask.at<float>(3, kWidth - 1), 1.0f);
  }
}

TEST_F(SceneTest, NoMasksFolderMeansNoMasks) {
  WriteScene(3, /*masks=*/false);
  const Scene scene = LoadScene(dir_.string());
  EXPECT_FALSE(scene.has_masks);
  for (const Frame& frame : scene.frames) EXPECT_TRUE(frame.mask.empty());
}

TEST_F(SceneTest, AcceptsPngMaskForJpgImage) {
  WriteScene(2);
  cv::Mat image = cv::imread((dir_ / "images" / FrameName(1)).string());
  fs::remove(dir_ / "images" / FrameName(1));
  fs::remove(dir_ / "masks" / FrameName(1));
  ASSERT_TRUE(cv::imwrite((dir_ / "images/late.jpg").string(), image));
  cv::Mat mask(kHeight, kWidth, CV_8UC1, cv::Scalar(255));
  ASSERT_TRUE(cv::imwrite((dir_ / "masks/late.png").string(), mask));
  ImageNamed(FrameName(1)).name = "late.jpg";
  SaveModel();
  const Scene scene = LoadScene(dir_.string());
  ASSERT_EQ(scene.frames.size(), 2u);
  EXPECT_EQ(scene.frames[1].camera.image_name, "late.jpg");
  EXPECT_EQ(scene.frames[1].mask.at<float>(5, 5), 1.0f);
}

TEST_F(SceneTest, ListsEveryMissingImageAndMask) {
  WriteScene(6);
  fs::remove(dir_ / "masks" / FrameName(4));
  fs::remove(dir_ / "masks" / FrameName(0));
  ExpectLoadError({"masks", FrameName(0), FrameName(4)});
  fs::remove(dir_ / "images" / FrameName(1));
  fs::remove(dir_ / "images" / FrameName(5));
  fs::remove_all(dir_ / "masks");
  ExpectLoadError({"images", FrameName(1), FrameName(5)});
}

TEST_F(SceneTest, ImageOrMaskOfWrongSizeIsNamed) {
  WriteScene(3);
  const cv::Mat small(kHeight, kWidth - 2, CV_8UC3, cv::Scalar(1, 2, 3));
  ASSERT_TRUE(cv::imwrite((dir_ / "masks" / FrameName(2)).string(), small));
  ExpectLoadError({(dir_ / "masks" / FrameName(2)).string(), "30x24"});
  ASSERT_TRUE(cv::imwrite((dir_ / "images" / FrameName(1)).string(), small));
  ExpectLoadError(
      {(dir_ / "images" / FrameName(1)).string(), "30x24", "32x24"});
}

TEST_F(SceneTest, UnsupportedCameraModelIsNamed) {
  WriteScene(2);
  model_.cameras[2] = {
      2, "OPENCV_FISHEYE", kWidth, kHeight, {30, 30, 16, 12, 0.1, 0, 0, 0}};
  SaveModel();
  ExpectLoadError({"OPENCV_FISHEYE", "cameras.txt"});
}

// D6: a zero focal length used to fail a CHECK in the rasterizer (exit
// 134) once training started; it is an input error naming cameras.txt.
TEST_F(SceneTest, ZeroOrNonFiniteFocalLengthIsNamed) {
  WriteScene(2);
  model_.cameras[2] = {2, "PINHOLE", kWidth, kHeight, {0, 0, 16, 12}};
  SaveModel();
  ExpectLoadError({"cameras.txt", "camera 2", "focal length"});
  model_.cameras[2] = {2, "SIMPLE_RADIAL", kWidth, kHeight, {-5, 16, 12, 0.1}};
  SaveModel();
  ExpectLoadError({"cameras.txt", "camera 2", "focal length"});
}

// D8: a one-line cameras.txt announcing a 50000 x 50000 distorted camera
// made the loader allocate two 10 GB undistortion maps before it looked at
// a frame; the frames' real size is now checked first.
TEST_F(SceneTest, HugeDistortedCameraIsRejectedBeforeAllocating) {
  WriteScene(2, /*masks=*/false);
  model_.cameras[2] = {2, "SIMPLE_RADIAL", 50000, 50000, {30, 16, 12, 0.1}};
  SaveModel();
  ExpectLoadError({(dir_ / "images" / FrameName(0)).string(), "32x24",
                   "50000x50000"});
}

TEST_F(SceneTest, UndecodableImageOrVideoIsNamed) {
  WriteScene(2, /*masks=*/false);
  std::ofstream((dir_ / "images" / FrameName(1)).string()) << "not a png";
  ExpectLoadError({(dir_ / "images" / FrameName(1)).string(), "decode"});

  // A video that is not one: every frame the model names is reported.
  fs::remove_all(dir_ / "images");
  fs::create_directories(dir_ / "images");
  std::ofstream((dir_ / "images" / "clip.mp4").string()) << "garbage";
  model_ = ColmapModel();
  model_.cameras[1] = {1, "SIMPLE_PINHOLE", kWidth, kHeight, {30, 16, 12}};
  ColmapImage im;
  im.id = 1;
  im.camera_id = 1;
  im.name = "frame_000000.png";
  model_.images[1] = im;
  SaveModel();
  ExpectLoadError({(dir_ / "images" / "clip.mp4").string()});
}

TEST_F(SceneTest, ImageScaleResizesFramesMasksAndIntrinsics) {
  WriteScene(2);
  SceneOptions options;
  options.image_scale = 0.5;
  const Scene scene = LoadScene(dir_.string(), options);
  const Frame& frame = scene.frames[0];
  EXPECT_EQ(frame.camera.width, kWidth / 2);
  EXPECT_EQ(frame.camera.height, kHeight / 2);
  EXPECT_DOUBLE_EQ(frame.camera.fx, 15);
  EXPECT_DOUBLE_EQ(frame.camera.cx, 8.25);
  EXPECT_EQ(frame.image.size(), cv::Size(kWidth / 2, kHeight / 2));
  EXPECT_EQ(frame.mask.size(), cv::Size(kWidth / 2, kHeight / 2));
  // Area averaging of the 2x2 block at the top-left pixel.
  EXPECT_NEAR(frame.image.at<cv::Vec3f>(0, 0)[0], 3.5 / 255, 1e-6);
  EXPECT_EQ(frame.mask.at<float>(0, kWidth / 2 - 1), 1.0f);
}

void ExpectValidSplit(const std::vector<int>& train,
                      const std::vector<int>& test, int n) {
  std::vector<int> all = train;
  all.insert(all.end(), test.begin(), test.end());
  std::sort(all.begin(), all.end());
  ASSERT_EQ(static_cast<int>(all.size()), n);
  for (int i = 0; i < n; ++i) ASSERT_EQ(all[i], i);
  EXPECT_TRUE(std::is_sorted(train.begin(), train.end()));
  EXPECT_TRUE(std::is_sorted(test.begin(), test.end()));
}

// Runs of consecutive indices in a sorted list.
std::vector<std::vector<int>> Runs(const std::vector<int>& sorted) {
  std::vector<std::vector<int>> runs;
  for (size_t i = 0; i < sorted.size(); ++i) {
    if (i == 0 || sorted[i] != sorted[i - 1] + 1) runs.emplace_back();
    runs.back().push_back(sorted[i]);
  }
  return runs;
}

TEST(DefaultSplitTest, ThreeEvenSegmentsAwayFromTheEnds) {
  const FrameSplit split = DefaultSplit(100, 3, 0.1);
  ExpectValidSplit(split.train, split.test, 100);
  ASSERT_EQ(split.test.size(), 10u);
  const auto runs = Runs(split.test);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_GT(runs.front().front(), 0);
  EXPECT_LT(runs.back().back(), 99);
  for (const auto& run : runs) {
    EXPECT_GE(run.size(), 3u);
    EXPECT_LE(run.size(), 4u);
  }
  // Evenly spread: run centres near 25, 50, 75.
  for (int s = 0; s < 3; ++s) {
    const double centre = (runs[s].front() + runs[s].back()) / 2.0;
    EXPECT_NEAR(centre, 25.0 * (s + 1), 3.0) << "segment " << s;
  }
}

TEST(DefaultSplitTest, SmallAndDegenerateCounts) {
  // 20 frames: round(2) raised to one per segment.
  FrameSplit split = DefaultSplit(20, 3, 0.1);
  ExpectValidSplit(split.train, split.test, 20);
  EXPECT_EQ(split.test.size(), 3u);
  EXPECT_EQ(Runs(split.test).size(), 3u);
  EXPECT_EQ(split.train.front(), 0);
  EXPECT_EQ(split.train.back(), 19);
  // Too few frames for three separated segments: fewer, still inside.
  split = DefaultSplit(5, 3, 0.1);
  ExpectValidSplit(split.train, split.test, 5);
  EXPECT_FALSE(split.test.empty());
  EXPECT_EQ(split.train.front(), 0);
  EXPECT_EQ(split.train.back(), 4);
  for (int n : {1, 2, 3}) {
    split = DefaultSplit(n, 3, 0.1);
    ExpectValidSplit(split.train, split.test, n);
    EXPECT_FALSE(split.train.empty()) << n;
  }
  split = DefaultSplit(50, 3, 0.0);
  EXPECT_TRUE(split.test.empty());
  EXPECT_THROW(DefaultSplit(50, 3, 1.0), InputError);
  EXPECT_THROW(DefaultSplit(50, -1, 0.1), InputError);
}

TEST_F(SceneTest, DefaultSplitIsUsedWithoutSplitFile) {
  WriteScene(12);
  const Scene scene = LoadScene(dir_.string());
  const FrameSplit expected = DefaultSplit(12, 3, 0.1);
  EXPECT_EQ(scene.train, expected.train);
  EXPECT_EQ(scene.test, expected.test);
  ExpectValidSplit(scene.train, scene.test, 12);
}

TEST_F(SceneTest, SplitFileOverridesDefault) {
  WriteScene(6);
  std::ofstream(dir_ / "split.txt")
      << "# held-out frames\n\n"
      << FrameName(3) << "\n  " << FrameName(1) << "   # trailing comment\n";
  const Scene scene = LoadScene(dir_.string());
  EXPECT_EQ(scene.test, (std::vector<int>{1, 3}));
  EXPECT_EQ(scene.train, (std::vector<int>{0, 2, 4, 5}));

  std::ofstream(dir_ / "split.txt") << FrameName(2) << "\nframe_999.png\n";
  ExpectLoadError({(dir_ / "split.txt").string() + ":2:", "frame_999.png"});
}

TEST_F(SceneTest, LoadsFramesFromAVideo) {
  const int n = 6;
  cv::VideoWriter writer((dir_ / "images/clip.avi").string(),
                         cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                         cv::Size(kWidth, kHeight));
  ASSERT_TRUE(writer.isOpened());
  for (int f = 0; f < n; ++f)
    writer.write(cv::Mat(kHeight, kWidth, CV_8UC3,
                         cv::Scalar(40 * f, 100, 200 - 30 * f)));
  writer.release();
  model_.cameras[1] = {1, "SIMPLE_PINHOLE", kWidth, kHeight, {30, 16, 12}};
  // Only some frames registered, as when COLMAP drops a few.
  for (int f : {0, 2, 3, 5}) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%06d.png", f);
    ColmapImage im;
    im.id = f + 1;
    im.camera_id = 1;
    im.name = name;
    model_.images[im.id] = im;
  }
  SaveModel();
  const Scene scene = LoadScene(dir_.string());
  ASSERT_EQ(scene.frames.size(), 4u);
  const int expected_frames[] = {0, 2, 3, 5};
  for (int k = 0; k < 4; ++k) {
    const Frame& frame = scene.frames[k];
    const int f = expected_frames[k];
    EXPECT_EQ(frame.image.size(), cv::Size(kWidth, kHeight));
    EXPECT_EQ(frame.camera.fy, 30);
    const cv::Scalar mean = cv::mean(frame.image);  // RGB
    EXPECT_NEAR(mean[0], (200 - 30 * f) / 255.0, 0.03) << "frame " << f;
    EXPECT_NEAR(mean[1], 100 / 255.0, 0.03) << "frame " << f;
    EXPECT_NEAR(mean[2], 40 * f / 255.0, 0.03) << "frame " << f;
    EXPECT_EQ(frame.time_index, f);
  }

  ColmapImage extra;
  extra.id = 50;
  extra.camera_id = 1;
  extra.name = "frame_000009.png";
  model_.images[extra.id] = extra;
  SaveModel();
  ExpectLoadError({"clip.avi", "frame_000009.png"});
}

// Writes a 16-bit image whose red channel (and a 16-bit mask) store each
// pixel's column index j and whose green channel stores its row i, so the
// undistorted value at a pixel tells where it was sampled from.
void WriteCoordinateRamp(const fs::path& dir, const std::string& name) {
  cv::Mat image(kHeight, kWidth, CV_16UC3);
  cv::Mat mask(kHeight, kWidth, CV_16UC1);
  for (int i = 0; i < kHeight; ++i)
    for (int j = 0; j < kWidth; ++j) {
      image.at<cv::Vec3w>(i, j) = cv::Vec3w(0, 2000 * i, 2000 * j);
      mask.at<uint16_t>(i, j) = 2000 * j;
    }
  ASSERT_TRUE(cv::imwrite((dir / "images" / name).string(), image));
  fs::create_directories(dir / "masks");
  ASSERT_TRUE(cv::imwrite((dir / "masks" / name).string(), mask));
}

TEST_F(SceneTest, SimpleRadialIsUndistortedToPinhole) {
  const double f = 30, cx = 16.5, cy = 11.5;
  WriteCoordinateRamp(dir_, "a.png");
  ColmapImage im;
  im.id = 1;
  im.camera_id = 1;
  im.name = "a.png";
  model_.images[1] = im;
  for (double k : {0.0, 0.15}) {
    model_.cameras[1] = {1, "SIMPLE_RADIAL", kWidth, kHeight, {f, cx, cy, k}};
    SaveModel();
    const Scene scene = LoadScene(dir_.string());
    const Frame& frame = scene.frames[0];
    EXPECT_EQ(frame.camera.fx, f);
    EXPECT_EQ(frame.camera.fy, f);
    EXPECT_EQ(frame.camera.cx, cx);
    EXPECT_EQ(frame.camera.cy, cy);
    int checked = 0;
    for (int i = 0; i < kHeight; ++i)
      for (int j = 0; j < kWidth; ++j) {
        // Where COLMAP's SIMPLE_RADIAL model puts the ray of pixel (j, i).
        const double x = (j + 0.5 - cx) / f, y = (i + 0.5 - cy) / f;
        const double radial = 1 + k * (x * x + y * y);
        const double u = f * x * radial + cx, v = f * y * radial + cy;
        if (u < 0.5 || u > kWidth - 0.5 || v < 0.5 || v > kHeight - 0.5)
          continue;  // sampled outside the source image
        const cv::Vec3f rgb = frame.image.at<cv::Vec3f>(i, j);
        // OpenCV's remap interpolates with 1/32-pixel weights.
        EXPECT_NEAR(rgb[0] * 65535 / 2000 + 0.5, u, 0.02) << i << "," << j;
        EXPECT_NEAR(rgb[1] * 65535 / 2000 + 0.5, v, 0.02) << i << "," << j;
        EXPECT_NEAR(frame.mask.at<float>(i, j) * 65535 / 2000 + 0.5, u, 0.02);
        if (k == 0) {
          EXPECT_EQ(rgb[0], 2000 * j / 65535.0f);
        }
        ++checked;
      }
    EXPECT_GT(checked, kWidth * kHeight / 2) << "k = " << k;
  }
}

}  // namespace
}  // namespace es
