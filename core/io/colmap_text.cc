// COLMAP's text model format (cameras.txt, images.txt, points3D.txt).

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/colmap_camera_models.h"
#include "core/io/colmap_io.h"
#include "core/io/colmap_points.h"
#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

// Reads a text file line by line and builds errors that name the file and
// the current line.
class LineReader {
 public:
  explicit LineReader(const fs::path& path) : path_(path.string()) {
    file_.open(path);
    if (!fs::is_regular_file(path) || !file_)
      throw InputError(path_ + ": cannot open file");
  }

  // Next line split into whitespace-separated tokens; false at end of file.
  bool Next(std::vector<std::string>* tokens) {
    std::string line;
    if (!std::getline(file_, line)) return false;
    ++line_number_;
    tokens->clear();
    std::istringstream stream(line);
    std::string token;
    while (stream >> token) tokens->push_back(token);
    return true;
  }

  // Next line that is neither empty nor a comment.
  bool NextRecord(std::vector<std::string>* tokens) {
    while (Next(tokens))
      if (!tokens->empty() && (*tokens)[0][0] != '#') return true;
    return false;
  }

  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(path_ + ":" + std::to_string(line_number_) + ": " +
                     message);
  }

  double Double(const std::string& token) const {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(v))
      Fail("'" + token + "' is not a finite number");
    return v;
  }

  int64_t Int(const std::string& token) const {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0' || errno == ERANGE)
      Fail("'" + token + "' is not an integer");
    return v;
  }

  int Int32(const std::string& token) const {
    const int64_t v = Int(token);
    if (v < std::numeric_limits<int>::min() ||
        v > std::numeric_limits<int>::max())
      Fail("'" + token + "' is out of range");
    return static_cast<int>(v);
  }

  void ExpectCount(const std::vector<std::string>& tokens, size_t count,
                   const std::string& what) const {
    if (tokens.size() != count)
      Fail("expected " + std::to_string(count) + " fields (" + what +
           "), found " + std::to_string(tokens.size()));
  }

 private:
  std::string path_;
  std::ifstream file_;
  int line_number_ = 0;
};

void ReadCameras(const fs::path& path, ColmapModel* model) {
  LineReader reader(path);
  std::vector<std::string> t;
  while (reader.NextRecord(&t)) {
    if (t.size() < 4)
      reader.Fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    const ColmapCameraModelInfo* info = FindColmapCameraModel(t[1]);
    if (info == nullptr) reader.Fail("unknown camera model '" + t[1] + "'");
    reader.ExpectCount(t, 4 + info->num_params,
                       "CAMERA_ID MODEL WIDTH HEIGHT and " +
                           std::to_string(info->num_params) + " " + t[1] +
                           " parameters");
    ColmapCamera camera;
    camera.id = reader.Int32(t[0]);
    camera.model = info->name;
    camera.width = reader.Int32(t[2]);
    camera.height = reader.Int32(t[3]);
    if (camera.width <= 0 || camera.height <= 0)
      reader.Fail("image size must be positive");
    for (int i = 0; i < info->num_params; ++i)
      camera.params.push_back(reader.Double(t[4 + i]));
    if (!model->cameras.emplace(camera.id, camera).second)
      reader.Fail("duplicate camera id " + t[0]);
  }
}

void ReadImages(const fs::path& path, ColmapModel* model) {
  LineReader reader(path);
  std::vector<std::string> t;
  while (reader.NextRecord(&t)) {
    reader.ExpectCount(t, 10, "IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    ColmapImage image;
    image.id = reader.Int32(t[0]);
    image.q_cw = Eigen::Quaterniond(reader.Double(t[1]), reader.Double(t[2]),
                                    reader.Double(t[3]), reader.Double(t[4]));
    image.t_cw = {reader.Double(t[5]), reader.Double(t[6]),
                  reader.Double(t[7])};
    image.camera_id = reader.Int32(t[8]);
    image.name = t[9];
    if (model->cameras.count(image.camera_id) == 0)
      reader.Fail("unknown camera id " + t[8]);
    // The 2D points line always follows, possibly empty (COLMAP's rule).
    if (reader.Next(&t)) {
      if (t.size() % 3 != 0)
        reader.Fail("expected POINTS2D[] as (X, Y, POINT3D_ID) triples");
      for (size_t i = 0; i < t.size(); i += 3) {
        image.points2d.emplace_back(reader.Double(t[i]),
                                    reader.Double(t[i + 1]));
        image.point3d_ids.push_back(reader.Int(t[i + 2]));
      }
    }
    if (!model->images.emplace(image.id, image).second)
      reader.Fail("duplicate image id " + std::to_string(image.id));
  }
}

void ReadPoints(const fs::path& path, ColmapModel* model) {
  LineReader reader(path);
  std::vector<std::string> t;
  while (reader.NextRecord(&t)) {
    if (t.size() < 8 || (t.size() - 8) % 2 != 0)
      reader.Fail(
          "expected POINT3D_ID X Y Z R G B ERROR TRACK[] as (IMAGE_ID, "
          "POINT2D_IDX) pairs");
    ColmapPoint3D point;
    point.id = reader.Int(t[0]);
    point.xyz = {reader.Double(t[1]), reader.Double(t[2]), reader.Double(t[3])};
    for (int c = 0; c < 3; ++c) {
      const int64_t v = reader.Int(t[4 + c]);
      if (v < 0 || v > 255) reader.Fail("color '" + t[4 + c] + "' not 0-255");
      point.rgb[c] = static_cast<uint8_t>(v);
    }
    point.error = reader.Double(t[7]);
    for (size_t i = 8; i < t.size(); i += 2)
      point.track.emplace_back(reader.Int32(t[i]), reader.Int32(t[i + 1]));
    model->points.push_back(std::move(point));
  }
  SortPointsById(path, &model->points);
}

// Writes `path` through `write(std::ostream&)`; throws InputError naming
// the file where it cannot be written.
template <typename Write>
void WriteModelFile(const fs::path& path, Write write) {
  std::ofstream file(path);
  if (!file) throw InputError(path.string() + ": cannot write file");
  file.precision(17);  // enough digits for doubles to round-trip
  write(file);
  file.close();
  if (!file) throw InputError(path.string() + ": write failed");
}

}  // namespace

ColmapModel ReadColmapText(const std::string& dir) {
  ColmapModel model;
  ReadCameras(fs::path(dir) / "cameras.txt", &model);
  ReadImages(fs::path(dir) / "images.txt", &model);
  ReadPoints(fs::path(dir) / "points3D.txt", &model);
  return model;
}

void WriteColmapText(const ColmapModel& model, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create directory: " + ec.message());
  const fs::path root(dir);

  WriteModelFile(root / "cameras.txt", [&model](std::ostream& cameras) {
    cameras << "# Camera list with one line of data per camera:\n"
            << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
    for (const auto& [id, camera] : model.cameras) {
      cameras << id << ' ' << camera.model << ' ' << camera.width << ' '
              << camera.height;
      for (double p : camera.params) cameras << ' ' << p;
      cameras << '\n';
    }
  });

  WriteModelFile(root / "images.txt", [&model](std::ostream& images) {
    images << "# Image list with two lines of data per image:\n"
           << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
           << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
    for (const auto& [id, image] : model.images) {
      const Eigen::Quaterniond& q = image.q_cw;
      images << id << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' '
             << q.z() << ' ' << image.t_cw.x() << ' ' << image.t_cw.y() << ' '
             << image.t_cw.z() << ' ' << image.camera_id << ' ' << image.name
             << '\n';
      for (size_t i = 0; i < image.points2d.size(); ++i) {
        if (i > 0) images << ' ';
        images << image.points2d[i].x() << ' ' << image.points2d[i].y() << ' '
               << image.point3d_ids[i];
      }
      images << '\n';
    }
  });

  WriteModelFile(root / "points3D.txt", [&model](std::ostream& points) {
    points << "# 3D point list with one line of data per point:\n"
           << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, "
              "TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
    for (const ColmapPoint3D& p : model.points) {
      points << p.id << ' ' << p.xyz.x() << ' ' << p.xyz.y() << ' ' << p.xyz.z()
             << ' ' << int{p.rgb[0]} << ' ' << int{p.rgb[1]} << ' '
             << int{p.rgb[2]} << ' ' << p.error;
      for (const auto& [image_id, point2d_idx] : p.track)
        points << ' ' << image_id << ' ' << point2d_idx;
      points << '\n';
    }
  });
}

}  // namespace es
