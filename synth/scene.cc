#include "synth/scene.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <glog/logging.h>

#include "core/base/input_error.h"
#include "core/render/render_maps.h"
#include "synth/camera.h"
#include "synth/random.h"
#include "synth/scenery.h"
#include "synth/sparse.h"
#include "synth/water.h"

namespace es {
namespace {

// Independent random streams derived from the one user seed.
enum SeedStream : uint64_t { kScenerySeed = 1, kCameraSeed, kWaterSeed,
                             kSparseSeed, kPresetSeed, kNoiseSeed };

void CheckSettings(const SynthSettings& s) {
  auto fail = [](const std::string& what) {
    throw InputError("es_synth: " + what);
  };
  if (s.frames < 1) fail("--frames must be >= 1");
  if (s.width < 8 || s.height < 8) fail("--width and --height must be >= 8");
  if (s.stochasticity < 0) fail("--stochasticity must be >= 0");
  if (s.substeps < 1) fail("--substeps must be >= 1");
  if (s.grid_resolution < 2) fail("--grid_resolution must be >= 2");
  if (s.num_points < 0) fail("--num_points must be >= 0");
}

// Grid nodes per axis: `longest` on the box's longest side, proportional
// elsewhere, at least 2.
Eigen::Vector3i GridResolution(const Eigen::AlignedBox3d& box, int longest) {
  const Eigen::Vector3d size = box.sizes();
  Eigen::Vector3i r;
  for (int a = 0; a < 3; ++a)
    r[a] = std::max(2, static_cast<int>(std::lround(
                           (longest - 1) * size[a] / size.maxCoeff())) + 1);
  return r;
}

cv::Mat ToImage(const RenderResult& r) {
  cv::Mat image(r.height, r.width, CV_8UC3);
  for (int i = 0; i < r.height; ++i) {
    uint8_t* row = image.ptr<uint8_t>(i);
    for (int j = 0; j < 3 * r.width; ++j) {
      const double v = std::clamp(r.rgb[3 * r.width * i + j], 0.0, 1.0);
      row[j] = static_cast<uint8_t>(std::lround(255.0 * v));
    }
  }
  return image;
}

cv::Mat ToMask(const RenderResult& r) {
  cv::Mat mask(r.height, r.width, CV_8UC1);
  for (int p = 0; p < r.width * r.height; ++p)
    mask.data[p] = r.extra[p] > kWaterMaskThreshold ? 255 : 0;
  return mask;
}

cv::Mat ToDepth(const RenderResult& r) {
  const std::vector<double> depth = ExpectedDepth(r, kDepthMinAlpha);
  cv::Mat out(r.height, r.width, CV_32FC1);
  for (int p = 0; p < r.width * r.height; ++p)
    out.at<float>(p) = static_cast<float>(depth[p]);
  return out;
}

// The frame as a shutter open for effects.shutter of it sees the water:
// the mean of motion_blur_samples renders spread evenly over that time
// (colour, alpha, depth and the water share alike).
void RenderMotionBlurred(const GaussianSet& scenery, const WaterSim& water,
                         const SynthPreset& preset, const Camera& camera,
                         Rasterizer* rasterizer, RenderResult* result) {
  const int samples = preset.effects.motion_blur_samples;
  RenderResult sample;
  for (int k = 0; k < samples; ++k) {
    WaterShot shot;
    shot.eye = camera.Center();
    shot.time_offset = preset.effects.shutter * ((k + 0.5) / samples - 0.5);
    RenderSynthFrame(scenery, water.ToGaussians(preset.look, shot), camera,
                     preset.background, rasterizer, &sample);
    if (k == 0) {
      *result = sample;
      continue;
    }
    for (auto [sum, add] : {std::pair{&result->rgb, &sample.rgb},
                            std::pair{&result->alpha, &sample.alpha},
                            std::pair{&result->depth, &sample.depth},
                            std::pair{&result->extra, &sample.extra}}) {
      for (size_t i = 0; i < sum->size(); ++i) (*sum)[i] += (*add)[i];
    }
  }
  for (std::vector<double>* image :
       {&result->rgb, &result->alpha, &result->depth, &result->extra}) {
    for (double& v : *image) v /= samples;
  }
}

// A path tracer's finite samples: independent normal noise on every pixel
// and channel, drawn anew each frame.
void AddSampleNoise(double std_dev, uint64_t seed, RenderResult* result) {
  SynthRandom random(seed);
  for (double& v : result->rgb) v += std_dev * random.Normal();
}

}  // namespace

void RenderSynthFrame(const GaussianSet& scenery, const GaussianSet& water,
                      const Camera& camera, const Eigen::Vector3d& background,
                      Rasterizer* rasterizer, RenderResult* result) {
  CHECK_EQ(scenery.sh_degree, water.sh_degree);
  GaussianSet all = scenery;
  for (int i = 0; i < water.size(); ++i) all.AppendFrom(water, i);
  std::vector<double> is_water(all.size(), 0.0);
  std::fill(is_water.begin() + scenery.size(), is_water.end(), 1.0);
  SplatView view = SplatView::Of(all);
  view.num_extra = 1;
  view.extra = is_water.data();
  RenderOptions options;
  options.background = background;
  rasterizer->Forward(camera, view, options, result);
}

SynthScene GenerateSynthScene(const SynthSettings& settings,
                              const SynthFrameObserver& observer) {
  CheckSettings(settings);
  SynthScene scene;
  scene.settings = settings;
  const uint64_t seed = settings.seed;
  scene.preset = MakeSynthPreset(settings.preset, settings.detail,
                                 SynthRandom::Derive(seed, kPresetSeed));
  const SynthPreset& preset = scene.preset;
  scene.scenery =
      BuildScenery(preset.scenery, SynthRandom::Derive(seed, kScenerySeed));
  scene.cameras =
      MakeCameraPath(preset.camera, settings.frames, settings.width,
                     settings.height, SynthRandom::Derive(seed, kCameraSeed));

  WaterSimOptions water_options = preset.water;
  water_options.seed = SynthRandom::Derive(
      settings.water_seed > 0 ? settings.water_seed : seed, kWaterSeed);
  water_options.stochasticity = settings.stochasticity;
  water_options.substeps = settings.substeps;
  WaterSim water(preset.flow, water_options);
  water.AdvanceFrames(preset.warmup_frames);

  Rasterizer rasterizer;
  RenderResult result;
  for (int f = 0; f < settings.frames; ++f) {
    if (f > 0) water.AdvanceFrames(1);
    WaterShot shot;
    shot.eye = scene.cameras[f].Center();
    const GaussianSet splats = water.ToGaussians(preset.look, shot);
    for (int i = 0; i < splats.size(); ++i)
      scene.water_box.extend(Eigen::Vector3d(splats.means[3 * i],
                                             splats.means[3 * i + 1],
                                             splats.means[3 * i + 2]));
    if (observer) observer(f, splats);
    if (preset.effects.motion_blur_samples > 1) {
      RenderMotionBlurred(scene.scenery, water, preset, scene.cameras[f],
                          &rasterizer, &result);
    } else {
      RenderSynthFrame(scene.scenery, splats, scene.cameras[f],
                       preset.background, &rasterizer, &result);
    }
    if (preset.effects.noise > 0.0) {
      AddSampleNoise(preset.effects.noise,
                     SynthRandom::Derive(seed, kNoiseSeed + f), &result);
    }
    scene.images.push_back(ToImage(result));
    scene.masks.push_back(ToMask(result));
    scene.depths.push_back(ToDepth(result));
    scene.coverage.push_back(cv::countNonZero(scene.masks.back()) /
                             static_cast<double>(result.width * result.height));
    scene.num_water.push_back(splats.size());
  }

  if (scene.water_box.isEmpty()) scene.water_box = preset.water.source;
  // A little margin so particles on the box faces are inside.
  const Eigen::Vector3d pad = 0.02 * scene.water_box.sizes() +
                              Eigen::Vector3d::Constant(1e-3);
  scene.water_box.extend(scene.water_box.min() - pad);
  scene.water_box.extend(scene.water_box.max() + pad);
  scene.velocity = SampleVelocityGrid(
      preset.flow, scene.water_box,
      GridResolution(scene.water_box, settings.grid_resolution));

  SynthSparseOptions sparse;
  sparse.num_points = settings.num_points;
  sparse.point_noise = settings.point_noise;
  sparse.pixel_noise = settings.pixel_noise;
  sparse.seed = SynthRandom::Derive(seed, kSparseSeed);
  scene.sparse =
      MakeSynthSparse(scene.cameras, scene.scenery, scene.depths, sparse);
  scene.split = DefaultSplit(settings.frames, settings.test_segments,
                             settings.test_fraction);
  return scene;
}

}  // namespace es
