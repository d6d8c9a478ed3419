#ifndef EULERSPLAT_CORE_MASKS_WATER_MATTING_H_
#define EULERSPLAT_CORE_MASKS_WATER_MATTING_H_

#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/masks/colour_model.h"
#include "core/masks/residual_change.h"

namespace es {

struct WaterMattingOptions {
  int stride = 2;        // every stride-th frame is a sample of each pixel
  int max_samples = 60;  // more frames: a longer stride (the cost is
                         // frames x samples)
  double grow = 0.05;    // the region grows by this fraction of the width
  double inner = 0.01;   // colour model: water this far inside a region,
  double outer = 0.025;  // scenery this far outside (fractions of width)
  // Beyond the grown regions, also the pixels water-coloured in every
  // sample (calm water) that connect to the water found.
  bool calm_water = true;
  // A pixel whose scenery was seen is water where the water's share of
  // its colour passes this: above the true masks' one half, as the share
  // is blurred and droplets' edges took the blur (measured:
  // docs/results/masks-2026-12-06b.md).
  double min_share = 0.55;
  // The water a share is measured against: the palette colour nearest the
  // wettest colour of the pixels within this radius (fraction of the
  // width; 0: the pixel's own).
  double water_radius = 0.01;
};

// Per-frame water masks at the resolution of single droplets, inside
// regions found by motion and change (which are smooth over space and time
// and so cover a whole curtain of spray, droplets and the gaps between
// them alike). A pixel is water where the water's share of its colour
// passes min_share: colour = share * water + (1 - share) * scenery behind.
//  - The scenery behind: of the pixel's surface point seen in every
//    stride-th frame (carried by the camera's motion over the static
//    depth), the colour least like water. Where water hides the scenery in
//    every frame, that colour is still water's (the colour model says so):
//    the pixel's own colour decides, water-like or not.
//  - The water: the palette colour (a pool's blue, a spray's white)
//    nearest the sample most unlike that scenery among those of the
//    pixels within water_radius: a translucent droplet's own wettest
//    sample is often a blend with the scenery, a neighbour's in some
//    frame dense water.
// With calm_water, the masks also take the pixels beyond the grown regions
// that are water-coloured in every sample (a still pool hides its scenery
// in every frame but moves too little for the regions) and connect to the
// water found; a second pass then learns the colour model again with that
// calm water counted as water, not as scenery.
// frames: the residual frames' cameras, depth and time (residual unused);
// images: CV_32FC3 in [0, 1]; regions: CV_8UC1, 255 = water. Returns
// CV_8UC1 masks, 255 = water. Calls progress(frames done) per frame.
std::vector<cv::Mat> MatWater(
    const std::vector<ResidualFrame>& frames,
    const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& regions,
    const WaterMattingOptions& options,
    const std::function<void(int)>& progress = nullptr);

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_WATER_MATTING_H_
