#ifndef EULERSPLAT_SOLVERS_EVAL_LOOP_EVALUATION_H_
#define EULERSPLAT_SOLVERS_EVAL_LOOP_EVALUATION_H_

#include <vector>

#include <opencv2/core.hpp>

#include "core/io/scene.h"
#include "core/loop/loop_frames.h"
#include "core/metrics/loop_seam.h"
#include "core/model/camera.h"
#include "core/loop/loop_model.h"
#include "core/render/image_rasterizer.h"
#include "core/render/rasterizer.h"

namespace es {

// Held-out quality of a looping model: each frame is composed at its time
// index (Alg. 1, t and p from its place in the video) and rendered. Means
// over frames; the water variants use the masks (> 0.5) and skip frames
// without water (NaN when none has any); psnr_static is the rest of the
// image (the scenery, which the loop should leave as Stage 1 fit it).
struct LoopMetrics {
  int frames = 0;
  double psnr = 0, ssim = 0;
  double psnr_water = 0, ssim_water = 0;
  double psnr_static = 0;
  // The scenery farther from the water than kFarSceneryDiagonals of the
  // image diagonal (held_out_means.h): what Stage 3 should not change.
  double psnr_far_scenery = 0;
};

// `rasterizer` renders the compositions (CPU or device); the options
// overload renders on the CPU.
LoopMetrics EvaluateLoopModel(const LoopModel& model,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices,
                              ImageRasterizer* rasterizer);
LoopMetrics EvaluateLoopModel(const LoopModel& model,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices,
                              const RenderOptions& options);

// The images EvaluateLoopModel measures: frames[indices[k]]'s composition
// (Alg. 1 at its time index) seen by its camera, CV_64FC3, RGB.
std::vector<cv::Mat> RenderCompositions(const LoopModel& model,
                                        const std::vector<Frame>& frames,
                                        const std::vector<int>& indices,
                                        ImageRasterizer* rasterizer);

// The same figures for given images: images[k] (CV_64FC3, RGB in [0, 1])
// against frames[indices[k]].
LoopMetrics CompareWithFrames(const std::vector<cv::Mat>& images,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices);

// Loop-seam score (core/metrics/loop_seam.h) of a fixed-view animation of
// `cycles` loops (cycles * L + 1 frames from frame 0, Alg. 2, p = 0) seen
// by `camera`. `loop` plays the model (CPU or device; LoopFrames); the
// options overload plays it on the CPU.
LoopSeamScore EvaluateLoopSeam(LoopFrames* loop, int cycle_length,
                               const Camera& camera, int cycles);
LoopSeamScore EvaluateLoopSeam(const LoopModel& model, const Camera& camera,
                               int cycles, const RenderOptions& options);

// Per-frame cost of playing the model both ways, in milliseconds: Alg. 1
// re-integrates every dynamic Gaussian from its canonical position (t Euler
// steps each, O(N L) per frame), Alg. 2 advances the previous frame by one
// step (O(N)). Composition (D, p = 0) and rasterization are the same for
// both and timed once. Also checks the two agree. On the CPU only: the
// figures are the CPU's cost, and the positions compared stay on the host.
struct AnimationTiming {
  int frames = 0;
  int num_dynamic = 0;
  double alg1_advect_ms = 0;
  double alg2_advect_ms = 0;
  double render_ms = 0;  // compose + rasterize
  double alg1_frame_ms() const { return alg1_advect_ms + render_ms; }
  double alg2_frame_ms() const { return alg2_advect_ms + render_ms; }
  // Largest |x_alg1 - x_alg2| over Gaussians and frames (world units).
  double max_position_difference = 0;
};

AnimationTiming TimeAnimation(const LoopModel& model, const Camera& camera,
                              int frames, const RenderOptions& options);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_LOOP_EVALUATION_H_
