#include "synth/writer.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/colmap_io.h"
#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

void MakeDir(const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir))
    throw InputError(dir.string() + ": cannot create directory");
}

void WriteImage(const fs::path& path, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), image);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path.string() + ": cannot write image");
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw InputError(path.string() + ": cannot write");
}

std::string Stem(const std::string& name) {
  return fs::path(name).stem().string();
}

std::string Vec(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(10);
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

}  // namespace

std::string SynthSettingsJson(const SynthScene& scene) {
  const SynthSettings& s = scene.settings;
  const std::vector<double>& cov = scene.coverage;
  const double mean_coverage =
      std::accumulate(cov.begin(), cov.end(), 0.0) / cov.size();
  const Eigen::Vector3i r = scene.velocity.resolution;
  std::ostringstream j;
  j.precision(10);
  j << "{\n"
    << "  \"generator\": \"es_synth\",\n"
    << "  \"preset\": \"" << s.preset << "\",\n"
    << "  \"frames\": " << s.frames << ",\n"
    << "  \"width\": " << s.width << ",\n"
    << "  \"height\": " << s.height << ",\n"
    << "  \"seed\": " << s.seed << ",\n"
    << "  \"water_seed\": " << s.water_seed << ",\n"
    << "  \"stochasticity\": " << s.stochasticity << ",\n"
    << "  \"detail\": " << s.detail << ",\n"
    << "  \"substeps\": " << s.substeps << ",\n"
    << "  \"integrator\": \"RK4\",\n"
    << "  \"warmup_frames\": " << scene.preset.warmup_frames << ",\n"
    << "  \"num_particles\": " << scene.preset.water.num_particles << ",\n"
    << "  \"num_scenery_gaussians\": " << scene.scenery.size() << ",\n"
    << "  \"num_points3d\": " << scene.sparse.points.size() << ",\n"
    << "  \"point_noise\": " << s.point_noise << ",\n"
    << "  \"pixel_noise\": " << s.pixel_noise << ",\n"
    << "  \"test_segments\": " << s.test_segments << ",\n"
    << "  \"test_fraction\": " << s.test_fraction << ",\n"
    << "  \"world_up\": [0, 1, 0],\n"
    << "  \"velocity_units\": \"world units per frame\",\n"
    << "  \"velocity_grid\": {\"file\": \"velocity_grid.bin\", "
    << "\"resolution\": [" << r.x() << ", " << r.y() << ", " << r.z()
    << "], \"box_min\": " << Vec(scene.velocity.box.min())
    << ", \"box_max\": " << Vec(scene.velocity.box.max()) << "},\n"
    << "  \"depth\": {\"files\": \"depth/<frame>.tiff\", \"format\": "
    << "\"float32 camera z, 0 where alpha <= " << kDepthMinAlpha << "\"},\n"
    << "  \"mask_threshold\": " << kWaterMaskThreshold << ",\n"
    << "  \"water_coverage\": {\"mean\": " << mean_coverage
    << ", \"min\": " << *std::min_element(cov.begin(), cov.end())
    << ", \"max\": " << *std::max_element(cov.begin(), cov.end()) << "}\n"
    << "}\n";
  return j.str();
}

void WriteSynthScene(const SynthScene& scene, const std::string& dir) {
  const fs::path root(dir);
  for (const char* sub : {"images", "masks", "sparse/0", "gt/depth"})
    MakeDir(root / sub);
  for (size_t f = 0; f < scene.cameras.size(); ++f) {
    const std::string& name = scene.cameras[f].image_name;
    cv::Mat bgr;
    cv::cvtColor(scene.images[f], bgr, cv::COLOR_RGB2BGR);
    WriteImage(root / "images" / name, bgr);
    WriteImage(root / "masks" / name, scene.masks[f]);
    WriteImage(root / "gt" / "depth" / (Stem(name) + ".tiff"),
               scene.depths[f]);
  }
  WriteColmapText(scene.sparse, (root / "sparse" / "0").string());

  std::string split = "# held-out test frames (es_synth)\n";
  for (int f : scene.split.test) split += scene.cameras[f].image_name + "\n";
  WriteText(root / "split.txt", split);

  WriteVelocityGrid(scene.velocity,
                    (root / "gt" / "velocity_grid.bin").string());
  WriteText(root / "gt" / "settings.json", SynthSettingsJson(scene));
}

}  // namespace es
