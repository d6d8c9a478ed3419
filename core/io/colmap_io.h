#ifndef EULERSPLAT_CORE_IO_COLMAP_IO_H_
#define EULERSPLAT_CORE_IO_COLMAP_IO_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace es {

// A COLMAP sparse model as stored in sparse/0 (cameras, images, points3D),
// kept close to COLMAP's own records so text and binary read identically.
struct ColmapCamera {
  int id = -1;
  std::string model;           // e.g. "PINHOLE", "SIMPLE_RADIAL", "OPENCV"
  int width = 0, height = 0;
  std::vector<double> params;  // in COLMAP's order for the model
};

struct ColmapImage {
  int id = -1;
  Eigen::Quaterniond q_cw = Eigen::Quaterniond::Identity();  // world->camera
  Eigen::Vector3d t_cw = Eigen::Vector3d::Zero();
  int camera_id = -1;
  std::string name;
  std::vector<Eigen::Vector2d> points2d;
  std::vector<int64_t> point3d_ids;  // -1 where the 2D point has no 3D point
};

struct ColmapPoint3D {
  int64_t id = -1;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix<uint8_t, 3, 1> rgb = Eigen::Matrix<uint8_t, 3, 1>::Zero();
  double error = 0;
  std::vector<std::pair<int, int>> track;  // (image id, point2D index)
};

struct ColmapModel {
  std::map<int, ColmapCamera> cameras;
  std::map<int, ColmapImage> images;
  std::vector<ColmapPoint3D> points;
};

// Reads dir/{cameras,images,points3D}.bin if all three exist, else the .txt
// files. Throws InputError naming the file (and line, for text) on any problem.
ColmapModel ReadColmapModel(const std::string& dir);
// True if dir holds all three .bin files, i.e. ReadColmapModel reads them.
bool HasColmapBinary(const std::string& dir);
ColmapModel ReadColmapText(const std::string& dir);
ColmapModel ReadColmapBinary(const std::string& dir);

// Writes the text format (cameras.txt, images.txt, points3D.txt) into dir,
// creating it if needed.
void WriteColmapText(const ColmapModel& model, const std::string& dir);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_COLMAP_IO_H_
