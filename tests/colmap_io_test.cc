#include "core/io/colmap_io.h"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "tests/expect_error.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

namespace fs = std::filesystem;

class ColmapIoTest : public TempDirTest {};

// Two cameras (one distorted), three images with 2D points, five 3D points
// whose tracks agree with the images' 2D points. Values are chosen so that
// COLMAP's own quaternion normalization leaves them unchanged.
ColmapModel SmallModel() {
  ColmapModel m;
  m.cameras[1] = {1, "PINHOLE", 32, 24, {30.5, 31.25, 16.1, 11.9}};
  m.cameras[3] = {3, "SIMPLE_RADIAL", 40, 30, {35.2, 20.3, 14.7, -0.0513}};
  const Eigen::Quaterniond quats[3] = {
      {1, 0, 0, 0}, {0.5, 0.5, 0.5, 0.5}, {0, 0, 1, 0}};
  const int image_ids[3] = {1, 2, 7};
  const int camera_ids[3] = {1, 3, 1};
  for (int i = 0; i < 3; ++i) {
    ColmapImage im;
    im.id = image_ids[i];
    im.q_cw = quats[i];
    im.t_cw = {0.1 * (i + 1), -0.37 * i, 2.0 + 1e-9 * i};
    im.camera_id = camera_ids[i];
    im.name = "frame_00" + std::to_string(i) + ".png";
    for (int p = 0; p < 4; ++p) {
      im.points2d.emplace_back(1.25 + p + 3.3 * i, 7.1 - 0.7 * p);
      im.point3d_ids.push_back(-1);
    }
    m.images[im.id] = im;
  }
  for (int p = 0; p < 5; ++p) {
    ColmapPoint3D point;
    point.id = 10 + 3 * p;
    point.xyz = {0.1 * p - 0.2, 1.0 / 3.0 + p, 5.5e-3 * p};
    point.rgb << 10 * p, 255 - p, 128;
    point.error = 0.123456789 * p;
    // Point p is seen in image i at 2D index p % 4 for i <= p % 3.
    for (int i = 0; i <= p % 3; ++i) {
      const int index = p % 4;
      ColmapImage& im = m.images[image_ids[i]];
      if (im.point3d_ids[index] != -1) continue;
      im.point3d_ids[index] = point.id;
      point.track.emplace_back(im.id, index);
    }
    m.points.push_back(point);
  }
  return m;
}

void ExpectSameModel(const ColmapModel& a, const ColmapModel& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, ca] : a.cameras) {
    ASSERT_EQ(b.cameras.count(id), 1u) << "camera " << id;
    const ColmapCamera& cb = b.cameras.at(id);
    EXPECT_EQ(ca.id, cb.id);
    EXPECT_EQ(ca.model, cb.model);
    EXPECT_EQ(ca.width, cb.width);
    EXPECT_EQ(ca.height, cb.height);
    EXPECT_EQ(ca.params, cb.params);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, ia] : a.images) {
    ASSERT_EQ(b.images.count(id), 1u) << "image " << id;
    const ColmapImage& ib = b.images.at(id);
    EXPECT_EQ(ia.id, ib.id);
    EXPECT_EQ(ia.q_cw.coeffs(), ib.q_cw.coeffs()) << "image " << id;
    EXPECT_EQ(ia.t_cw, ib.t_cw) << "image " << id;
    EXPECT_EQ(ia.camera_id, ib.camera_id);
    EXPECT_EQ(ia.name, ib.name);
    EXPECT_EQ(ia.points2d, ib.points2d);
    EXPECT_EQ(ia.point3d_ids, ib.point3d_ids);
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].id, b.points[i].id);
    EXPECT_EQ(a.points[i].xyz, b.points[i].xyz);
    EXPECT_EQ(a.points[i].rgb, b.points[i].rgb);
    EXPECT_EQ(a.points[i].error, b.points[i].error);
    EXPECT_EQ(a.points[i].track, b.points[i].track);
  }
}

TEST_F(ColmapIoTest, TextRoundTripIsExact) {
  const ColmapModel model = SmallModel();
  WriteColmapText(model, (dir_ / "txt").string());
  ExpectSameModel(ReadColmapText((dir_ / "txt").string()), model);
  ExpectSameModel(ReadColmapModel((dir_ / "txt").string()), model);
}

TEST_F(ColmapIoTest, BinaryFromColmapReadsLikeText) {
  if (std::system("command -v colmap > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "colmap is not on PATH; cannot make a reference .bin";
  const ColmapModel model = SmallModel();
  const fs::path txt = dir_ / "txt", bin = dir_ / "bin";
  WriteColmapText(model, txt.string());
  fs::create_directories(bin);
  const std::string command = "colmap model_converter --input_path '" +
                              txt.string() + "' --output_path '" +
                              bin.string() +
                              "' --output_type BIN > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_TRUE(fs::exists(bin / "points3D.bin"));
  const ColmapModel from_bin = ReadColmapBinary(bin.string());
  ExpectSameModel(from_bin, ReadColmapText(txt.string()));
  ExpectSameModel(from_bin, model);
  ExpectSameModel(ReadColmapModel(bin.string()), model);
}

// Hand-made binary files, so binary errors are tested without colmap.
class BinaryWriter {
 public:
  template <typename T>
  BinaryWriter& Put(T v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
    return *this;
  }
  void Save(const fs::path& path, size_t drop_last = 0) const {
    std::ofstream(path, std::ios::binary)
        << bytes_.substr(0, bytes_.size() - drop_last);
  }

 private:
  std::string bytes_;
};

// cameras.bin with one PINHOLE (model id 1) camera, or another model id.
BinaryWriter OneCameraBin(int32_t model_id = 1) {
  BinaryWriter w;
  w.Put<uint64_t>(1).Put<uint32_t>(4).Put<int32_t>(model_id);
  w.Put<uint64_t>(64).Put<uint64_t>(48);
  for (double p : {50.0, 51.0, 32.0, 24.0}) w.Put(p);
  return w;
}

void WriteEmptyBins(const fs::path& dir) {
  BinaryWriter empty;
  empty.Put<uint64_t>(0);
  empty.Save(dir / "images.bin");
  empty.Save(dir / "points3D.bin");
}

TEST_F(ColmapIoTest, PrefersBinaryWhenAllThreeExist) {
  WriteColmapText(SmallModel(), dir_.string());
  OneCameraBin().Save(dir_ / "cameras.bin");
  WriteEmptyBins(dir_);
  const ColmapModel m = ReadColmapModel(dir_.string());
  ASSERT_EQ(m.cameras.size(), 1u);
  const ColmapCamera& c = m.cameras.at(4);
  EXPECT_EQ(c.model, "PINHOLE");
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.height, 48);
  EXPECT_EQ(c.params, (std::vector<double>{50, 51, 32, 24}));
  EXPECT_TRUE(m.images.empty());

  fs::remove(dir_ / "points3D.bin");  // incomplete binary model: use text
  EXPECT_EQ(ReadColmapModel(dir_.string()).cameras.size(), 2u);
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

TEST_F(ColmapIoTest, MissingFileIsNamed) {
  WriteColmapText(SmallModel(), dir_.string());
  fs::remove(dir_ / "images.txt");
  const std::string d = dir_.string();
  ExpectErrorNaming<InputError>([&] { ReadColmapModel(d); },
                                {(dir_ / "images.txt").string()});
  ExpectErrorNaming<InputError>([&] { ReadColmapBinary(d); },
                                {(dir_ / "cameras.bin").string()});
}

TEST_F(ColmapIoTest, BadTextLinesNameFileAndLine) {
  WriteColmapText(SmallModel(), dir_.string());
  const std::string d = dir_.string();
  const auto expect_refused = [&d](const std::vector<std::string>& parts) {
    ExpectErrorNaming<InputError>([&d] { ReadColmapText(d); }, parts);
  };
  const std::string cameras = (dir_ / "cameras.txt").string();
  WriteText(cameras, "# comment\n\n1 PINHOLE 32 24 30 30 16\n");
  expect_refused({cameras + ":3:", "fields"});
  WriteText(cameras, "# comment\n1 FISHEYE_X 32 24 30 30 16 12\n");
  expect_refused({cameras + ":2:", "FISHEYE_X"});
  WriteText(cameras, "1 PINHOLE 32 24 30 inf 16 12\n");
  expect_refused({cameras + ":1:", "inf"});

  WriteColmapText(SmallModel(), d);
  const std::string images = (dir_ / "images.txt").string();
  WriteText(images, "# c\n1 1 0 0 0 0 nan 0 1 a.png\n\n");
  expect_refused({images + ":2:", "nan"});
  WriteText(images, "1 1 0 0 0 0 0 0 1 a.png\n1.0 2.0\n");
  expect_refused({images + ":2:"});
  WriteText(images, "1 1 0 0 0 0 0 0 9 a.png\n\n");
  expect_refused({images + ":1:", "camera id"});

  WriteColmapText(SmallModel(), d);
  const std::string points = (dir_ / "points3D.txt").string();
  WriteText(points, "1 0 0 0 1 2 3 0.5 1\n");
  expect_refused({points + ":1:"});
}

TEST_F(ColmapIoTest, BadBinaryNamesFile) {
  WriteEmptyBins(dir_);
  const std::string d = dir_.string();
  const auto expect_refused = [&d](const std::vector<std::string>& parts) {
    ExpectErrorNaming<InputError>([&d] { ReadColmapBinary(d); }, parts);
  };
  const std::string cameras = (dir_ / "cameras.bin").string();
  OneCameraBin().Save(cameras);
  EXPECT_EQ(ReadColmapBinary(d).cameras.size(), 1u);
  OneCameraBin().Save(cameras, 3);
  expect_refused({cameras, "truncated"});
  OneCameraBin(42).Save(cameras);
  expect_refused({cameras, "model id 42"});

  // An image whose name string is cut off before its terminating zero.
  OneCameraBin().Save(cameras);
  BinaryWriter images;
  images.Put<uint64_t>(1).Put<uint32_t>(1);
  for (int i = 0; i < 7; ++i) images.Put(i == 0 ? 1.0 : 0.0);
  images.Put<uint32_t>(4).Put('a').Put('b');
  images.Save(dir_ / "images.bin");
  expect_refused({(dir_ / "images.bin").string(), "truncated"});
}

}  // namespace
}  // namespace es
