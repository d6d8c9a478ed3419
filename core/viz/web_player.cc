#include "core/viz/web_player.h"

#include <algorithm>
#include <filesystem>

#include <glog/logging.h>

#include "core/base/input_error.h"
#include "core/io/json_file.h"
#include "core/loop/loop_file.h"
#include "core/loop/loop_renderer.h"
#include "core/viz/render_png.h"

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr char kLoopFileName[] = "scene.esloop";
constexpr char kPosterName[] = "poster.png";

// What the page imports, from web/node_modules, and where it goes under
// lib/ (the import map in index.html names these paths).
const struct {
  const char* from;
  const char* to;
} kViewerFiles[] = {
    {"@sparkjsdev/spark/dist/spark.module.js", "spark/spark.module.js"},
    {"@sparkjsdev/spark/LICENSE", "spark/LICENSE"},
    {"three/build/three.module.js", "three/build/three.module.js"},
    {"three/build/three.core.js", "three/build/three.core.js"},
    {"three/examples/jsm/controls/OrbitControls.js",
     "three/examples/jsm/controls/OrbitControls.js"},
    {"three/examples/jsm/postprocessing/Pass.js",
     "three/examples/jsm/postprocessing/Pass.js"},
    {"three/LICENSE", "three/LICENSE"},
};

void CopyInto(const fs::path& from, const fs::path& to,
              const std::string& hint) {
  if (!fs::is_regular_file(from))
    throw InputError(from.string() + ": missing (" + hint + ")");
  std::error_code error;
  fs::create_directories(to.parent_path(), error);
  if (!error)
    fs::copy_file(from, to, fs::copy_options::overwrite_existing, error);
  if (error)
    throw InputError(to.string() + ": cannot write (" + error.message() + ")");
}

// How far in front of the start camera the orbit target lies: the median
// depth of the splats it sees.
double TargetDistance(const LoopModel& model, const Camera& camera) {
  std::vector<double> depths;
  const GaussianSet& g = model.gaussians;
  for (int i = 0; i < g.size(); ++i) {
    const double z =
        camera.WorldToCamera(Eigen::Vector3d(&g.means[3 * i])).z();
    if (z > 0) depths.push_back(z);
  }
  if (depths.empty()) return 1.0;
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2,
                   depths.end());
  return depths[depths.size() / 2];
}

nlohmann::ordered_json ViewJson(const LoopModel& model,
                                const std::vector<Camera>& cameras) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const Camera& c : cameras) {
    const Eigen::Matrix3d r = c.R();
    nlohmann::ordered_json rotation = nlohmann::ordered_json::array();
    for (int k = 0; k < 9; ++k) rotation.push_back(r(k / 3, k % 3));
    list.push_back({{"width", c.width},
                    {"height", c.height},
                    {"fx", c.fx},
                    {"fy", c.fy},
                    {"cx", c.cx},
                    {"cy", c.cy},
                    {"rotation", rotation},
                    {"translation", {c.t_cw.x(), c.t_cw.y(), c.t_cw.z()}}});
  }
  nlohmann::ordered_json view;
  view["loop"] = kLoopFileName;
  view["target_distance"] = TargetDistance(model, cameras[0]);
  view["cameras"] = list;
  return view;
}

}  // namespace

int64_t ExportWebPlayer(const LoopModel& model,
                        const std::vector<Camera>& cameras,
                        const WebPlayerOptions& options,
                        const std::string& dir) {
  CHECK(!cameras.empty());
  const fs::path out(dir);
  for (const char* name : {"index.html", "player.js"})
    CopyInto(fs::path(options.page_dir) / name, out / name,
             "the page is in the project's web/player");
  for (const auto& file : kViewerFiles)
    CopyInto(fs::path(options.modules_dir) / file.from,
             out / "lib" / file.to,
             "scripts/setup.sh installs the npm packages");
  LoopFileOptions loop;
  loop.fps = options.fps;
  loop.background = options.background;
  const int64_t bytes =
      WriteLoopFile(model, loop, (out / kLoopFileName).string());
  WriteJsonFile((out / "view.json").string(), ViewJson(model, cameras));
  // What the page shows until the player has drawn: loop frame 0 from the
  // start camera, as es_animate renders it.
  RenderOptions render;
  render.background = options.background;
  LoopRenderer player(&model, render);
  player.Start(0);
  WriteRgbPng(player.Render(cameras[0]), (out / kPosterName).string());
  return bytes;
}

}  // namespace es
