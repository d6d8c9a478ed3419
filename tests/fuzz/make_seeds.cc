// Writes the fuzzers' seed corpora: small files of every kind the project
// reads, made by the project's own writers (the COLMAP binary model, which
// the project only reads, is encoded here record by record).
//   make_fuzz_seeds OUT_DIR  ->  OUT_DIR/<target>/seed_*

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/io/colmap_io.h"
#include "core/fields/field_io.h"
#include "core/io/ply_io.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "tests/whole_file.h"

namespace es {
namespace {

namespace fs = std::filesystem;

GaussianSet SmallGaussians(int n, int degree) {
  GaussianSet g;
  g.sh_degree = degree;
  g.Resize(n);
  for (size_t i = 0; i < g.means.size(); ++i) g.means[i] = 0.1 * i;
  for (size_t i = 0; i < g.sh.size(); ++i) g.sh[i] = 0.01 * i;
  for (double& s : g.log_scales) s = -3;
  return g;
}

ColmapModel SmallColmapModel() {
  ColmapModel m;
  ColmapCamera pinhole{1, "PINHOLE", 32, 24, {30, 30, 16, 12}};
  ColmapCamera radial{2, "SIMPLE_RADIAL", 32, 24, {30, 16, 12, 0.01}};
  m.cameras[1] = pinhole;
  m.cameras[2] = radial;
  for (int i = 1; i <= 2; ++i) {
    ColmapImage image;
    image.id = i;
    image.camera_id = i;
    image.t_cw = {0.1 * i, 0, 2};
    image.name = "frame_00000" + std::to_string(i) + ".png";
    image.points2d = {{3.5, 4.5}, {10, 11}};
    image.point3d_ids = {7, -1};
    m.images[i] = image;
  }
  ColmapPoint3D point;
  point.id = 7;
  point.xyz = {0.5, -0.5, 1};
  point.rgb << 10, 200, 30;
  point.error = 0.3;
  point.track = {{1, 0}, {2, 0}};
  m.points.push_back(point);
  return m;
}

template <typename T>
void Put(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// COLMAP's binary records (little-endian), as src/colmap/scene/reconstruction
// io writes them.
std::string ColmapBinary(const ColmapModel& m) {
  std::string cameras, images, points;
  Put<uint64_t>(&cameras, m.cameras.size());
  for (const auto& [id, c] : m.cameras) {
    Put<uint32_t>(&cameras, id);
    Put<int32_t>(&cameras, c.model == "PINHOLE" ? 1 : 2);
    Put<uint64_t>(&cameras, c.width);
    Put<uint64_t>(&cameras, c.height);
    for (double p : c.params) Put<double>(&cameras, p);
  }
  Put<uint64_t>(&images, m.images.size());
  for (const auto& [id, im] : m.images) {
    Put<uint32_t>(&images, id);
    for (double q : {im.q_cw.w(), im.q_cw.x(), im.q_cw.y(), im.q_cw.z()})
      Put<double>(&images, q);
    for (int a = 0; a < 3; ++a) Put<double>(&images, im.t_cw[a]);
    Put<uint32_t>(&images, im.camera_id);
    images += im.name;
    images += '\0';
    Put<uint64_t>(&images, im.points2d.size());
    for (size_t p = 0; p < im.points2d.size(); ++p) {
      Put<double>(&images, im.points2d[p].x());
      Put<double>(&images, im.points2d[p].y());
      Put<uint64_t>(&images, im.point3d_ids[p] < 0 ? ~uint64_t{0}
                                                   : im.point3d_ids[p]);
    }
  }
  Put<uint64_t>(&points, m.points.size());
  for (const ColmapPoint3D& p : m.points) {
    Put<uint64_t>(&points, p.id);
    for (int a = 0; a < 3; ++a) Put<double>(&points, p.xyz[a]);
    for (int c = 0; c < 3; ++c) Put<uint8_t>(&points, p.rgb[c]);
    Put<double>(&points, p.error);
    Put<uint64_t>(&points, p.track.size());
    for (const auto& [image, index] : p.track) {
      Put<uint32_t>(&points, image);
      Put<uint32_t>(&points, index);
    }
  }
  return cameras + "\n@@\n" + images + "\n@@\n" + points;
}

// ASCII form of a small PLY, as other 3DGS tools write it, with an extra
// element and a list property before the vertices.
std::string AsciiPly() {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\ncomment seed\nelement junk 2\n"
       "property list uchar float v\nproperty int k\nelement vertex 2\n";
  for (const char* name :
       {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2",
        "opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2",
        "rot_3"})
    s << "property float " << name << "\n";
  s << "end_header\n2 0.5 1.5 7\n0 -3\n";
  for (int n = 0; n < 2; ++n) {
    for (int p = 0; p < 17; ++p) s << 0.25 * (p + n) << ' ';
    s << "\n";
  }
  return s.str();
}

void MakeSeeds(const fs::path& out) {
  const fs::path tmp = out / "tmp";
  fs::create_directories(tmp);
  auto dir = [&](const char* target) {
    fs::create_directories(out / target);
    return out / target;
  };

  const fs::path ply = dir("fuzz_ply");
  for (int degree : {0, 1}) {
    WritePly(SmallGaussians(2, degree), (tmp / "g.ply").string());
    WriteWholeFile(ply / ("seed_binary_sh" + std::to_string(degree)),
             ReadWholeFile(tmp / "g.ply"));
  }
  WriteWholeFile(ply / "seed_ascii", AsciiPly());

  const ColmapModel model = SmallColmapModel();
  WriteColmapText(model, tmp.string());
  WriteWholeFile(dir("fuzz_colmap_text") / "seed_model",
           ReadWholeFile(tmp / "cameras.txt") + "\n@@\n" +
               ReadWholeFile(tmp / "images.txt") + "\n@@\n" +
               ReadWholeFile(tmp / "points3D.txt"));
  WriteWholeFile(dir("fuzz_colmap_binary") / "seed_model", ColmapBinary(model));

  WriteWholeFile(dir("fuzz_split") / "seed_split",
           "# held out\nframe_000001.png\n  frame_000003.png  # comment\n\n"
           "frame_000001.jpg\n");

  MotionFieldOptions mo;
  mo.triplane.resolution = 2;
  mo.triplane.channels = 2;
  mo.mlp_width = 3;
  mo.mlp_depth = 1;
  SaveMotionField(MotionField(mo), (tmp / "m.bin").string());
  WriteWholeFile(dir("fuzz_field") / "seed_motion", ReadWholeFile(tmp / "m.bin"));
  ResidualFieldOptions ro;
  ro.triplane.resolution = 2;
  ro.triplane.channels = 2;
  ro.mlp_width = 3;
  ro.mlp_depth = 1;
  ro.t_frequencies = ro.p_frequencies = 1;
  ro.cycle_length = 3;
  SaveResidualField(ResidualField(ro), (tmp / "r.bin").string());
  WriteWholeFile(dir("fuzz_field") / "seed_residual", ReadWholeFile(tmp / "r.bin"));

  Checkpoint c;
  c.iteration = 5;
  c.gaussians = c.adam.m = c.adam.v = SmallGaussians(2, 0);
  c.adam.step = 5;
  c.sampler.rng = "1 2 3";
  c.sampler.order = {0, 1};
  c.sampler.position = 1;
  c.rng = "4 5 6";
  c.grad_sum = c.grad_count = c.max_radius = {0, 1};
  WriteCheckpoint(c, (tmp / "c.bin").string());
  WriteWholeFile(dir("fuzz_checkpoint") / "seed_static", ReadWholeFile(tmp / "c.bin"));
  JointCheckpoint j;
  j.iteration = 3;
  j.gaussians = j.adam.m = j.adam.v = SmallGaussians(3, 0);
  j.dynamic_index = {0, 2};
  j.start_times = {1, 0};
  j.field_params = j.field_m = j.field_v = {{1, 2}, {3}};
  j.field_boxes = std::vector<double>(6, 0.5);
  j.sampler = c.sampler;
  j.rng = "7";
  WriteJointCheckpoint(j, (tmp / "j.bin").string());
  WriteWholeFile(dir("fuzz_checkpoint") / "seed_joint", ReadWholeFile(tmp / "j.bin"));
  fs::remove_all(tmp);
}

}  // namespace
}  // namespace es

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  es::MakeSeeds(argv[1]);
  return 0;
}
