#include "solvers/eval/realism_evaluation.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>

#include <glog/logging.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/base/atomic_file.h"
#include "costs/water_input_noise.h"
#include "solvers/eval/loop_evaluation.h"

namespace es {

std::vector<cv::Mat> RenderAtInputCameras(LoopFrames* loop,
                                          const std::vector<Frame>& frames) {
  std::vector<cv::Mat> out;
  // Each frame at its place in the video: frames COLMAP did not register
  // are stepped over, not closed up.
  int time = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (i == 0 || frames[i].time_index < time) {
      time = frames[i].time_index;
      loop->Start(time);
    }
    for (; time < frames[i].time_index; ++time) loop->Advance();
    const Camera& camera = frames[i].camera;
    out.push_back(cv::Mat(camera.height, camera.width, CV_64FC3,
                          const_cast<double*>(loop->Rgb(camera).data()))
                      .clone());
  }
  return out;
}

std::vector<cv::Mat> RenderTrainingComposition(
    const LoopModel& model, const std::vector<Frame>& frames,
    ImageRasterizer* rasterizer) {
  std::vector<int> all(frames.size());
  std::iota(all.begin(), all.end(), 0);
  return RenderCompositions(model, frames, all, rasterizer);
}

RealismMetrics EvaluateRealism(const std::vector<cv::Mat>& rendered,
                               const std::vector<Frame>& frames,
                               const RealismOptions& realism,
                               const std::array<double, 3>& input_noise) {
  CHECK_GE(frames.size(), 2u);
  CHECK_EQ(rendered.size(), frames.size());
  std::vector<cv::Mat> noisy;  // copies only when there is noise to draw
  if (HasInputNoise(input_noise)) {
    for (size_t i = 0; i < rendered.size(); ++i) {
      noisy.push_back(rendered[i].clone());
      DrawInputNoise(input_noise, realism.seed * 1000003 + i, &noisy.back());
    }
  }
  std::vector<cv::Mat> real, masks;
  bool has_masks = true;
  for (const Frame& f : frames) {
    real.push_back(f.image);
    masks.push_back(f.mask);
    has_masks = has_masks && !f.mask.empty();
  }
  if (!has_masks) masks.clear();
  return ComputeRealism(noisy.empty() ? rendered : noisy, real, masks,
                        realism);
}

void WriteComparisonFrames(const std::vector<cv::Mat>& rendered,
                           const std::vector<Frame>& frames, int count,
                           const std::string& dir) {
  CHECK_EQ(rendered.size(), frames.size());
  const int n = static_cast<int>(frames.size());
  count = std::min(count, n);
  std::vector<int> indices;
  std::vector<cv::Mat> chosen;
  for (int k = 0; k < count; ++k) {
    indices.push_back(count > 1 ? k * (n - 1) / (count - 1) : 0);
    chosen.push_back(rendered[indices.back()]);
  }
  WriteSideBySideFrames(chosen, frames, indices, dir);
}

void WriteSideBySideFrames(const std::vector<cv::Mat>& rendered,
                           const std::vector<Frame>& frames,
                           const std::vector<int>& indices,
                           const std::string& dir) {
  CHECK_EQ(rendered.size(), indices.size());
  std::filesystem::create_directories(dir);
  for (size_t k = 0; k < indices.size(); ++k) {
    const int i = indices[k];
    cv::Mat side, out;
    cv::Mat input;
    frames[i].image.convertTo(input, CV_64FC3);
    cv::hconcat(rendered[k], input, side);
    side.convertTo(out, CV_8UC3, 255.0);
    cv::cvtColor(out, out, cv::COLOR_RGB2BGR);
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%06d.png", i);
    std::vector<uchar> png;
    cv::imencode(".png", out, png);
    WriteFileAtomically(dir + name, [&png](std::ofstream& file) {
      file.write(reinterpret_cast<const char*>(png.data()), png.size());
    });
  }
}

}  // namespace es
