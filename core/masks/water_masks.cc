#include "core/masks/water_masks.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"
#include "core/flow/flow_lifting.h"
#include "core/flow/optical_flow.h"
#include "core/masks/camera_flow.h"
#include "core/masks/disk.h"
#include "core/masks/residual_change.h"
#include "core/masks/water_matting.h"
#include "core/render/render_maps.h"

namespace es {
namespace {

// frame - static render, and the rendered depth.
struct StaticFit {
  cv::Mat residual;  // CV_32FC3
  cv::Mat misfit;    // CV_32FC1, |residual| mean over channels
  cv::Mat depth;     // CV_32FC1, 0 = no surface or an occluding edge
};

StaticFit FitFrame(const Frame& frame, const SplatView& splats,
                   const RenderOptions& options, double misfit_blur,
                   Rasterizer* rasterizer) {
  RenderResult render;
  rasterizer->Forward(frame.camera, splats, options, &render);
  cv::Mat rgb;
  cv::Mat(render.height, render.width, CV_64FC3, render.rgb.data())
      .convertTo(rgb, CV_32FC3);
  StaticFit fit;
  fit.residual = frame.image - rgb;
  cv::Mat blurred = fit.residual;
  if (misfit_blur > 0)
    cv::GaussianBlur(fit.residual, blurred, cv::Size(0, 0), misfit_blur);
  cv::transform(cv::abs(blurred), fit.misfit,
                cv::Matx13f(1 / 3.f, 1 / 3.f, 1 / 3.f));
  fit.depth = FloatImage(render, ExpectedDepth(render, 0.5));
  // At occluding edges the depth is a blend and the camera's flow there is
  // wrong: no depth, no flow nor change cue.
  cv::Mat lo, hi;
  cv::erode(fit.depth, lo, cv::Mat());
  cv::dilate(fit.depth, hi, cv::Mat());
  fit.depth.setTo(0, hi - lo > 0.05 * lo);
  return fit;
}

// |flow - camera flow| per pixel; 0 where the camera flow is unknown.
cv::Mat NonRigidFlow(const cv::Mat& flow, const cv::Mat& camera_flow) {
  cv::Mat out(flow.size(), CV_32FC1, cv::Scalar(0.f));
  for (int y = 0; y < flow.rows; ++y)
    for (int x = 0; x < flow.cols; ++x) {
      const cv::Vec2f c = camera_flow.at<cv::Vec2f>(y, x);
      if (std::isnan(c[0])) continue;
      const cv::Vec2f f = flow.at<cv::Vec2f>(y, x);
      out.at<float>(y, x) = std::hypot(f[0] - c[0], f[1] - c[1]);
    }
  return out;
}

// Median of the values of `maps` where `valid` (same layout, optional) is
// non-zero, from a regular subsample.
double Median(const std::vector<cv::Mat>& maps,
              const std::vector<cv::Mat>* valid) {
  std::vector<float> values;
  for (size_t i = 0; i < maps.size(); ++i) {
    const cv::Mat& m = maps[i];
    for (int p = 0; p < static_cast<int>(m.total()); p += 7) {
      if (valid && (*valid)[i].at<float>(p) <= 0) continue;
      values.push_back(m.at<float>(p));
    }
  }
  if (values.empty()) return 0;
  auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Otsu's threshold of the evidence, on its log (evidence spans decades).
double OtsuThreshold(const std::vector<cv::Mat>& evidence) {
  const double lo = std::log(0.25), hi = std::log(256.0);
  std::vector<uchar> bytes;
  for (const cv::Mat& e : evidence)
    for (int p = 0; p < static_cast<int>(e.total()); p += 3) {
      const double v = std::log(std::max(e.at<float>(p), 1e-6f));
      bytes.push_back(cv::saturate_cast<uchar>(
          255.0 * (std::clamp(v, lo, hi) - lo) / (hi - lo)));
    }
  cv::Mat row(1, static_cast<int>(bytes.size()), CV_8UC1, bytes.data());
  cv::Mat unused;
  const double t = cv::threshold(row, unused, 0, 255,
                                 cv::THRESH_BINARY | cv::THRESH_OTSU);
  return std::exp(lo + t / 255.0 * (hi - lo));
}

// Removes connected blobs smaller than min_area pixels.
void DropSmallBlobs(int min_area, cv::Mat* mask) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(*mask, labels, stats,
                                                 centroids, 8, CV_32S);
  for (int y = 0; y < mask->rows; ++y)
    for (int x = 0; x < mask->cols; ++x) {
      const int l = labels.at<int>(y, x);
      if (l > 0 && l < n &&
          stats.at<int>(l, cv::CC_STAT_AREA) < min_area)
        mask->at<uchar>(y, x) = 0;
    }
}

// For each frame, the frames within `window` video frames of it (itself
// included), as indices into frames.
std::vector<std::vector<int>> TemporalNeighbours(
    const std::vector<Frame>& frames, int window) {
  std::vector<std::vector<int>> out(frames.size());
  for (size_t i = 0; i < frames.size(); ++i)
    for (size_t j = 0; j < frames.size(); ++j)
      if (std::abs(frames[j].time_index - frames[i].time_index) <= window)
        out[i].push_back(static_cast<int>(j));
  return out;
}

}  // namespace

WaterCues ParseWaterCues(const std::string& list) {
  WaterCues cues{false, false, false};
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name == "flow") cues.flow = true;
    else if (name == "change") cues.change = true;
    else if (name == "misfit") cues.misfit = true;
    else
      throw InputError("--cues: unknown cue '" + name +
                       "' (flow, change or misfit)");
  }
  if (!cues.flow && !cues.change && !cues.misfit)
    throw InputError("--cues: name at least one cue");
  return cues;
}

WaterMaskResult EstimateWaterMasks(
    const Scene& scene, const GaussianSet& static_model,
    const WaterMaskOptions& options,
    const std::function<void(int, int)>& progress) {
  const std::vector<Frame>& frames = scene.frames;
  const int n = static_cast<int>(frames.size());
  CHECK_GT(n, 0);
  std::map<int, int> by_time;
  for (int i = 0; i < n; ++i) by_time[frames[i].time_index] = i;

  // The flow cue for every frame, and what the change cue needs.
  const SplatView splats = SplatView::Of(static_model);
  Rasterizer rasterizer;
  OpticalFlow flow(FlowMethod::kDisMedium);
  std::vector<cv::Mat> misfit(n), nonrigid(n), unexplained(n), has_depth(n);
  std::vector<ResidualFrame> residuals(n);
  for (int i = 0; i < n; ++i) {
    const StaticFit fit =
        FitFrame(frames[i], splats, options.render,
                 options.misfit_blur * frames[i].image.cols, &rasterizer);
    misfit[i] = fit.misfit;
    residuals[i] = {frames[i].camera, fit.residual, fit.depth,
                    frames[i].time_index};
    cv::threshold(fit.depth, has_depth[i], 0, 1, cv::THRESH_BINARY);
    // The next frame in time, else the previous one.
    int j = -1;
    for (int step : {1, -1}) {
      const auto it = by_time.find(frames[i].time_index + step);
      if (it != by_time.end()) {
        j = it->second;
        break;
      }
    }
    nonrigid[i] = cv::Mat(fit.depth.size(), CV_32FC1, cv::Scalar(0.f));
    if (j >= 0 && options.cues.flow) {
      const cv::Mat camera_flow =
          CameraFlow(fit.depth, frames[i].camera, frames[j].camera);
      nonrigid[i] = NonRigidFlow(
          flow.Compute(frames[i].image, frames[j].image), camera_flow);
      if (options.flow_needs_change) {
        cv::Mat carried, known;
        CarryByCameraFlow(frames[j].image, camera_flow, &carried, &known);
        unexplained[i] = TolerantDifference(frames[i].image, carried,
                                            options.change.tolerance);
        unexplained[i].setTo(0, known == 0);
      }
    }
    if (progress) progress(i + 1, 2 * n);
  }

  // Each cue in units of the static majority's level.
  // Floors: below them a level is noise, and a video in which nothing
  // moves must not find water in its noise.
  const double flow_level =
      std::max(Median(nonrigid, &has_depth), options.min_flow_level);
  // The level of what the camera's motion leaves unexplained from one
  // frame to the next: noise on static surfaces.
  std::vector<cv::Mat> with_flow, flow_depth;
  for (int i = 0; i < n; ++i)
    if (!unexplained[i].empty()) {
      with_flow.push_back(unexplained[i]);
      flow_depth.push_back(has_depth[i]);
    }
  const double unexplained_level =
      std::max(Median(with_flow, &flow_depth), options.min_misfit_level);
  const std::vector<cv::Mat> change =
      options.cues.change ? ResidualChange(residuals, options.change)
                          : std::vector<cv::Mat>(n, cv::Mat(misfit[0].size(),
                                                           CV_32FC1,
                                                           cv::Scalar(-1.f)));
  std::vector<cv::Mat> has_change(n);
  for (int i = 0; i < n; ++i)
    cv::threshold(change[i], has_change[i], -0.5, 1, cv::THRESH_BINARY);
  const double change_level =
      std::max(Median(change, &has_change), options.min_misfit_level);
  const double misfit_level =
      std::max(Median(misfit, nullptr), options.min_misfit_level);
  std::vector<cv::Mat> cue(n);
  for (int i = 0; i < n; ++i) {
    // A misfit alone cannot tell water from scenery the model has not
    // learned yet, so it counts at a fraction of its weight: only a
    // surface the model shows nothing like is water by misfit alone.
    const cv::Mat zero(misfit[i].size(), CV_32FC1, cv::Scalar(0.f));
    const cv::Mat change_cue = options.cues.change
        ? cv::Mat(cv::max(change[i], 0.f) / change_level) : zero;
    const cv::Mat misfit_cue = options.cues.misfit
        ? cv::Mat(misfit[i] * (options.misfit_weight / misfit_level)) : zero;
    // Motion the camera does not explain, and (when asked) only as far
    // as colours it does not explain either.
    cv::Mat flow_cue = nonrigid[i] / flow_level;
    if (!unexplained[i].empty())
      flow_cue = cv::min(flow_cue, unexplained[i] / unexplained_level);
    cue[i] = cv::max(cv::max(flow_cue, change_cue), misfit_cue);
    cv::GaussianBlur(cue[i], cue[i], cv::Size(0, 0), 1.0);
  }
  const std::vector<std::vector<int>> near =
      TemporalNeighbours(frames, options.window);
  WaterMaskResult result;
  result.evidence.resize(n);
  for (int i = 0; i < n; ++i) {
    result.evidence[i] = cv::Mat(cue[i].size(), CV_32FC1, cv::Scalar(0.f));
    for (int j : near[i]) result.evidence[i] += cue[j];
    result.evidence[i] /= static_cast<double>(near[i].size());
  }
  result.threshold =
      std::max(OtsuThreshold(result.evidence), options.min_score);

  // Threshold and clean each frame, then vote over the window.
  const int width = frames[0].image.cols;
  const cv::Mat open = Disk(std::lround(options.open_radius * width));
  const cv::Mat close = Disk(std::lround(options.close_radius * width));
  std::vector<cv::Mat> raw(n);
  for (int i = 0; i < n; ++i) {
    cv::Mat m;
    cv::threshold(result.evidence[i], m, result.threshold, 255,
                  cv::THRESH_BINARY);
    m.convertTo(raw[i], CV_8U);
    cv::morphologyEx(raw[i], raw[i], cv::MORPH_OPEN, open);
    cv::morphologyEx(raw[i], raw[i], cv::MORPH_CLOSE, close);
  }
  result.masks.resize(n);
  double fraction = 0;
  for (int i = 0; i < n; ++i) {
    cv::Mat votes(raw[i].size(), CV_32FC1, cv::Scalar(0.f));
    for (int j : near[i]) cv::accumulate(raw[j], votes);
    cv::Mat majority;
    cv::threshold(votes, majority, 255.0 * near[i].size() / 2, 255,
                  cv::THRESH_BINARY);
    majority.convertTo(result.masks[i], CV_8U);
    DropSmallBlobs(static_cast<int>(options.min_blob *
                                    result.masks[i].total()),
                   &result.masks[i]);
    fraction += cv::countNonZero(result.masks[i]) /
                static_cast<double>(result.masks[i].total());
  }
  // Whether there is water at all is the regions' call; within them, the
  // matting finds it per pixel.
  result.water_fraction = fraction / n;
  result.has_water = result.water_fraction >= options.min_water_fraction;
  if (result.has_water && options.matting) {
    std::vector<cv::Mat> images(n);
    for (int i = 0; i < n; ++i) images[i] = frames[i].image;
    result.regions = result.masks;
    result.masks = MatWater(residuals, images, result.regions,
                            options.matting_options, [&](int done) {
                              if (progress) progress(n + done, 2 * n);
                            });
    fraction = 0;
    for (const cv::Mat& m : result.masks)
      fraction += cv::countNonZero(m) / static_cast<double>(m.total());
    result.water_fraction = fraction / n;
  } else if (progress) {
    progress(2 * n, 2 * n);
  }
  return result;
}

cv::Mat WaterMaskSheet(const Scene& scene, const WaterMaskResult& result,
                       int count) {
  const int n = static_cast<int>(scene.frames.size());
  CHECK_EQ(static_cast<int>(result.masks.size()), n);
  count = std::clamp(count, 1, n);
  const cv::Size size = scene.frames[0].image.size();
  const int columns = 4;  // two (frame, evidence) pairs per row
  const int rows = (2 * count + columns - 1) / columns;
  cv::Mat sheet(rows * size.height, columns * size.width, CV_8UC3,
                cv::Scalar(40, 40, 40));
  for (int k = 0; k < count; ++k) {
    const int i = count == 1 ? 0 : k * (n - 1) / (count - 1);
    cv::Mat bgr;
    cv::cvtColor(scene.frames[i].image, bgr, cv::COLOR_RGB2BGR);
    bgr.convertTo(bgr, CV_8U, 255);
    cv::Mat tinted = bgr.clone();
    tinted.setTo(cv::Scalar(255, 160, 0), result.masks[i]);
    cv::addWeighted(bgr, 0.55, tinted, 0.45, 0, bgr);
    // The outline of the region (per-pixel masks would outline every
    // droplet).
    const cv::Mat& outline =
        result.regions.empty() ? result.masks[i] : result.regions[i];
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(outline.clone(), contours, cv::RETR_EXTERNAL,
                     cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(bgr, contours, -1, cv::Scalar(0, 255, 255), 1);
    // Evidence on a log scale: 1 (static level) dark, 64 bright.
    cv::Mat level;
    cv::log(cv::max(result.evidence[i], 1.0f), level);
    level.convertTo(level, CV_8U, 255.0 / std::log(64.0));
    cv::Mat heat;
    cv::applyColorMap(level, heat, cv::COLORMAP_INFERNO);
    const cv::Mat tiles[2] = {bgr, heat};
    for (int t = 0; t < 2; ++t) {
      const int slot = 2 * k + t;
      const cv::Rect where((slot % columns) * size.width,
                           (slot / columns) * size.height, size.width,
                           size.height);
      tiles[t].copyTo(sheet(where));
      const std::string label =
          t == 0 ? scene.frames[i].camera.image_name : "evidence";
      cv::putText(sheet, label, where.tl() + cv::Point(3, 12),
                  cv::FONT_HERSHEY_SIMPLEX, std::max(0.3, size.width / 800.0),
                  cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    }
  }
  return sheet;
}

}  // namespace es
