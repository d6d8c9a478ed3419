#ifndef EULERSPLAT_CORE_METRICS_REALISM_H_
#define EULERSPLAT_CORE_METRICS_REALISM_H_

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace es {

// Does a rendered video look and move like the real one? PSNR rewards the
// temporal mean of stochastic water (a smooth sheet); these figures do not.
// All are computed on the grey image, offline, without learned weights:
//
// - detail: mean |band| of each band of a Laplacian pyramid (finest first),
//   rendered / real; detail_ratio is the mean over bands (1 = as much
//   high-frequency energy as the input, a blur scores < 1).
// - motion: mean |I(t+1) - I(t)| over consecutive frames, rendered / real
//   (a frozen video scores 0).
// - distribution distance: sliced Wasserstein-1 distance between the sets
//   of feature vectors of random patches of the two videos (our offline
//   stand-in for FID / FVD). A 2D patch at (x, y, t) is the 3x3
//   neighbourhood of every Laplacian band around (x, y) in frame t; a 3D
//   (x, y, t) patch adds the 3x3 neighbourhood of the temporal difference
//   G(t+1) - G(t) of every Gaussian level. Both videos are sampled at the
//   same patch positions, so identical videos are at distance 0; the
//   distance compares the distributions (sorted projections), not pairs.
//
// Each figure is computed inside a region: the water (the real frame's
// mask > 0.5, widened by RealismOptions::water_margin), the static rest as
// a control, and the whole frame.

struct RealismOptions {
  int levels = 3;            // Laplacian bands (and Gaussian levels)
  // Random patches per region, or every position of a region with no more
  // than that. Fewer inflate the distances of close videos: on our 160x120
  // scenes a model's ratio to the static-only model's distance moves by
  // 0.02-0.05 from 4096 to 16384 patches and by <= 0.02 from there to
  // 65536.
  int patch_samples = 65536;
  int projections = 64;      // sliced-Wasserstein directions
  uint64_t seed = 0;         // patch positions and directions
  // The water region is the mask dilated by this fraction of the image
  // diagonal (0: the mask itself), the static region the rest. A mask that
  // outlines single droplets selects where the input has spray at that
  // moment: another, equally real draw of the spray scores 1.4x the motion
  // there and a large distance (es_synth droplets, es_compare). 2% of the
  // diagonal covers the gaps between droplets, and that draw then scores
  // 1.0; on sheets of water (mask = region) nothing changes.
  double water_margin = 0.02;
};

struct RealismRegion {
  // Region pixels summed over frames; 0: the region is empty and every
  // figure below is NaN.
  long long pixels = 0;
  std::vector<double> band_ratio;  // per band, finest first
  double detail_ratio = 0;
  double motion_ratio = 0;
  double real_detail = 0;  // mean |finest band| of the real video
  double real_motion = 0;  // mean |I(t+1) - I(t)| of the real video
  int patches = 0;         // patches drawn (fewer when the region is small)
  double distance_2d = 0;
  double distance_3d = 0;
};

struct RealismMetrics {
  RealismRegion water;   // empty without masks
  RealismRegion static_region;  // empty without masks
  RealismRegion frame;   // every pixel
};

// rendered[t] and real[t] show the same camera at the same time; all
// frames have one size, any channel count (RGB order), 8-bit (0..255) or
// float (0..1). masks: empty, or one per frame (single channel, float in
// [0, 1] or 8-bit, > 0.5 resp. > 127 = water). Needs >= 2 frames.
RealismMetrics ComputeRealism(const std::vector<cv::Mat>& rendered,
                              const std::vector<cv::Mat>& real,
                              const std::vector<cv::Mat>& masks,
                              const RealismOptions& options = {});

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_REALISM_H_
