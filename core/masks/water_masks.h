#ifndef EULERSPLAT_CORE_MASKS_WATER_MASKS_H_
#define EULERSPLAT_CORE_MASKS_WATER_MASKS_H_

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/io/scene.h"
#include "core/masks/mask_scores.h"
#include "core/masks/residual_change.h"
#include "core/masks/water_matting.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"

namespace es {

// Water masks found from the video itself, without a segmentation network.
// A static model fitted to all frames (no masks) explains everything that
// stands still; water is what it cannot explain:
//  - non-rigid motion: the optical flow to the next frame minus the flow the
//    camera motion induces over the static model's depth,
//  - change: how much the residual frame - static render at a surface point
//    differs from its residual a few frames earlier and later (see
//    ResidualChange). The residual alone (misfit) also fires on scenery a
//    short fit has not learned yet, but that misfit stays put over time;
//    water's changes.
//  - misfit |frame - static render| itself, at a fraction of its weight:
//    only a surface the model shows nothing like (a calm pool over known
//    ground) is water by misfit alone.
// Each cue is divided by its median over all pixels (the static majority's
// noise level); a pixel's evidence is the strongest of them (water shows
// either, e.g. slow water changes, fast thin water moves), averaged over a
// temporal window, thresholded (Otsu on the log, never below min_score),
// cleaned with morphology, voted over the same window, and small blobs are
// dropped. These regions are smooth; the masks within them are per pixel:
// where the water's share of the colour is over one half (with a margin:
// min_share), plus the calm water joined to them that is water-coloured in
// every frame (MatWater).
// Which cues the evidence takes (all by default; the others for measuring
// what each brings).
struct WaterCues {
  bool flow = true;
  bool change = true;
  bool misfit = true;
};

// A comma-separated list of cue names (flow, change, misfit) as WaterCues;
// throws InputError for an unknown name or an empty list.
WaterCues ParseWaterCues(const std::string& list);

struct WaterMaskOptions {
  WaterCues cues;
  int window = 2;            // frames on each side for averaging and voting
  double min_score = 2.0;    // evidence (x the median) that can be water
  double min_flow_level = 0.35;    // px per frame: optical flow noise
  double min_misfit_level = 0.02;  // [0, 1] range: fit noise (and change)
  double misfit_weight = 0.25;     // of the misfit cue, against the others
  // The misfit is that of the residual blurred over this radius (fraction
  // of the width): fine texture a short fit renders as its average leaves
  // a residual that averages out, a surface of another colour does not.
  // 0 (default): per pixel; blurring lowered the IoU on the sprays
  // (docs/results/masks-2026-12-05.md).
  double misfit_blur = 0;
  // The flow cue counts only as far as the next frame, carried by the
  // camera's motion, fails to explain the frame (with the change's
  // tolerance): optical flow goes wrong on fine repeating texture, where
  // the camera's motion still explains the colours. Off by default: a
  // smooth stream's colours change too little and it is lost.
  bool flow_needs_change = false;
  ResidualChangeOptions change;  // which frames the change compares
  double open_radius = 0.006;   // morphology radii, fraction of the width
  double close_radius = 0.015;
  double min_blob = 0.002;   // blobs below this fraction of the frame: gone
  // Below this mean water fraction the scene is called static.
  double min_water_fraction = 0.02;
  RenderOptions render;      // the static model's background
  // Then, within those regions, water per pixel by its share of the
  // colour (MatWater): a curtain of spray is droplets, not a sheet.
  bool matting = true;
  WaterMattingOptions matting_options;
};

struct WaterMaskResult {
  std::vector<cv::Mat> masks;     // per frame, CV_8UC1, 255 = water
  std::vector<cv::Mat> regions;   // before the matting (empty without)
  std::vector<cv::Mat> evidence;  // per frame, CV_32FC1, x the median
  double threshold = 0;           // on the evidence
  double water_fraction = 0;      // of the masks, mean over frames
  // The regions' water fraction >= min_water_fraction (the matting starts
  // from them).
  bool has_water = false;
};

// Masks for every frame of `scene` (at the frames' size), in its order.
// Consecutive frames are those one video frame apart (Frame::time_index);
// a frame with no neighbour one video frame away gets no flow cue, a pixel
// whose change is unknown (too few partner frames see it) no change cue.
// Calls
// progress(done, total) twice per frame (the cues, then the matting).
WaterMaskResult EstimateWaterMasks(
    const Scene& scene, const GaussianSet& static_model,
    const WaterMaskOptions& options,
    const std::function<void(int, int)>& progress = nullptr);

// A sheet a person can check masks with: `count` frames evenly spaced,
// each as the frame with its water tinted and its region outlined, beside
// the evidence map; labelled with the frame names. BGR 8-bit.
cv::Mat WaterMaskSheet(const Scene& scene, const WaterMaskResult& result,
                       int count);

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_WATER_MASKS_H_
