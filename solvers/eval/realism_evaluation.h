#ifndef EULERSPLAT_SOLVERS_EVAL_REALISM_EVALUATION_H_
#define EULERSPLAT_SOLVERS_EVAL_REALISM_EVALUATION_H_

#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/io/scene.h"
#include "core/loop/loop_frames.h"
#include "core/metrics/realism.h"
#include "core/loop/loop_model.h"
#include "core/render/image_rasterizer.h"

namespace es {

// The looping model played with Alg. 2 (p = 0) by `loop` (its frames on
// the CPU or a device) and seen by every input camera: element i is the
// loop at frames[i].time_index (its place in the video) rendered at
// frames[i]'s camera (CV_64FC3, RGB). Training and held-out frames alike.
std::vector<cv::Mat> RenderAtInputCameras(LoopFrames* loop,
                                          const std::vector<Frame>& frames);

// What training optimizes at the same cameras: Alg. 1 at each frame's
// true place in the video, D with its true cycle number (the loop above
// plays every cycle with p = 0), composed on the host and rendered by
// `rasterizer`.
std::vector<cv::Mat> RenderTrainingComposition(
    const LoopModel& model, const std::vector<Frame>& frames,
    ImageRasterizer* rasterizer);

// core/metrics/realism.h of that video against the input frames, inside
// the input's water masks (when the scene has them), the static rest and
// the whole frame. `input_noise` (per opponent channel,
// costs/water_input_noise.h) is drawn onto a copy of each rendered frame
// first (seeded by realism.seed and the frame): the input's detail and
// change include its noise, a render's do not.
RealismMetrics EvaluateRealism(const std::vector<cv::Mat>& rendered,
                               const std::vector<Frame>& frames,
                               const RealismOptions& realism = {},
                               const std::array<double, 3>& input_noise = {});

// Writes `count` frames spread over the video as DIR/frame_NNNNNN.png,
// rendered (left) beside the input (right), 8-bit RGB: to look at.
void WriteComparisonFrames(const std::vector<cv::Mat>& rendered,
                           const std::vector<Frame>& frames, int count,
                           const std::string& dir);

// The same for chosen frames: rendered[k] beside frames[indices[k]] as
// DIR/frame_NNNNNN.png, NNNNNN = indices[k].
void WriteSideBySideFrames(const std::vector<cv::Mat>& rendered,
                           const std::vector<Frame>& frames,
                           const std::vector<int>& indices,
                           const std::string& dir);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_REALISM_EVALUATION_H_
