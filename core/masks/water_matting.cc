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

// The scenery behind a pixel, from its colours over time (the frame's
// own first). Without `recurrence`: the colour least like water. With it:
// the least water-like colour that recurs, i.e. that at least that share
// of the colours lie within `recurrence_tolerance` of (the mean of those):
// the scenery is seen whenever the water leaves it, the water changes, and
// one stray sample (a misregistered edge of fine texture) is not the
// scenery. When no colour recurs that often, the most recurrent one.
// far, order: scratch.
cv::Vec3f SceneryColour(const std::vector<cv::Vec3f>& colours,
                        const cv::Vec3f& water,
                        const WaterMattingOptions& options,
                        std::vector<float>* far, std::vector<int>* order) {
  const int m = static_cast<int>(colours.size());
  if (options.recurrence <= 0) {
    cv::Vec3f scenery = colours[0];
    float farthest = L1(colours[0], water);
    for (int k = 1; k < m; ++k) {
      const float d = L1(colours[k], water);
      if (d > farthest) farthest = d, scenery = colours[k];
    }
    return scenery;
  }
  far->resize(m);
  order->resize(m);
  for (int k = 0; k < m; ++k) {
    (*far)[k] = L1(colours[k], water);
    (*order)[k] = k;
  }
  std::sort(order->begin(), order->end(),
            [&](int a, int b) { return (*far)[a] > (*far)[b]; });
  const int needed =
      std::max(1, static_cast<int>(std::ceil(options.recurrence * m)));
  const float tolerance = static_cast<float>(options.recurrence_tolerance);
  cv::Vec3f mode = colours[0];
  int mode_count = 0;
  for (int k : *order) {
    cv::Vec3f sum(0.f, 0.f, 0.f);
    int count = 0;
    for (const cv::Vec3f& c : colours)
      if (L1(c, colours[k]) <= tolerance) sum += c, ++count;
    const cv::Vec3f mean = sum / static_cast<float>(count);
    if (count >= needed) return mean;
    if (count > mode_count) mode_count = count, mode = mean;
  }
  return mode;
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
  std::vector<cv::Mat> samples, known;
  std::vector<cv::Vec3f> seen_colours;
  std::vector<float> far;
  std::vector<int> order;
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
    const int m = static_cast<int>(samples.size());
    for (int p = 0; p < static_cast<int>(image.total()); ++p) {
      const cv::Vec3f colour = image.at<cv::Vec3f>(p);
      seen_colours.assign(1, colour);
      for (int k = 0; k < m; ++k)
        if (known[k].at<uchar>(p))
          seen_colours.push_back(samples[k].at<cv::Vec3f>(p));
      const cv::Vec3f scenery =
          SceneryColour(seen_colours, water, options, &far, &order);
      if (colours.LogRatio(scenery) < 0) seen.at<uchar>(p) = 255;
      // The water: the sample most unlike that scenery, as a palette colour.
      cv::Vec3f wettest = colour;
      float apart = L1(colour, scenery);
      for (int k = 0; k < m; ++k) {
        if (!known[k].at<uchar>(p)) continue;
        const cv::Vec3f s = samples[k].at<cv::Vec3f>(p);
        const float d = L1(s, scenery);
        if (d > apart) apart = d, wettest = s;
      }
      cv::Vec3f pure = water;
      float nearest = std::numeric_limits<float>::max();
      for (const cv::Vec3f& c : colours.palette()) {
        const cv::Vec3f e = c - wettest;
        if (e.dot(e) < nearest) nearest = e.dot(e), pure = c;
      }
      const cv::Vec3f axis = pure - scenery;
      share.at<float>(p) =
          (colour - scenery).dot(axis) / std::max(axis.dot(axis), 1e-6f);
    }
    cv::GaussianBlur(share, share, cv::Size(0, 0), 0.5);
    cv::Mat by_share, by_colour, region;
    cv::compare(share, 0.5, by_share, cv::CMP_GT);
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
