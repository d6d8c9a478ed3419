#ifndef EULERSPLAT_CORE_VIZ_WEB_PLAYER_H_
#define EULERSPLAT_CORE_VIZ_WEB_PLAYER_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/loop/loop_model.h"

namespace es {

struct WebPlayerOptions {
  double fps = 24;
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
  // The page's own files (index.html, player.js): web/player in the source
  // tree.
  std::string page_dir;
  // The npm packages scripts/setup.sh installs (web/node_modules): the
  // Gaussian-splat viewer and three.js, copied next to the page.
  std::string modules_dir;
};

// Writes a self-contained web page that plays the loop forever with orbit
// controls, built on the Spark splat viewer:
//   dir/index.html, player.js   the page
//   dir/scene.esloop            the loop file (core/loop/loop_file.h)
//   dir/view.json               cameras (COLMAP convention) and where the
//                               orbit target lies in front of the first
//   dir/poster.png              loop frame 0 from the first camera (our
//                               rasterizer, as es_animate draws it): the
//                               page shows it until the player has drawn
//                               a frame, so a screenshot taken early (or a
//                               browser without WebGL) shows the scene
//   dir/lib/                    the viewer's modules and their licenses
// The page fetches only these files; browsers need it served over HTTP
// (python3 -m http.server). `cameras` must not be empty; the first one is
// the start view. Throws InputError naming what is missing (the page or
// the npm packages: run scripts/setup.sh) or cannot be written. Returns
// the loop file's size in bytes.
int64_t ExportWebPlayer(const LoopModel& model,
                        const std::vector<Camera>& cameras,
                        const WebPlayerOptions& options,
                        const std::string& dir);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_WEB_PLAYER_H_
