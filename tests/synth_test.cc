#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/colmap_io.h"
#include "core/base/input_error.h"
#include "core/io/scene.h"
#include "core/render/rasterizer.h"
#include "core/render/render_maps.h"
#include "synth/camera.h"
#include "synth/preset.h"
#include "synth/scene.h"
#include "synth/velocity_grid.h"
#include "synth/water.h"
#include "synth/writer.h"
#include "tests/tiny_synth_settings.h"

namespace es {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::path(ES_BINARY_DIR) / "synth_test" / name;
  fs::remove_all(dir);
  return dir;
}

std::map<std::string, std::string> ReadTree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    files[fs::relative(e.path(), root).string()] =
        std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

TEST(SynthTest, SameSeedGivesSameBytes) {
  const fs::path a = TempDir("same_a"), b = TempDir("same_b");
  WriteSynthScene(GenerateSynthScene(TinySynthSettings()), a.string());
  WriteSynthScene(GenerateSynthScene(TinySynthSettings()), b.string());
  const auto files_a = ReadTree(a), files_b = ReadTree(b);
  ASSERT_GT(files_a.size(), 30u);  // 10 images, 10 masks, 10 depths, ...
  EXPECT_EQ(files_a, files_b);

  SynthSettings other = TinySynthSettings();
  other.seed = 8;
  const SynthScene changed = GenerateSynthScene(other);
  const SynthScene same = GenerateSynthScene(TinySynthSettings());
  EXPECT_GT(cv::norm(changed.images[0], same.images[0], cv::NORM_L1), 0.0);
}

// Another water seed re-draws the water alone: the scenery and the cameras
// stay, and the water pixels change.
TEST(SynthTest, WaterSeedChangesOnlyTheWater) {
  const SynthScene base = GenerateSynthScene(TinySynthSettings());
  SynthSettings other = TinySynthSettings();
  other.water_seed = 99;
  const SynthScene redrawn = GenerateSynthScene(other);
  EXPECT_EQ(base.scenery.means, redrawn.scenery.means);
  EXPECT_EQ(base.scenery.sh, redrawn.scenery.sh);
  ASSERT_EQ(base.images.size(), redrawn.images.size());
  double water_change = 0;
  int water_pixels = 0;
  for (size_t f = 0; f < base.images.size(); ++f) {
    EXPECT_TRUE(base.cameras[f].Center().isApprox(redrawn.cameras[f].Center()));
    EXPECT_TRUE(base.cameras[f].R().isApprox(redrawn.cameras[f].R()));
    cv::Mat diff;
    cv::absdiff(base.images[f], redrawn.images[f], diff);
    cv::Mat water = base.masks[f] | redrawn.masks[f];
    const cv::Scalar sum = cv::sum(diff.setTo(0, ~water));
    water_change += sum[0] + sum[1] + sum[2];
    water_pixels += cv::countNonZero(water);
  }
  ASSERT_GT(water_pixels, 0);
  // 8-bit levels summed over the channels; same seed: 0.
  EXPECT_GT(water_change / water_pixels, 10.0);
}

// With no perturbation, particle motion is the analytic field: central
// differences of positions at consecutive RK4 sub-steps match it.
TEST(SynthTest, GroundTruthVelocityMatchesParticleMotion) {
  for (const std::string& name : SynthPresetNames()) {
    SCOPED_TRACE(name);
    const SynthPreset preset = MakeSynthPreset(name, 0.02, 3);
    WaterSimOptions options = preset.water;
    options.stochasticity = 0.0;
    options.substeps = 16;
    WaterSim sim(preset.flow, options);
    // Long enough for particles to reach every part of the flow.
    sim.AdvanceFrames(80);
    const auto before = sim.particles();
    sim.Substep();
    const auto middle = sim.particles();
    sim.Substep();
    const auto after = sim.particles();
    int checked = 0;
    double worst = 0.0;
    for (size_t i = 0; i < before.size(); ++i) {
      if (!before[i].active() || before[i].generation != after[i].generation ||
          before[i].age > after[i].age)
        continue;
      const Eigen::Vector3d fd =
          (after[i].position - before[i].position) / (2.0 * sim.dt());
      const Eigen::Vector3d v = preset.flow.Velocity(middle[i].position);
      worst = std::max(worst, (fd - v).norm() / (v.norm() + 1e-3));
      ++checked;
    }
    EXPECT_GT(checked, 100);
    EXPECT_LT(worst, 2e-3);
  }
}

// The perturbation really moves particles off the field; without it each
// step is the field's (compared at the step's midpoint, O(dt^3)).
TEST(SynthTest, StochasticityPerturbsParticles) {
  const SynthPreset preset = MakeSynthPreset("waterfall", 0.02, 3);
  double deviation[2] = {0, 0};
  for (int s = 0; s < 2; ++s) {
    WaterSimOptions options = preset.water;
    options.stochasticity = s;
    options.substeps = 16;
    WaterSim sim(preset.flow, options);
    sim.AdvanceFrames(80);
    const auto before = sim.particles();
    sim.Substep();
    const auto after = sim.particles();
    for (size_t i = 0; i < before.size(); ++i) {
      if (!before[i].active() || before[i].generation != after[i].generation)
        continue;
      const Eigen::Vector3d step = after[i].position - before[i].position;
      const Eigen::Vector3d field =
          sim.dt() * preset.flow.Velocity(
                         0.5 * (before[i].position + after[i].position));
      deviation[s] = std::max(deviation[s], (step - field).norm() /
                                                (field.norm() + 1e-9));
    }
  }
  EXPECT_LT(deviation[0], 0.01);
  EXPECT_GT(deviation[1], 0.1);
}

TEST(SynthTest, VelocityGridIsTheFieldAndRoundTrips) {
  const SynthScene scene = GenerateSynthScene(TinySynthSettings());
  const VelocityGrid& grid = scene.velocity;
  EXPECT_EQ(grid.resolution.maxCoeff(), 8);
  EXPECT_TRUE(grid.box.contains(scene.preset.water.source.center()));
  const Eigen::Vector3i r = grid.resolution;
  for (int k = 0; k < r.z(); k += 3) {
    for (int j = 0; j < r.y(); j += 2) {
      for (int i = 0; i < r.x(); i += 2) {
        const Eigen::Vector3d v =
            scene.preset.flow.Velocity(grid.Node(i, j, k));
        EXPECT_LT((grid.At(i, j, k) - v).norm(), 1e-6 * (1 + v.norm()));
      }
    }
  }
  const fs::path dir = TempDir("grid");
  fs::create_directories(dir);
  const std::string path = (dir / "velocity_grid.bin").string();
  WriteVelocityGrid(grid, path);
  const VelocityGrid read = ReadVelocityGrid(path);
  EXPECT_EQ(read.resolution, grid.resolution);
  EXPECT_EQ(read.box.min(), grid.box.min());
  EXPECT_EQ(read.box.max(), grid.box.max());
  EXPECT_EQ(read.values, grid.values);
  // Trilinear sampling reproduces the node values.
  EXPECT_LT((read.Sample(read.Node(2, 1, 1)) - read.At(2, 1, 1)).norm(),
            1e-6);

  std::ofstream(path, std::ios::binary | std::ios::trunc) << "ESVGRID1";
  EXPECT_THROW(ReadVelocityGrid(path), InputError);
}

// The mask is where the rendered water dominates. The water's share of a
// pixel can never exceed the alpha of the water rendered alone, and where
// the water alone is dense and in front of the scenery the mask is set.
TEST(SynthTest, MasksMatchTheRenderedWater) {
  std::vector<GaussianSet> waters;
  const SynthScene scene = GenerateSynthScene(
      TinySynthSettings(),
      [&waters](int, const GaussianSet& water) { waters.push_back(water); });
  ASSERT_EQ(waters.size(), scene.images.size());
  Rasterizer rasterizer;
  RenderOptions options;
  options.background = scene.preset.background;
  for (int f : {0, 9}) {
    SCOPED_TRACE(f);
    const Camera& camera = scene.cameras[f];
    RenderResult water, scenery;
    rasterizer.Forward(camera, SplatView::Of(waters[f]), options, &water);
    rasterizer.Forward(camera, SplatView::Of(scene.scenery), options,
                       &scenery);
    const std::vector<double> water_depth = ExpectedDepth(water, 0.5);
    const std::vector<double> scenery_depth = ExpectedDepth(scenery, 0.5);
    const cv::Mat& mask = scene.masks[f];
    int in_mask = 0, outside_dense_water = 0, dense_in_front = 0,
        dense_in_front_masked = 0;
    double change_in = 0, change_out = 0;
    for (int p = 0; p < static_cast<int>(mask.total()); ++p) {
      const bool masked = mask.data[p] == 255;
      const bool dense = water.alpha[p] > 0.9;
      if (masked) ++in_mask;
      if (masked && water.alpha[p] <= kWaterMaskThreshold)
        ++outside_dense_water;
      if (dense && (scenery_depth[p] == 0 ||
                    water_depth[p] < 0.9 * scenery_depth[p])) {
        ++dense_in_front;
        if (masked) ++dense_in_front_masked;
      }
      // How much the water changed the pixel compared to the scenery alone.
      double change = 0;
      for (int c = 0; c < 3; ++c)
        change += std::abs(scene.images[f].data[3 * p + c] / 255.0 -
                           scenery.rgb[3 * p + c]);
      (masked ? change_in : change_out) += change;
    }
    const int pixels = static_cast<int>(mask.total());
    ASSERT_GT(in_mask, pixels / 10);
    ASSERT_LT(in_mask, pixels * 9 / 10);
    EXPECT_EQ(outside_dense_water, 0);
    ASSERT_GT(dense_in_front, pixels / 20);
    EXPECT_GT(dense_in_front_masked, 0.95 * dense_in_front);
    EXPECT_GT(change_in / in_mask, 5.0 * change_out / (pixels - in_mask));
  }
}

TEST(SynthTest, SceneLoadsBackWithExactPoses) {
  const SynthScene synth = GenerateSynthScene(TinySynthSettings());
  const fs::path dir = TempDir("load");
  WriteSynthScene(synth, dir.string());

  const ColmapModel model = ReadColmapModel((dir / "sparse" / "0").string());
  ASSERT_EQ(model.cameras.size(), 1u);
  EXPECT_EQ(model.cameras.begin()->second.model, "PINHOLE");
  EXPECT_EQ(model.images.size(), synth.cameras.size());
  ASSERT_GT(model.points.size(), 50u);
  // Every track observation lies where its point projects (pixel noise and
  // a small position noise only).
  for (const ColmapPoint3D& point : model.points) {
    ASSERT_GE(point.track.size(), 2u);
    for (const auto& [image_id, index] : point.track) {
      const ColmapImage& image = model.images.at(image_id);
      const Camera& camera = synth.cameras[image_id - 1];
      const Eigen::Vector2d uv =
          camera.Project(camera.WorldToCamera(point.xyz));
      EXPECT_LT((uv - image.points2d[index]).norm(), 4.0);
      EXPECT_EQ(image.point3d_ids[index], point.id);
    }
  }

  const Scene scene = LoadScene(dir.string());
  ASSERT_EQ(scene.frames.size(), synth.cameras.size());
  ASSERT_TRUE(scene.has_masks);
  EXPECT_EQ(scene.test, synth.split.test);
  EXPECT_FALSE(scene.test.empty());
  for (size_t f = 0; f < scene.frames.size(); ++f) {
    const Camera& loaded = scene.frames[f].camera;
    const Camera& truth = synth.cameras[f];
    EXPECT_EQ(loaded.image_name, truth.image_name);
    EXPECT_NEAR(loaded.fx, truth.fx, 1e-9);
    EXPECT_NEAR(loaded.cy, truth.cy, 1e-9);
    EXPECT_LT((loaded.Center() - truth.Center()).norm(), 1e-6);
    EXPECT_LT(loaded.q_cw.angularDistance(truth.q_cw), 1e-6);
    cv::Mat mask;
    scene.frames[f].mask.convertTo(mask, CV_8U, 255.0);
    EXPECT_EQ(cv::norm(mask, synth.masks[f], cv::NORM_INF), 0.0);
  }

  // Depth ground truth: float32 camera z, the rendered surface's.
  const cv::Mat depth = cv::imread(
      (dir / "gt" / "depth" / "frame_000003.tiff").string(),
      cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_32FC1);
  EXPECT_EQ(cv::norm(depth, synth.depths[3], cv::NORM_INF), 0.0);
  EXPECT_GT(cv::countNonZero(depth), static_cast<int>(depth.total()) / 2);
  EXPECT_TRUE(fs::exists(dir / "gt" / "settings.json"));
}

TEST(SynthTest, EveryPresetFramesItsWater) {
  for (const std::string& name : SynthPresetNames()) {
    SCOPED_TRACE(name);
    SynthSettings s = TinySynthSettings(name);
    s.frames = 3;
    const SynthScene scene = GenerateSynthScene(s);
    // A spray of few tiny droplets (at the test's low detail) is thin by
    // design; the others are sheets.
    const bool spray = name == "droplets" || name == "pathtraced" ||
                       name == "planks";
    const double min_coverage = spray ? 0.05 : 0.15;
    for (double c : scene.coverage) {
      EXPECT_GT(c, min_coverage);
      EXPECT_LT(c, 0.75);
    }
  }
  EXPECT_THROW(MakeSynthPreset("lake", 1.0, 1), InputError);
}

// The path-traced look's glints: bright only near the sun's mirror
// direction, so a few droplets flash and which ones depends on the eye.
TEST(SynthTest, GlintsAreNarrowAndFollowTheEye) {
  const SynthPreset preset = MakeSynthPreset("pathtraced", 0.05, 3);
  ASSERT_GT(preset.look.glint, 0.0);
  WaterSim sim(preset.flow, preset.water);
  sim.AdvanceFrames(60);
  WaterLook plain = preset.look;
  plain.glint = 0.0;
  WaterShot left, right;
  left.eye = {-1.0, 1.9, 5.8};
  right.eye = {1.0, 2.2, 5.5};
  const GaussianSet base = sim.ToGaussians(plain, left);
  const GaussianSet a = sim.ToGaussians(preset.look, left);
  const GaussianSet b = sim.ToGaussians(preset.look, right);
  ASSERT_EQ(a.size(), base.size());
  ASSERT_GT(a.size(), 100);
  int bright_a = 0, bright_b = 0, both = 0;
  for (int n = 0; n < a.size(); ++n) {
    const double glint_a = (a.sh[3 * n] - base.sh[3 * n]) * kShC0;
    const double glint_b = (b.sh[3 * n] - base.sh[3 * n]) * kShC0;
    ASSERT_GE(glint_a, -1e-12);  // light is only added
    EXPECT_NEAR(a.sh[3 * n + 1] - base.sh[3 * n + 1],
                a.sh[3 * n] - base.sh[3 * n], 1e-12);  // white light
    bright_a += glint_a > 0.3;
    bright_b += glint_b > 0.3;
    both += glint_a > 0.3 && glint_b > 0.3;
  }
  EXPECT_GT(bright_a, 0);
  EXPECT_GT(bright_b, 0);
  EXPECT_LT(bright_a, a.size() / 5);  // a sparkle, not a sheen
  EXPECT_LT(both, std::min(bright_a, bright_b));
}

// The path-traced look's sample noise: the same scenery and cameras as
// the droplets preset, and away from their water a difference of the
// noise's std alone (8-bit levels; median statistics, as faint droplets
// below the masks' threshold still differ).
TEST(SynthTest, PathTracedFramesAddSampleNoiseToTheScenery) {
  SynthSettings settings = TinySynthSettings("droplets");
  settings.frames = 2;
  settings.width = 96;
  settings.height = 72;
  const SynthScene plain = GenerateSynthScene(settings);
  settings.preset = "pathtraced";
  const SynthScene traced = GenerateSynthScene(settings);
  ASSERT_EQ(traced.images.size(), 2u);
  const double noise = 255.0 * traced.preset.effects.noise;
  for (int f = 0; f < 2; ++f) {
    cv::Mat water = plain.masks[f] | traced.masks[f];
    cv::dilate(water, water, cv::Mat::ones(9, 9, CV_8UC1));
    std::vector<double> differences;
    for (int i = 0; i < water.rows; ++i) {
      for (int j = 0; j < water.cols; ++j) {
        if (water.at<uint8_t>(i, j) != 0) continue;
        const cv::Vec3b a = traced.images[f].at<cv::Vec3b>(i, j);
        const cv::Vec3b b = plain.images[f].at<cv::Vec3b>(i, j);
        for (int c = 0; c < 3; ++c) differences.push_back(double(a[c]) - b[c]);
      }
    }
    ASSERT_GT(differences.size(), 3000u);
    auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    EXPECT_NEAR(median(differences), 0.0, 0.5);
    std::vector<double> deviations;
    for (double d : differences) deviations.push_back(std::abs(d));
    // The median absolute deviation of a normal is 0.6745 of its std.
    EXPECT_NEAR(median(deviations) / 0.6745, noise, 0.2 * noise);
  }
}

TEST(SynthTest, LookAtCentersTheTarget) {
  Camera c = LookAt({1, 2, 5}, {0.5, 1, 0}, {0, 1, 0}, 0.0);
  c.fx = c.fy = 100;
  c.cx = 32;
  c.cy = 24;
  const Eigen::Vector3d target = c.WorldToCamera({0.5, 1, 0});
  EXPECT_GT(target.z(), 0);
  EXPECT_LT((c.Project(target) - Eigen::Vector2d(32, 24)).norm(), 1e-9);
  // World up is image up (smaller v).
  EXPECT_LT(c.Project(c.WorldToCamera({0.5, 1.2, 0})).y(), 24);
}

}  // namespace
}  // namespace es
