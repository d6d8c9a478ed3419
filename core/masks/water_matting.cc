#include "core/masks/water_matting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/masks/camera_flow.h"
#include "core/masks/disk.h"

namespace es {
namespace {

float L1(const cv::Vec3f& a, const cv::Vec3f& b) {
  return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

// The pixels of `through` (CV_8UC1) 8-connected to a pixel of `seeds`
// (a subset of `through`).
cv::Mat ConnectedTo(const cv::Mat& seeds, const cv::Mat& through) {
  cv::Mat labels;
  const int n = cv::connectedComponents(through, labels, 8, CV_32S);
  std::vector<uchar> reached(n, 0);
  for (int p = 0; p < static_cast<int>(seeds.total()); ++p)
    if (seeds.at<uchar>(p)) reached[labels.at<int>(p)] = 255;
  reached[0] = 0;
  cv::Mat out(seeds.size(), CV_8UC1);
  for (int p = 0; p < static_cast<int>(out.total()); ++p)
    out.at<uchar>(p) = reached[labels.at<int>(p)];
  return out;
}

// The scenery behind a pixel: of its colours over time (the frame's own
// first), the one least like water.
cv::Vec3f SceneryColour(const std::vector<cv::Vec3f>& colours,
                        const cv::Vec3f& water) {
  cv::Vec3f scenery = colours[0];
  float farthest = L1(colours[0], water);
  for (size_t k = 1; k < colours.size(); ++k) {
    const float d = L1(colours[k], water);
    if (d > farthest) farthest = d, scenery = colours[k];
  }
  return scenery;
}

// The water in front of `scenery`: the palette colour nearest the colour
// most unlike the scenery among `wettest` (the wettest sample of each
// pixel) within `radius` of (x, y). Droplets are translucent: one pixel's
// wettest sample is often a faint droplet's blend with the scenery, and
// measured against it a faint droplet's share came out too high; over a
// few pixels some sample holds dense water, while on a shaded sheet the
// neighbours' water is as shaded (docs/results/masks-2026-12-06b.md).
cv::Vec3f PurestWater(const WaterColourModel& colours,
                      const cv::Vec3f& scenery, const cv::Mat& wettest,
                      int x, int y, int radius) {
  cv::Vec3f deepest = wettest.at<cv::Vec3f>(y, x);
  float apart = L1(deepest, scenery);
  for (int v = std::max(0, y - radius);
       v <= std::min(wettest.rows - 1, y + radius); ++v)
    for (int u = std::max(0, x - radius);
         u <= std::min(wettest.cols - 1, x + radius); ++u) {
      const cv::Vec3f c = wettest.at<cv::Vec3f>(v, u);
      const float d = L1(c, scenery);
      if (d > apart) apart = d, deepest = c;
    }
  cv::Vec3f pure = colours.mean_water();
  float nearest = std::numeric_limits<float>::max();
  for (const cv::Vec3f& c : colours.palette()) {
    const cv::Vec3f e = c - deepest;
    if (e.dot(e) < nearest) nearest = e.dot(e), pure = c;
  }
  return pure;
}

// One pass of the matting with the given colour model: the mask of every
// frame. Calls progress(frames done).
std::vector<cv::Mat> MatFrames(const std::vector<ResidualFrame>& frames,
                               const std::vector<cv::Mat>& images,
                               const std::vector<cv::Mat>& regions,
                               const WaterColourModel& colours, int stride,
                               const WaterMattingOptions& options,
                               const std::function<void(int)>& progress) {
  const int n = static_cast<int>(frames.size());
  std::vector<cv::Mat> masks(n);
  const cv::Vec3f water = colours.mean_water();
  const cv::Mat grow = Disk(std::lround(options.grow * images[0].cols));
  const int radius = std::lround(options.water_radius * images[0].cols);
  std::vector<cv::Mat> samples, known;
  std::vector<cv::Vec3f> seen_colours;
  for (int i = 0; i < n; ++i) {
    const ResidualFrame& f = frames[i];
    samples.clear();
    known.clear();
    for (int j = i % stride; j < n; j += stride) {
      samples.emplace_back();
      known.emplace_back();
      CarryByCameraFlow(images[j],
                        CameraFlow(f.depth, f.camera, frames[j].camera),
                        &samples.back(), &known.back());
    }
    const cv::Mat& image = images[i];
    cv::Mat ratio = colours.LogRatio(image);
    cv::GaussianBlur(ratio, ratio, cv::Size(0, 0), 1.0);
    cv::Mat share(image.size(), CV_32FC1, cv::Scalar(0.f));
    cv::Mat seen(image.size(), CV_8UC1, cv::Scalar(0));
    cv::Mat scenery(image.size(), CV_32FC3), wettest(image.size(), CV_32FC3);
    const int m = static_cast<int>(samples.size());
    for (int p = 0; p < static_cast<int>(image.total()); ++p) {
      const cv::Vec3f colour = image.at<cv::Vec3f>(p);
      seen_colours.assign(1, colour);
      for (int k = 0; k < m; ++k)
        if (known[k].at<uchar>(p))
          seen_colours.push_back(samples[k].at<cv::Vec3f>(p));
      const cv::Vec3f behind = SceneryColour(seen_colours, water);
      scenery.at<cv::Vec3f>(p) = behind;
      if (colours.LogRatio(behind) < 0) seen.at<uchar>(p) = 255;
      // The pixel's wettest colour: its sample most unlike that scenery.
      cv::Vec3f wet = colour;
      float apart = L1(colour, behind);
      for (const cv::Vec3f& c : seen_colours)
        if (L1(c, behind) > apart) apart = L1(c, behind), wet = c;
      wettest.at<cv::Vec3f>(p) = wet;
    }
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const cv::Vec3f behind = scenery.at<cv::Vec3f>(y, x);
        const cv::Vec3f axis =
            PurestWater(colours, behind, wettest, x, y, radius) - behind;
        share.at<float>(y, x) = (image.at<cv::Vec3f>(y, x) - behind).dot(axis) /
                                std::max(axis.dot(axis), 1e-6f);
      }
    cv::GaussianBlur(share, share, cv::Size(0, 0), 0.5);
    cv::Mat by_share, by_colour, region;
    cv::compare(share, options.min_share, by_share, cv::CMP_GT);
    cv::compare(ratio, 0, by_colour, cv::CMP_GT);
    cv::dilate(regions[i], region, grow);
    const cv::Mat water_here = (by_share & seen) | (by_colour & ~seen);
    masks[i] = water_here & region;
    // Calm water (a still pool below a fall) can move and change too
    // little for the regions, but it is water-coloured in every frame,
    // hiding its scenery: such pixels connected to the water found are
    // water too. Scenery seen in any frame is not followed.
    if (options.calm_water)
      masks[i] = ConnectedTo(masks[i], masks[i] | (by_colour & ~seen));
    progress(i + 1);
  }
  return masks;
}

}  // namespace

std::vector<cv::Mat> MatWater(const std::vector<ResidualFrame>& frames,
                              const std::vector<cv::Mat>& images,
                              const std::vector<cv::Mat>& regions,
                              const WaterMattingOptions& options,
                              const std::function<void(int)>& progress) {
  CHECK_GT(options.stride, 0);
  CHECK_GT(options.max_samples, 0);
  const int n = static_cast<int>(frames.size());
  const int stride = std::max(
      options.stride, (n + options.max_samples - 1) / options.max_samples);
  CHECK_EQ(static_cast<int>(images.size()), n);
  CHECK_EQ(static_cast<int>(regions.size()), n);
  std::vector<cv::Mat> masks(n);
  if (n == 0) return masks;
  const int width = images[0].cols;
  const int inner = std::lround(options.inner * width);
  const int outer = std::lround(options.outer * width);
  // Progress over the passes (with calm water, two: the second where
  // some was found).
  const int passes = options.calm_water ? 2 : 1;
  int reported = 0;
  const auto report = [&](int pass, int done) {
    const int now = (pass * n + done) / passes;
    if (progress && now > reported) progress(reported = now);
  };
  masks = MatFrames(frames, images, regions,
                    WaterColourModel(images, regions, inner, outer), stride,
                    options, [&](int done) { report(0, done); });
  if (!options.calm_water) return masks;
  // The calm water found beyond the regions had taught the colour model
  // scenery (it lay outside them), which makes its colours look less like
  // water than they are: learn them again with it inside.
  const cv::Mat grow = Disk(std::lround(options.grow * width));
  std::vector<cv::Mat> wider(n);
  bool found = false;
  for (int i = 0; i < n; ++i) {
    cv::Mat near;
    cv::dilate(regions[i], near, grow);
    const cv::Mat beyond = masks[i] & ~near;
    found = found || cv::countNonZero(beyond) > 0;
    wider[i] = regions[i] | beyond;
  }
  if (!found) {
    report(1, n);
    return masks;
  }
  return MatFrames(frames, images, regions,
                   WaterColourModel(images, wider, inner, outer), stride,
                   options, [&](int done) { report(1, done); });
}

}  // namespace es
