#ifndef EULERSPLAT_COSTS_WATER_TEXTURE_LOSS_H_
#define EULERSPLAT_COSTS_WATER_TEXTURE_LOSS_H_

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/metrics/sorted_order.h"
#include "costs/input_cache.h"
#include "costs/water_image_filters.h"
#include "costs/water_kernels.h"

namespace es {

struct WaterTextureOptions {
  double weight = 0;    // 0: off
  int bands = 2;        // difference-of-Gaussians bands, finest first
  int projections = 16; // random directions per evaluation
  double sigma = 1.0;   // pixels: G_0; band k's blurs are 2^k times wider
  // Std of the input's per-pixel noise on each opponent channel
  // (costs/water_input_noise.h): white noise of this std is drawn onto
  // the render's channels before its bands are taken, so the render is
  // compared as the camera would have filmed it and is not asked to
  // paint the noise.
  std::array<double, 3> input_noise = {0, 0, 0};
  // What each input's water pixels, their neighbourhoods and the input's
  // bands may keep between calls (costs/input_cache.h): every frame's of
  // a 224 x 168 clip of 54 training frames with 40% water takes 117 MB.
  size_t input_cache_bytes = size_t{128} << 20;
};

namespace internal {
// What the loss takes from an input and its mask alone: the water pixels'
// indices, their 3 x 3 neighbourhoods per band level (taps[k][9 i + o],
// pixel indices) and the input's bands, channel-major.
struct TextureInputs {
  std::vector<int> water;
  std::vector<std::vector<int>> taps;
  std::vector<std::vector<double>> bands;
};
}  // namespace internal

// A loss on the distribution of the water's texture rather than its
// pixels or its local energy (costs/water_energy_loss.h matches how much
// texture each neighbourhood has, not what it looks like). Every water
// pixel of a frame gets a feature vector: on each opponent colour channel
// and each band k of a difference-of-Gaussians pyramid (band 0 = y - G_0 *
// y, band k = G_{k-1} * y - G_k * y, G_k of sigma 2^k pixels), the band's
// 3 x 3 neighbourhood at a spacing of 2^k pixels (clamped borders). The
// loss is the sliced Wasserstein-1 distance between the rendered frame's
// and the input frame's sets of vectors over the same pixels: for each
// of `projections` random unit directions, both sets' projections are
// sorted and matched by rank, and the loss is the mean |difference|. It is
// zero when the two sets are equal as sets, wherever each streak is, and
// grows for a blur (fewer large band values) and for texture of the wrong
// shape or orientation (the neighbourhoods). As in texture synthesis by
// sliced Wasserstein losses, each evaluation draws new directions; `draw`
// picks them, so a resumed run sees the same ones.
//
// Reuses its buffers between calls, so not thread-safe.
class WaterTextureLoss {
 public:
  explicit WaterTextureLoss(const WaterTextureOptions& options);

  const WaterTextureOptions& options() const { return options_; }

  // Feature length: 3 channels x bands x 9.
  int dims() const;

  // rendered: H x W x 3 row-major RGB doubles; input: CV_32FC3 or CV_64FC3
  // RGB in [0, 1] of the same size; mask: empty (every pixel) or CV_32FC1
  // / CV_64FC1 in [0, 1] (> 0.5 = water). Returns weight * scale * the
  // distance (0 with fewer than 2 water pixels); if d_rendered is not null,
  // weight * scale * d distance / d rendered is added to it (+=).
  double Evaluate(const double* rendered, const cv::Mat& input,
                  const cv::Mat& mask, double scale, uint64_t draw,
                  double* d_rendered);

 private:
  // The bands of every channel of one RGB image, channel-major; with
  // `noise` set, input_noise is drawn from it onto each channel first.
  void Bands(const double* rgb, std::mt19937_64* noise,
             std::vector<std::vector<double>>* bands);

  // The water pixels of mask_ (w_ x h_), their taps and the input's bands.
  void FindInputs(const cv::Mat& input, internal::TextureInputs* out);

  // The kernels' view of `bands` (rendered or input), the taps and the
  // directions.
  TextureProjection Projection(const std::vector<std::vector<double>>& bands);

  // Every water pixel's projection on every direction: n x projections.
  void Project(const std::vector<std::vector<double>>& bands,
               std::vector<double>* out);

  WaterTextureOptions options_;
  std::vector<std::vector<double>> kernels_;  // G_k
  int w_ = 0, h_ = 0;
  InputCache<internal::TextureInputs> inputs_;
  const internal::TextureInputs* inputs_now_ = nullptr;  // this call's
  std::vector<const double*> band_pointers_;
  std::vector<const int*> tap_pointers_;
  // Scratch, reused.
  cv::Mat input_;
  std::vector<double> mask_;
  // Per opponent channel (they run in parallel): the channel or its
  // gradient, and its blurs' scratch.
  struct ChannelWork {
    std::vector<double> channel, low, coarse;
    internal::BlurScratch blur;
  };
  std::array<ChannelWork, 3> channels_;
  std::vector<std::vector<double>> rendered_bands_, d_bands_;
  Eigen::MatrixXd directions_;  // dims x projections, unit columns
  // n x projections, column-major; vectors, so that a frame with more
  // water pixels than the last reuses their memory.
  std::vector<double> proj_r_, proj_i_, d_proj_;
  // Per direction, the input's sorted projections and the render's rank
  // order (one per thread at a time).
  struct DirectionSort {
    SortedOrderScratch scratch;
    std::vector<double> input_sorted;
    std::vector<int> rendered_order;
  };
  std::vector<DirectionSort> sorts_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_TEXTURE_LOSS_H_
