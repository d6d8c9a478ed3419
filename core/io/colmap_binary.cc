// COLMAP's binary model format (cameras.bin, images.bin, points3D.bin), all
// little-endian: uint64 record counts, uint32 camera/image ids, int32 camera
// model ids, uint64 point ids (max value = no 3D point), double values.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "core/io/colmap_camera_models.h"
#include "core/io/colmap_io.h"
#include "core/io/colmap_points.h"
#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kInvalidPoint3dId = std::numeric_limits<uint64_t>::max();

// Reads little-endian values from a whole file held in memory; errors name
// the file and the byte offset.
class BinaryReader {
 public:
  explicit BinaryReader(const fs::path& path) : path_(path.string()) {
    std::ifstream file(path, std::ios::binary);
    if (!fs::is_regular_file(path) || !file)
      throw InputError(path_ + ": cannot open file");
    file.seekg(0, std::ios::end);
    data_.resize(static_cast<size_t>(file.tellg()));
    file.seekg(0);
    if (!file.read(data_.data(), data_.size()))
      throw InputError(path_ + ": read error");
  }

  template <typename T>
  T Read() {
    static_assert(std::is_arithmetic<T>::value, "plain values only");
    if (data_.size() - pos_ < sizeof(T))
      Fail("truncated file (" + std::to_string(data_.size()) + " bytes)");
    T value;
    std::memcpy(&value, data_.data() + pos_, sizeof(T));  // host is LE
    pos_ += sizeof(T);
    return value;
  }

  double Double() {
    const double v = Read<double>();
    if (!std::isfinite(v)) Fail("non-finite number");
    return v;
  }

  // An id, count or size stored as the unsigned type `Stored`, as an int.
  template <typename Stored>
  int Int(const char* what) {
    const uint64_t v = Read<Stored>();
    if (v > static_cast<uint64_t>(std::numeric_limits<int>::max()))
      Fail(std::string(what) + " out of range");
    return static_cast<int>(v);
  }

  // N finite doubles, in file order.
  template <int N>
  Eigen::Matrix<double, N, 1> Doubles() {
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = Double();
    return v;
  }

  std::string String() {
    const auto end = std::find(data_.begin() + pos_, data_.end(), '\0');
    if (end == data_.end()) Fail("truncated file (unterminated string)");
    std::string s(data_.begin() + pos_, end);
    pos_ = (end - data_.begin()) + 1;
    return s;
  }

  void ExpectEnd() const {
    if (pos_ != data_.size()) Fail("unexpected data after the last record");
  }

  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(path_ + ": at byte " + std::to_string(pos_) + ": " +
                     message);
  }

 private:
  std::string path_;
  std::vector<char> data_;
  size_t pos_ = 0;
};

// Each file is a record count, the records and nothing after them.
template <typename ReadRecord>
void ReadRecords(const fs::path& path, ReadRecord read_record) {
  BinaryReader reader(path);
  const uint64_t count = reader.Read<uint64_t>();
  for (uint64_t i = 0; i < count; ++i) read_record(reader);
  reader.ExpectEnd();
}

// Adds `record` under its id, which must be new.
template <typename Record>
void AddRecord(const Record& record, const char* what,
               const BinaryReader& reader, std::map<int, Record>* records) {
  if (!records->emplace(record.id, record).second)
    reader.Fail(std::string("duplicate ") + what + " id " +
                std::to_string(record.id));
}

void ReadCameras(const fs::path& path, ColmapModel* model) {
  ReadRecords(path, [model](BinaryReader& reader) {
    ColmapCamera camera;
    camera.id = reader.Int<uint32_t>("camera id");
    const int model_id = reader.Read<int32_t>();
    const ColmapCameraModelInfo* info = FindColmapCameraModel(model_id);
    if (info == nullptr)
      reader.Fail("unknown camera model id " + std::to_string(model_id));
    camera.model = info->name;
    camera.width = reader.Int<uint64_t>("width");
    camera.height = reader.Int<uint64_t>("height");
    if (camera.width <= 0 || camera.height <= 0)
      reader.Fail("image size must be positive");
    for (int p = 0; p < info->num_params; ++p)
      camera.params.push_back(reader.Double());
    AddRecord(camera, "camera", reader, &model->cameras);
  });
}

void ReadImages(const fs::path& path, ColmapModel* model) {
  ReadRecords(path, [model](BinaryReader& reader) {
    ColmapImage image;
    image.id = reader.Int<uint32_t>("image id");
    const Eigen::Vector4d q = reader.Doubles<4>();  // w, x, y, z
    image.q_cw = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    image.t_cw = reader.Doubles<3>();
    image.camera_id = reader.Int<uint32_t>("camera id");
    if (model->cameras.count(image.camera_id) == 0)
      reader.Fail("unknown camera id " + std::to_string(image.camera_id));
    image.name = reader.String();
    const uint64_t num_points = reader.Read<uint64_t>();
    for (uint64_t p = 0; p < num_points; ++p) {
      image.points2d.push_back(reader.Doubles<2>());
      const uint64_t id = reader.Read<uint64_t>();
      image.point3d_ids.push_back(
          id == kInvalidPoint3dId ? -1 : static_cast<int64_t>(id));
    }
    AddRecord(image, "image", reader, &model->images);
  });
}

void ReadPoints(const fs::path& path, ColmapModel* model) {
  ReadRecords(path, [model](BinaryReader& reader) {
    ColmapPoint3D point;
    point.id = static_cast<int64_t>(reader.Read<uint64_t>());
    point.xyz = reader.Doubles<3>();
    for (int c = 0; c < 3; ++c) point.rgb[c] = reader.Read<uint8_t>();
    point.error = reader.Double();
    const uint64_t track_length = reader.Read<uint64_t>();
    for (uint64_t t = 0; t < track_length; ++t) {
      const int image_id = reader.Int<uint32_t>("image id");
      point.track.emplace_back(image_id, reader.Int<uint32_t>("index"));
    }
    model->points.push_back(std::move(point));
  });
  SortPointsById(path, &model->points);
}

}  // namespace

ColmapModel ReadColmapBinary(const std::string& dir) {
  ColmapModel model;
  ReadCameras(fs::path(dir) / "cameras.bin", &model);
  ReadImages(fs::path(dir) / "images.bin", &model);
  ReadPoints(fs::path(dir) / "points3D.bin", &model);
  return model;
}

}  // namespace es
