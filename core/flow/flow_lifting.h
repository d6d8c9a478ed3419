#ifndef EULERSPLAT_CORE_FLOW_FLOW_LIFTING_H_
#define EULERSPLAT_CORE_FLOW_FLOW_LIFTING_H_

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/flow/optical_flow.h"
#include "core/io/scene.h"
#include "core/model/camera.h"
#include "core/render/rasterizer.h"

namespace es {

// A pseudo ground-truth scene-flow pair for pretraining V: the point x (world)
// seen in water at frame i moves by v (world units per frame): its motion to
// frame i + gap divided by the gap. Optical flow does not see motion along
// camera i's line of sight: a sample whose v has none by construction (the
// facing-plane second end) records that line as `unseen`, and the
// scene-flow losses weight the residual along it by 1 - |unseen|^2: a unit
// vector leaves V's component along it free, a shorter one pulls it toward
// v's partly. Zero: v holds in all three components.
struct SceneFlowSample {
  Eigen::Vector3d x;
  Eigen::Vector3d v;
  Eigen::Vector3d unseen = Eigen::Vector3d::Zero();
};

// A render map (core/render/render_maps.h) as a CV_32FC1 image.
cv::Mat FloatImage(const RenderResult& render,
                   const std::vector<double>& map);

// Where the second end x' of a sample lies on the ray of frame i + 1
// through p + f(p).
enum class SecondEnd {
  // Where that ray meets the plane through x facing camera i: the sample
  // has no motion along camera i's line of sight, which 2D flow does not
  // observe. Default: differencing two rendered depths of a time-averaged
  // water surface turns its roughness into large spurious motion along the
  // ray (measured on es_synth water: most of the lifted samples' error).
  kFacingPlane,
  // At the static model's rendered depth of frame i + 1 there: keeps
  // motion toward / away from the camera where that depth is reliable.
  kRenderedDepth,
};
// Flag spellings plane, depth; Parse throws InputError on others.
SecondEnd ParseSecondEnd(const std::string& name);
const char* SecondEndName(SecondEnd end);

struct LiftingOptions {
  int stride = 2;                  // sample every stride-th pixel and row
  SecondEnd second_end = SecondEnd::kFacingPlane;
  double max_fb_error_px = 1.0;    // |f(x) + b(x + f(x))| above this: reject
  // (max - min) / min of the depth in the 3x3 neighbourhood above this:
  // the pixel straddles an occluding edge, its depth is a blend; reject.
  double max_rel_depth_jump = 0.05;
  double water_threshold = 0.5;    // water mask value that counts as water
  // Video frames between the two ends; samples are motion per frame (the
  // displacement divided by this).
  int frame_gap = 1;
  // Facing-plane samples record camera i's line of sight as unseen, so that
  // fitting V to them does not pull its motion along that line to zero:
  // the residual along it keeps this weight, stored as |unseen| =
  // sqrt(1 - weight). 0: free; 1: no unseen line, the samples claim no
  // motion along it (the behaviour before, for ablations).
  double line_of_sight_weight = 0.0;
};

// Why candidates were dropped (a candidate is a water pixel of frame i on the
// stride grid).
struct LiftingStats {
  long candidates = 0;
  long no_depth = 0;        // no surface at either end
  long depth_edge = 0;      // depth discontinuity at either end
  long outside = 0;         // flow leaves the image
  long inconsistent = 0;    // forward-backward check failed
  long not_water = 0;       // lands outside the water of frame i + 1
  long accepted = 0;

  void Add(const LiftingStats& other);
};

// One frame's inputs: its camera, expected depth (FloatImage of ExpectedDepth)
// and water mask (CV_32FC1 in [0, 1]), all the same size.
struct LiftingView {
  const Camera* camera = nullptr;
  cv::Mat depth;
  cv::Mat water;
};

// Lifts the flow between frames `first` (i) and `second` (i + gap) to 3D:
// x = unproject(p, depth_i), x' on the second camera's ray through p + f(p)
// as options.second_end says, sample (x, (x' - x) / options.frame_gap).
// second.depth is only read for kRenderedDepth. Appends the accepted
// samples to *samples; adds the counts to *stats when not null.
void LiftFlow(const LiftingView& first, const LiftingView& second,
              const FlowPair& flow, const LiftingOptions& options,
              std::vector<SceneFlowSample>* samples, LiftingStats* stats);

// Where the water pixels come from.
enum class WaterSource {
  kAuto,   // the scene's masks if it has them, else the model
  kMasks,  // masks/ (InputError if the scene has none)
  kModel,  // the static model's rendered dynamic probability
};
// Flag spellings auto, masks, model; Parse throws InputError on others.
WaterSource ParseWaterSource(const std::string& name);

// What the optical flow is computed on.
enum class FlowImage {
  kFrame,        // the video frames
  // Each frame minus the static model's render of it (plus gray): the
  // time-averaged part, water blobs and the scenery seen through them,
  // is gone, so the flow follows the moving texture alone instead of
  // being pulled toward the still background it is blended with.
  kFluctuation,
};
// Flag spellings frame, fluctuation; Parse throws InputError on others.
FlowImage ParseFlowImage(const std::string& name);
const char* FlowImageName(FlowImage image);

// kFluctuation's image: frame - render.rgb + 0.5 per channel, clamped to
// [0, 1] (CV_32FC3; frame is CV_32FC3 RGB of the render's size).
cv::Mat Fluctuation(const cv::Mat& frame, const RenderResult& render);

struct SceneFlowOptions {
  FlowMethod method = FlowMethod::kDisMedium;
  FlowImage image = FlowImage::kFrame;
  // The static model's render: its background must be the training one
  // for kFluctuation.
  RenderOptions render;
  LiftingOptions lifting;
  double min_alpha = 0.5;  // depth is valid where the rendered alpha exceeds
  WaterSource water = WaterSource::kAuto;
  // Held-out frames stay unseen unless this is set.
  bool use_test_frames = false;
  // Called after each frame pair with its index, the pair count, the two
  // image names and the samples it gave.
  std::function<void(int, int, const std::string&, const std::string&,
                     long)>
      progress;
};

struct SceneFlowResult {
  std::vector<SceneFlowSample> samples;
  LiftingStats stats;
  int num_pairs = 0;       // frame pairs (frame_gap apart in time) lifted
  int num_dry_pairs = 0;   // of those, without water: flow not computed
  bool used_masks = false;
  double render_seconds = 0, flow_seconds = 0, lift_seconds = 0;
};

// Stage 2's sample collection: for every pair of frames (i, i + gap) both
// used for training (gap = options.lifting.frame_gap video frames),
// renders the static model's expected depth (and, without masks, its
// dynamic probability) at both frames, computes the flow both ways and
// lifts it. Throws InputError when masks are asked for but
// missing, or no frame pair is usable.
SceneFlowResult LiftSceneFlow(const Scene& scene, const GaussianSet& model,
                              const SceneFlowOptions& options);

}  // namespace es

#endif  // EULERSPLAT_CORE_FLOW_FLOW_LIFTING_H_
