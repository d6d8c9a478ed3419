// Auto water masks on a synthetic scene whose answer is known: with the
// true scenery as the static model, the masks must find the true water;
// a video with no water must be called static, also when the static model
// has not learned part of the scenery; IoU on known cases.

#include "core/masks/water_masks.h"

#include <cstdio>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "synth/scene.h"

namespace es {
namespace {

SynthSettings SmallSettings(const std::string& preset) {
  SynthSettings s;
  s.preset = preset;
  s.frames = 12;
  // Water with some texture (at a smaller size or detail it is a smooth
  // blur that looks the same in every frame).
  s.width = 160;
  s.height = 120;
  s.detail = 0.3;
  s.seed = 3;
  s.grid_resolution = 8;
  s.num_points = 100;
  return s;
}

Scene ToScene(const SynthScene& synth) {
  Scene scene;
  for (size_t i = 0; i < synth.images.size(); ++i) {
    Frame f;
    f.camera = synth.cameras[i];
    synth.images[i].convertTo(f.image, CV_32FC3, 1.0 / 255);
    f.time_index = static_cast<int>(i);
    scene.frames.push_back(f);
  }
  return scene;
}

double MeanIou(const WaterMaskResult& result, const SynthScene& synth,
               const Scene& scene) {
  double sum = 0;
  for (size_t k = 0; k < scene.frames.size(); ++k)
    sum += MaskIou(result.masks[k],
                   synth.masks[scene.frames[k].time_index]);
  return sum / scene.frames.size();
}

TEST(WaterMasksTest, FindsTheTrueWaterOfEachPreset) {
  for (const std::string preset : {"waterfall", "stream", "fountain"}) {
    const SynthScene synth = GenerateSynthScene(SmallSettings(preset));
    Scene scene = ToScene(synth);
    const WaterMaskResult result =
        EstimateWaterMasks(scene, synth.scenery, WaterMaskOptions());
    ASSERT_EQ(result.masks.size(), scene.frames.size());
    EXPECT_TRUE(result.has_water) << preset;
    EXPECT_GT(MeanIou(result, synth, scene), 0.6) << preset;

    // A frame COLMAP did not register: the others keep their neighbours in
    // time and still find the water.
    scene.frames.erase(scene.frames.begin() + 5);
    const WaterMaskResult gap =
        EstimateWaterMasks(scene, synth.scenery, WaterMaskOptions());
    EXPECT_GT(MeanIou(gap, synth, scene), 0.6) << preset;
  }
}

// A curtain of spray is droplets with the cliff between them: its true
// masks are speckle, which the smooth regions cannot follow (they cover the
// whole curtain); the per-pixel matting must.
TEST(WaterMasksTest, FindsTheDropletsOfASprayInEachFrame) {
  const SynthScene synth = GenerateSynthScene(SmallSettings("droplets"));
  const Scene scene = ToScene(synth);
  WaterMaskOptions regions_only;
  regions_only.matting = false;
  const double regions =
      MeanIou(EstimateWaterMasks(scene, synth.scenery, regions_only), synth,
              scene);
  const WaterMaskResult result =
      EstimateWaterMasks(scene, synth.scenery, WaterMaskOptions());
  const double matted = MeanIou(result, synth, scene);
  std::printf("droplets IoU: regions %.3f, matted %.3f\n", regions, matted);
  EXPECT_TRUE(result.has_water);
  // 12 frames only: the cliff behind the densest spray is seldom seen
  // (regions 0.35, matted 0.55 when written).
  EXPECT_GT(matted, 0.45);
  EXPECT_GT(matted, regions + 0.1);
}

// Mean IoU and precision over the frames.
MaskScore MeanScore(const WaterMaskResult& result, const SynthScene& synth,
                    const Scene& scene) {
  MaskScore mean{0, 0, 0};
  for (size_t k = 0; k < scene.frames.size(); ++k) {
    const MaskScore s = ScoreMask(result.masks[k],
                                  synth.masks[scene.frames[k].time_index]);
    mean.iou += s.iou / scene.frames.size();
    mean.precision += s.precision / scene.frames.size();
    mean.recall += s.recall / scene.frames.size();
  }
  return mean;
}

// The trap (issue #48): the path-traced spray in front of walls of fine
// boards with dark seams, which a spray's matting can take for water where
// it sees them between droplets. 12 frames (6 samples of each pixel) and
// the true scenery as the static model: IoU 0.623, precision 0.634,
// recall 0.974 with the share measured against the water within a few
// pixels (0.597 / 0.598 / 0.996 against the pixel's own wettest sample).
TEST(WaterMasksTest, FineBoardsBehindASprayKeepTheirScores) {
  const SynthScene synth = GenerateSynthScene(SmallSettings("planks"));
  const Scene scene = ToScene(synth);
  const WaterMaskResult result =
      EstimateWaterMasks(scene, synth.scenery, WaterMaskOptions());
  const MaskScore score = MeanScore(result, synth, scene);
  std::printf("planks IoU / precision / recall: %.3f / %.3f / %.3f\n",
              score.iou, score.precision, score.recall);
  EXPECT_TRUE(result.has_water);
  EXPECT_GT(score.iou, 0.61);
  EXPECT_GT(score.precision, 0.62);
  EXPECT_GT(score.recall, 0.95);
}

// Frames of the scenery alone: everything the camera sees stands still.
Scene StillScene(const SynthScene& synth) {
  Scene scene = ToScene(synth);
  Rasterizer rasterizer;
  RenderResult render;
  for (Frame& f : scene.frames) {
    rasterizer.Forward(f.camera, SplatView::Of(synth.scenery),
                       RenderOptions(), &render);
    cv::Mat(render.height, render.width, CV_64FC3, render.rgb.data())
        .convertTo(f.image, CV_32FC3);
  }
  return scene;
}

TEST(WaterMasksTest, AVideoWithoutWaterIsStatic) {
  const SynthScene synth = GenerateSynthScene(SmallSettings("waterfall"));
  const Scene scene = StillScene(synth);
  // A slightly wrong static model, as a fit would be.
  GaussianSet fitted = synth.scenery;
  for (double& c : fitted.sh) c *= 0.97;
  const WaterMaskResult result =
      EstimateWaterMasks(scene, fitted, WaterMaskOptions());
  EXPECT_FALSE(result.has_water) << result.water_fraction;
  EXPECT_LT(result.water_fraction, WaterMaskOptions().min_water_fraction);
}

TEST(WaterMasksTest, SceneryTheModelHasNotLearnedIsNotWater) {
  const SynthScene synth = GenerateSynthScene(SmallSettings("waterfall"));
  const Scene scene = StillScene(synth);
  // The static model has the colour of the scenery left of x = -0.5 (over
  // a fifth of it) wrong by 0.1, as a short fit leaves scenery it has not
  // learned yet: a misfit several times the rest's, the same in every
  // frame. (With the misfit at full weight this finds water.)
  GaussianSet fitted = synth.scenery;
  constexpr double kDcToColour = 0.28209479177387814;
  const int k = NumShCoeffs(fitted.sh_degree);
  int changed = 0;
  for (int g = 0; g < fitted.size(); ++g) {
    if (fitted.means[3 * g] > -0.5) continue;
    for (int c = 0; c < 3; ++c)
      fitted.sh[(g * k) * 3 + c] += 0.1 / kDcToColour;
    ++changed;
  }
  ASSERT_GT(changed, fitted.size() / 5);
  const WaterMaskResult result =
      EstimateWaterMasks(scene, fitted, WaterMaskOptions());
  EXPECT_FALSE(result.has_water) << result.water_fraction;
}

TEST(WaterMasksTest, IouOfKnownMasks) {
  cv::Mat a(10, 10, CV_8UC1, cv::Scalar(0)), b = a.clone();
  EXPECT_EQ(MaskIou(a, b), 1.0);  // both empty
  a(cv::Rect(0, 0, 4, 10)).setTo(255);  // 40 pixels
  b(cv::Rect(2, 0, 4, 10)).setTo(255);  // 40 pixels, 20 shared
  EXPECT_NEAR(MaskIou(a, b), 20.0 / 60.0, 1e-12);
  cv::Mat f;
  a.convertTo(f, CV_32F, 1.0 / 255);
  EXPECT_NEAR(MaskIou(f, b), 20.0 / 60.0, 1e-12);
  EXPECT_EQ(MaskIou(a, a), 1.0);
}

}  // namespace
}  // namespace es
