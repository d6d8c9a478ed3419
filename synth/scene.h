#ifndef EULERSPLAT_SYNTH_SCENE_H_
#define EULERSPLAT_SYNTH_SCENE_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/io/colmap_io.h"
#include "core/io/split.h"
#include "core/model/camera.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "synth/preset.h"
#include "synth/velocity_grid.h"

namespace es {

// The generator's knobs (es_synth's flags); saved to gt/settings.json.
struct SynthSettings {
  std::string preset = "waterfall";
  int frames = 120;
  int width = 320, height = 240;
  uint64_t seed = 1;
  // Seeds only the water's particles when > 0 (default: derived from
  // seed): the same scenery, cameras and flow with another realization of
  // the stochastic water.
  uint64_t water_seed = 0;
  double stochasticity = 1.0;  // 0: every particle follows the field exactly
  double detail = 1.0;         // Gaussian count scale (see MakeSynthPreset)
  int substeps = 4;            // RK4 steps per frame
  int grid_resolution = 32;    // velocity grid nodes along the longest side
  int num_points = 4000;       // points3D sampled on the scenery
  double point_noise = 0.01;   // their position noise std (world units)
  double pixel_noise = 0.3;    // their 2D observations' noise std (pixels)
  int test_segments = 3;       // split.txt: held-out runs of frames
  double test_fraction = 0.1;
};

// A pixel is water when the water's share of the composited color (the
// extra channel) is above this.
constexpr double kWaterMaskThreshold = 0.5;
// Depth is written where the composited alpha is above this.
constexpr double kDepthMinAlpha = 0.5;

struct SynthScene {
  SynthSettings settings;
  SynthPreset preset;
  GaussianSet scenery;
  std::vector<Camera> cameras;
  std::vector<cv::Mat> images;    // CV_8UC3, RGB
  std::vector<cv::Mat> masks;     // CV_8UC1, 255 = water
  std::vector<cv::Mat> depths;    // CV_32FC1, camera z; 0 = no surface
  std::vector<double> coverage;   // water fraction of each frame
  std::vector<int> num_water;     // water Gaussians rendered per frame
  Eigen::AlignedBox3d water_box;  // all rendered water positions
  VelocityGrid velocity;          // analytic field over water_box
  ColmapModel sparse;
  FrameSplit split;
};

// Called with each frame's index and water Gaussians as they are rendered.
using SynthFrameObserver = std::function<void(int, const GaussianSet&)>;

// Builds the scenery, warms the water up, then renders every frame.
// Deterministic for fixed settings. Throws InputError for bad settings.
SynthScene GenerateSynthScene(const SynthSettings& settings,
                              const SynthFrameObserver& observer = nullptr);

// Renders scenery and water together; the one extra channel is 1 on water
// Gaussians and 0 on scenery, so result->extra is the water's share of
// each pixel.
void RenderSynthFrame(const GaussianSet& scenery, const GaussianSet& water,
                      const Camera& camera, const Eigen::Vector3d& background,
                      Rasterizer* rasterizer, RenderResult* result);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_SCENE_H_
