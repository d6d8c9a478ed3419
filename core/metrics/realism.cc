#include "core/metrics/realism.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/metrics/random_direction.h"
#include "core/metrics/sorted_order.h"

namespace es {
namespace {

constexpr int kRegions = 3;  // water, static, frame
constexpr int kMinPatches = 16;
const double kNan = std::numeric_limits<double>::quiet_NaN();

cv::Mat Grey(const cv::Mat& frame) {
  cv::Mat f;
  frame.convertTo(f, CV_32F, frame.depth() == CV_8U ? 1.0 / 255 : 1.0);
  if (f.channels() == 1) return f;
  CHECK(f.channels() == 3 || f.channels() == 4) << f.channels();
  cv::Mat grey;
  cv::cvtColor(f, grey, f.channels() == 3 ? cv::COLOR_RGB2GRAY
                                          : cv::COLOR_RGBA2GRAY);
  return grey;
}

// Gaussian levels 0..levels and the Laplacian bands 0..levels-1 between.
struct Pyramid {
  std::vector<cv::Mat> gauss;
  std::vector<cv::Mat> bands;
};

Pyramid BuildPyramid(const cv::Mat& frame, int levels) {
  Pyramid p;
  p.gauss.push_back(Grey(frame));
  for (int l = 0; l < levels; ++l) {
    cv::Mat down, up;
    cv::pyrDown(p.gauss[l], down);
    cv::pyrUp(down, up, p.gauss[l].size());
    p.bands.push_back(p.gauss[l] - up);
    p.gauss.push_back(down);
  }
  return p;
}

// The water region of one frame (CV_8U, 255 = water): the mask > 0.5,
// dilated by `margin` times the image diagonal.
cv::Mat WaterRegion(const cv::Mat& mask, double margin) {
  cv::Mat m;
  mask.convertTo(m, CV_32F, mask.depth() == CV_8U ? 1.0 / 255 : 1.0);
  cv::Mat water = m > 0.5f;
  const int radius = static_cast<int>(
      std::lround(margin * std::hypot(mask.cols, mask.rows)));
  if (radius > 0) {
    cv::dilate(water, water,
               cv::getStructuringElement(
                   cv::MORPH_ELLIPSE,
                   cv::Size(2 * radius + 1, 2 * radius + 1)));
  }
  return water;
}

// Region masks (CV_8U, 255 = inside) of one frame at every level, from
// its water region.
using LevelMasks = std::vector<cv::Mat>;

std::array<LevelMasks, kRegions> RegionMasks(const cv::Mat& mask,
                                             const Pyramid& shape) {
  std::array<LevelMasks, kRegions> out;
  for (size_t l = 0; l < shape.bands.size(); ++l) {
    const cv::Size size = shape.bands[l].size();
    out[2].push_back(cv::Mat(size, CV_8U, cv::Scalar(255)));
    if (mask.empty()) continue;
    cv::Mat water = mask;
    if (l > 0) {
      cv::Mat m;
      mask.convertTo(m, CV_32F, 1.0 / 255);
      cv::resize(m, m, size, 0, 0, cv::INTER_AREA);
      water = m > 0.5f;
    }
    out[0].push_back(water);
    out[1].push_back(~water);
  }
  return out;
}

struct Patch {
  int t, x, y;
};

// Whether (t, x, y) lies in the region: the water (0), the static rest
// (1) or the whole frame (2).
bool InRegion(const std::vector<cv::Mat>& masks, int region, const Patch& p) {
  if (region == 2) return true;
  return (masks[p.t].at<uint8_t>(p.y, p.x) != 0) == (region == 0);
}

// `count` random positions (t < frames - 1, so a 3D patch has a next
// frame) inside the region, by rejection against the full-size masks; all
// of the region's positions where it has no more than `count`: drawing
// more would only repeat them.
std::vector<Patch> DrawPatches(const std::vector<cv::Mat>& masks, int region,
                               cv::Size size, int frames, int count,
                               std::mt19937_64* rng) {
  long long positions = 0;
  for (int t = 0; t + 1 < frames; ++t) {
    const long long inside =
        region == 2 ? size.area() : cv::countNonZero(masks[t]);
    positions += region == 1 ? size.area() - inside : inside;
  }
  std::vector<Patch> out;
  if (positions <= count) {
    for (int t = 0; t + 1 < frames; ++t)
      for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x)
          if (InRegion(masks, region, {t, x, y})) out.push_back({t, x, y});
    return out;
  }
  std::uniform_int_distribution<int> t_of(0, frames - 2);
  std::uniform_int_distribution<int> x_of(0, size.width - 1);
  std::uniform_int_distribution<int> y_of(0, size.height - 1);
  while (static_cast<int>(out.size()) < count) {
    const Patch p{t_of(*rng), x_of(*rng), y_of(*rng)};
    if (InRegion(masks, region, p)) out.push_back(p);
  }
  return out;
}

// Appends the 3x3 neighbourhood of `image` around full-size pixel (x, y)
// at pyramid level `level` (clamped at the border).
void AppendNeighbourhood(const cv::Mat& image, int level, int x, int y,
                         std::vector<float>* out) {
  const int cx = x >> level, cy = y >> level;
  for (int dy = -1; dy <= 1; ++dy) {
    const int yy = std::clamp(cy + dy, 0, image.rows - 1);
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = std::clamp(cx + dx, 0, image.cols - 1);
      out->push_back(image.at<float>(yy, xx));
    }
  }
}

// Feature vectors of one video's patches, row-major, `dims` per patch.
struct Features {
  int dims = 0;
  std::vector<float> values;
};

// Each Gaussian level's change from one frame to the next.
std::vector<cv::Mat> LevelChanges(const Pyramid& now, const Pyramid& next,
                                  int levels) {
  std::vector<cv::Mat> change;
  for (int l = 0; l < levels; ++l)
    change.push_back(next.gauss[l] - now.gauss[l]);
  return change;
}

// A patch's 2D features (the bands at frame t) and 3D ones (those and the
// levels' changes to frame t + 1).
void AppendPatchFeatures(const Pyramid& now,
                         const std::vector<cv::Mat>& change, const Patch& p,
                         Features* f2, Features* f3) {
  std::vector<float> v;
  for (size_t l = 0; l < now.bands.size(); ++l) {
    AppendNeighbourhood(now.bands[l], l, p.x, p.y, &v);
  }
  f2->dims = static_cast<int>(v.size());
  f2->values.insert(f2->values.end(), v.begin(), v.end());
  for (size_t l = 0; l < change.size(); ++l) {
    AppendNeighbourhood(change[l], l, p.x, p.y, &v);
  }
  f3->dims = static_cast<int>(v.size());
  f3->values.insert(f3->values.end(), v.begin(), v.end());
}

// Sliced Wasserstein-1 distance between two equally large point sets.
double SlicedWasserstein(const Features& a, const Features& b,
                         int projections, uint64_t seed) {
  CHECK_EQ(a.dims, b.dims);
  CHECK_EQ(a.values.size(), b.values.size());
  const int d = a.dims;
  const size_t n = a.values.size() / d;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<double> dir(d), pa(n), pb(n);
  SortedOrderScratch scratch;
  std::vector<int> order_a, order_b;
  double total = 0;
  for (int k = 0; k < projections; ++k) {
    DrawUnitDirection(&rng, &normal, &dir);
    for (size_t i = 0; i < n; ++i) {
      double sa = 0, sb = 0;
      for (int j = 0; j < d; ++j) {
        sa += dir[j] * a.values[i * d + j];
        sb += dir[j] * b.values[i * d + j];
      }
      pa[i] = sa;
      pb[i] = sb;
    }
    SortedOrder(pa.data(), static_cast<int>(n), 1, &scratch, &order_a);
    SortedOrder(pb.data(), static_cast<int>(n), 1, &scratch, &order_b);
    double w = 0;
    for (size_t i = 0; i < n; ++i)
      w += std::abs(pa[order_a[i]] - pb[order_b[i]]);
    total += w / n;
  }
  return total / projections;
}

struct Accumulator {
  std::vector<double> band_rendered, band_real;
  long long pixels = 0;
  double motion_rendered = 0, motion_real = 0;
  long long motion_pixels = 0;
  std::vector<Patch> patches;
  size_t next_patch = 0;  // patches are sorted by frame
  Features rendered2, real2, rendered3, real3;
};

// Sum of |image| over the mask's nonzero pixels.
double MaskedAbsSum(const cv::Mat& image, const cv::Mat& mask) {
  const int count = cv::countNonZero(mask);
  return count ? cv::mean(cv::abs(image), mask)[0] * count : 0.0;
}

double Ratio(double a, double b) { return b > 0 ? a / b : kNan; }

RealismRegion Finish(const Accumulator& acc, const RealismOptions& options,
                     uint64_t seed) {
  RealismRegion r;
  r.pixels = acc.pixels;
  if (acc.pixels == 0) {
    r.band_ratio.assign(options.levels, kNan);
    r.detail_ratio = r.motion_ratio = r.real_detail = r.real_motion = kNan;
    r.distance_2d = r.distance_3d = kNan;
    return r;
  }
  double sum = 0;
  int bands = 0;
  for (int l = 0; l < options.levels; ++l) {
    r.band_ratio.push_back(Ratio(acc.band_rendered[l], acc.band_real[l]));
    if (std::isfinite(r.band_ratio.back())) {
      sum += r.band_ratio.back();
      ++bands;
    }
  }
  r.detail_ratio = bands ? sum / bands : kNan;
  r.real_detail = acc.band_real[0] / acc.pixels;
  r.motion_ratio = Ratio(acc.motion_rendered, acc.motion_real);
  r.real_motion =
      acc.motion_pixels ? acc.motion_real / acc.motion_pixels : kNan;
  r.patches = static_cast<int>(acc.patches.size());
  if (r.patches < kMinPatches) {
    r.distance_2d = r.distance_3d = kNan;
  } else {
    r.distance_2d = SlicedWasserstein(acc.rendered2, acc.real2,
                                      options.projections, seed);
    r.distance_3d = SlicedWasserstein(acc.rendered3, acc.real3,
                                      options.projections, seed + 1);
  }
  return r;
}

}  // namespace

RealismMetrics ComputeRealism(const std::vector<cv::Mat>& rendered,
                              const std::vector<cv::Mat>& real,
                              const std::vector<cv::Mat>& masks,
                              const RealismOptions& options) {
  CHECK_GE(real.size(), 2u);
  CHECK_EQ(rendered.size(), real.size());
  CHECK(masks.empty() || masks.size() == real.size());
  CHECK_GE(options.levels, 1);
  const int frames = static_cast<int>(real.size());
  const cv::Size size = real[0].size();
  for (int t = 0; t < frames; ++t) {
    CHECK(real[t].size() == size && rendered[t].size() == size);
    CHECK(masks.empty() || masks[t].size() == size);
  }
  const bool has_masks = !masks.empty();
  std::vector<cv::Mat> water;  // CV_8U, 255 = the water region
  for (const cv::Mat& mask : masks)
    water.push_back(WaterRegion(mask, options.water_margin));

  std::mt19937_64 rng(options.seed);
  std::array<Accumulator, kRegions> acc;
  for (int r = 0; r < kRegions; ++r) {
    acc[r].band_rendered.assign(options.levels, 0.0);
    acc[r].band_real.assign(options.levels, 0.0);
    if (r < 2 && !has_masks) continue;
    acc[r].patches = DrawPatches(water, r, size, frames,
                                 options.patch_samples, &rng);
    std::sort(acc[r].patches.begin(), acc[r].patches.end(),
              [](const Patch& a, const Patch& b) { return a.t < b.t; });
  }

  // One pass over the frames, holding two pyramids per video.
  Pyramid prev_rendered, prev_real;
  std::array<LevelMasks, kRegions> prev_masks;
  for (int t = 0; t < frames; ++t) {
    Pyramid pr = BuildPyramid(rendered[t], options.levels);
    Pyramid pt = BuildPyramid(real[t], options.levels);
    std::array<LevelMasks, kRegions> region =
        RegionMasks(has_masks ? water[t] : cv::Mat(), pt);
    // Each level's change since the last frame, once per frame pair: the
    // motion sums and the 3D patches' features (once per patch made
    // es_eval take minutes at 1168x880).
    std::vector<cv::Mat> change_rendered, change_real;
    if (t > 0) {
      change_rendered = LevelChanges(prev_rendered, pr, options.levels);
      change_real = LevelChanges(prev_real, pt, options.levels);
    }
    for (int r = 0; r < kRegions; ++r) {
      if (region[r].empty()) continue;
      Accumulator& a = acc[r];
      a.pixels += cv::countNonZero(region[r][0]);
      for (int l = 0; l < options.levels; ++l) {
        const cv::Mat& m = region[r][l];
        a.band_rendered[l] += MaskedAbsSum(pr.bands[l], m);
        a.band_real[l] += MaskedAbsSum(pt.bands[l], m);
      }
      if (t == 0) continue;
      const cv::Mat both = prev_masks[r][0] & region[r][0];
      a.motion_pixels += cv::countNonZero(both);
      a.motion_rendered += MaskedAbsSum(change_rendered[0], both);
      a.motion_real += MaskedAbsSum(change_real[0], both);
      while (a.next_patch < a.patches.size() &&
             a.patches[a.next_patch].t == t - 1) {
        const Patch& p = a.patches[a.next_patch++];
        AppendPatchFeatures(prev_rendered, change_rendered, p, &a.rendered2,
                            &a.rendered3);
        AppendPatchFeatures(prev_real, change_real, p, &a.real2, &a.real3);
      }
    }
    prev_rendered = std::move(pr);
    prev_real = std::move(pt);
    prev_masks = std::move(region);
  }

  RealismMetrics m;
  m.water = Finish(acc[0], options, options.seed + 10);
  m.static_region = Finish(acc[1], options, options.seed + 10);
  m.frame = Finish(acc[2], options, options.seed + 10);
  return m;
}

}  // namespace es
