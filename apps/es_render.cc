// Renders a 3DGS PLY from every registered image of a COLMAP model.

#include <cstdio>
#include <filesystem>
#include <string>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/parse_color.h"
#include "core/io/colmap_io.h"
#include "core/base/input_error.h"
#include "core/io/output_dir.h"
#include "core/io/pinhole_camera.h"
#include "core/io/ply_io.h"
#include "core/render/rasterizer.h"
#include "core/viz/render_png.h"

constexpr char kUsage[] =
    "Renders every image of a COLMAP model from a 3DGS PLY.\n"
    "  es_render --ply FILE --sparse DIR --out_dir DIR "
    "[--background r,g,b] [--depth]\n"
    "Writes <out_dir>/<image name>.png (8-bit RGB) and, with --depth, "
    "<name>_depth.png (16-bit, expected depth * --depth_scale).";

DEFINE_string(ply, "", "3DGS PLY file to render (standard layout).");
DEFINE_string(sparse, "",
              "COLMAP model directory (cameras, images, points3D; .bin or "
              ".txt). Cameras must be PINHOLE or SIMPLE_PINHOLE.");
DEFINE_string(out_dir, "", "Output directory, created if needed.");
DEFINE_string(background, "0,0,0", "Background color r,g,b in [0, 1].");
DEFINE_bool(depth, false,
            "Also write <name>_depth.png: 16-bit expected depth "
            "(depth / alpha) times --depth_scale, 0 where alpha <= 1e-3.");
DEFINE_double(depth_scale, 1000.0,
              "Depth PNG value per scene unit (1000: millimetres if the "
              "model is in metres); values clamp at 65535.");

namespace {

int Run() {
  if (FLAGS_ply.empty() || FLAGS_sparse.empty() || FLAGS_out_dir.empty()) {
    throw es::InputError("--ply, --sparse and --out_dir are required");
  }
  if (!(FLAGS_depth_scale > 0)) {
    throw es::InputError("--depth_scale must be positive");
  }
  const Eigen::Vector3d background =
      es::ParseColor(FLAGS_background, "background");
  es::PrepareOutputDirectory(FLAGS_out_dir, "out_dir");
  const es::GaussianSet gaussians = es::ReadPly(FLAGS_ply);
  const es::ColmapModel model = es::ReadColmapModel(FLAGS_sparse);

  es::Rasterizer rasterizer;
  es::RenderResult result;
  es::RenderOptions options;
  options.background = background;
  const es::SplatView splats = es::SplatView::Of(gaussians);
  for (const auto& [id, image] : model.images) {
    const auto cam = model.cameras.find(image.camera_id);
    if (cam == model.cameras.end()) {
      throw es::InputError(FLAGS_sparse + ": image " + image.name +
                           " refers to missing camera " +
                           std::to_string(image.camera_id));
    }
    const es::Camera camera =
        es::PinholeCameraFromColmap(cam->second, image, FLAGS_sparse);
    rasterizer.Forward(camera, splats, options, &result);
    const std::filesystem::path stem =
        std::filesystem::path(FLAGS_out_dir) /
        std::filesystem::path(image.name).replace_extension();
    std::filesystem::create_directories(stem.parent_path());
    es::WriteRgbPng(result, stem.string() + ".png");
    if (FLAGS_depth) {
      es::WriteDepthPng(result, FLAGS_depth_scale,
                        stem.string() + "_depth.png");
    }
    std::printf("%s: %d of %d Gaussians visible\n", image.name.c_str(),
                rasterizer.num_visible(), gaussians.size());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, Run);
}
