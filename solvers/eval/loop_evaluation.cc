#include "solvers/eval/loop_evaluation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <glog/logging.h>

#include "core/loop/cycle_time.h"
#include "core/loop/euler_chain.h"
#include "core/loop/frame_composer.h"
#include "core/loop/loop_renderer.h"
#include "solvers/eval/held_out_means.h"

namespace es {
namespace {

using Clock = std::chrono::steady_clock;

double Milliseconds(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start)
      .count();
}

cv::Mat WrapRgb(const RenderResult& r) {
  return cv::Mat(r.height, r.width, CV_64FC3,
                 const_cast<double*>(r.rgb.data()));
}

cv::Mat WrapRgb(const std::vector<double>& rgb, const Camera& camera) {
  return cv::Mat(camera.height, camera.width, CV_64FC3,
                 const_cast<double*>(rgb.data()));
}

}  // namespace

LoopMetrics EvaluateLoopModel(const LoopModel& model,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices,
                              ImageRasterizer* rasterizer) {
  return CompareWithFrames(
      RenderCompositions(model, frames, indices, rasterizer), frames,
      indices);
}

LoopMetrics EvaluateLoopModel(const LoopModel& model,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices,
                              const RenderOptions& options) {
  CpuImageRasterizer rasterizer(options);
  return EvaluateLoopModel(model, frames, indices, &rasterizer);
}

std::vector<cv::Mat> RenderCompositions(const LoopModel& model,
                                        const std::vector<Frame>& frames,
                                        const std::vector<int>& indices,
                                        ImageRasterizer* rasterizer) {
  const LoopModelView view = LoopModelView::Of(model);
  FrameComposer composer;
  std::vector<cv::Mat> images;
  for (int index : indices) {
    const Frame& f = frames[index];
    images.push_back(
        WrapRgb(rasterizer->Render(f.camera,
                                   composer.Compose(view, f.time_index)))
            .clone());
  }
  return images;
}

LoopMetrics CompareWithFrames(const std::vector<cv::Mat>& images,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices) {
  CHECK_EQ(images.size(), indices.size());
  HeldOutMeans means;
  for (size_t k = 0; k < indices.size(); ++k) {
    const Frame& f = frames[indices[k]];
    const cv::Mat& x = images[k];
    cv::Mat y;
    f.image.convertTo(y, CV_64F);
    means.Add(x, y, f.mask);
  }
  LoopMetrics out;
  means.WriteTo(static_cast<int>(indices.size()), &out);
  return out;
}

LoopSeamScore EvaluateLoopSeam(LoopFrames* loop, int cycle_length,
                               const Camera& camera, int cycles) {
  CHECK_GE(cycles, 1);
  std::vector<cv::Mat> frames;
  const int count = cycles * cycle_length + 1;
  loop->Start(0);
  for (int k = 0; k < count; ++k) {
    if (k > 0) loop->Advance();
    frames.push_back(WrapRgb(loop->Rgb(camera), camera).clone());
  }
  return ComputeLoopSeam(frames, cycle_length, 0);
}

LoopSeamScore EvaluateLoopSeam(const LoopModel& model, const Camera& camera,
                               int cycles, const RenderOptions& options) {
  CpuLoopFrames loop(&model, options);
  return EvaluateLoopSeam(&loop, model.cycle_length, camera, cycles);
}

AnimationTiming TimeAnimation(const LoopModel& model, const Camera& camera,
                              int frames, const RenderOptions& options) {
  CHECK_GT(frames, 0);
  const int n = model.num_dynamic();
  std::vector<double> x0(3 * static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < 3; ++j) {
      x0[3 * k + j] = model.gaussians.means[3 * model.dynamic_index[k] + j];
    }
  }
  AnimationTiming timing;
  timing.frames = frames;
  timing.num_dynamic = n;

  // Alg. 1: every frame from scratch.
  std::vector<std::vector<double>> alg1(frames);
  std::vector<int> steps(n);
  if (model.motion) {
    EulerChain chain(&*model.motion, EulerOptions());
    for (int f = 0; f < frames; ++f) {
      const Clock::time_point start = Clock::now();
      for (int k = 0; k < n; ++k) {
        steps[k] = CycleIndex(f, model.start_times[k], model.cycle_length);
      }
      alg1[f].resize(x0.size());
      chain.Forward(model.motion->params(), n, x0.data(), steps.data(),
                    alg1[f].data());
      timing.alg1_advect_ms += Milliseconds(start);
    }
  } else {
    std::fill(alg1.begin(), alg1.end(), x0);
  }

  // Alg. 2 through the renderer the animations use; rendering timed apart.
  LoopRenderer renderer(&model, options);
  for (int f = 0; f < frames; ++f) {
    Clock::time_point start = Clock::now();
    if (f == 0) {
      renderer.Start(0);
    } else {
      renderer.Advance();
    }
    // Start is Alg. 1 once; only the per-frame steps are Alg. 2's cost.
    if (f > 0) timing.alg2_advect_ms += Milliseconds(start);
    const std::vector<double>& x = renderer.positions();
    for (size_t i = 0; i < x.size(); ++i) {
      timing.max_position_difference = std::max(
          timing.max_position_difference, std::abs(x[i] - alg1[f][i]));
    }
    start = Clock::now();
    renderer.Render(camera);
    timing.render_ms += Milliseconds(start);
  }
  timing.alg1_advect_ms /= frames;
  timing.alg2_advect_ms /= std::max(1, frames - 1);
  timing.render_ms /= frames;
  return timing;
}

}  // namespace es
