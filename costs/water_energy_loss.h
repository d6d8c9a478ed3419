#ifndef EULERSPLAT_COSTS_WATER_ENERGY_LOSS_H_
#define EULERSPLAT_COSTS_WATER_ENERGY_LOSS_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "costs/input_cache.h"
#include "costs/water_energy_terms.h"
#include "costs/water_image_filters.h"

namespace es {

namespace internal {
// What the loss takes from its inputs alone, per opponent channel c:
// energies[c][t] is the input's motion energy of a pair, W_0 * (y_B -
// y_A)^2 (t = 0), or a frame's detail energy of band t, W_t * band_t(y)^2.
struct InputEnergies {
  std::array<std::vector<std::vector<double>>, 3> energies;
};

// Scratch of one term of one opponent channel (the motion, or one
// frame's detail): its gradients by the channel of each render (those it
// has), and its blurs' images.
struct TermScratch {
  std::vector<double> dya, dyb, diff, e_r, d_e, g, high, low, term;
  BlurScratch blur;
};

// One opponent channel of the two renders and its terms' scratch.
struct ChannelScratch {
  std::vector<double> ya, yb;
  std::array<TermScratch, 3> terms;
};
}  // namespace internal

// A loss on the statistics of water rather than its pixels. The L1 / SSIM
// loss of one frame is lowest at the temporal mean of stochastic water (a
// smooth, slow sheet), since no model can predict where each streak is.
// This loss compares local energies instead, which do not depend on the
// streaks' exact places: on each opponent colour channel y (orthonormal:
// luminance, red-green, yellow-blue) of two consecutive frames A and B
// (rendered) against the input frames,
//   motion: e = W * (y_B - y_A)^2           (frame-to-frame change)
//   detail: e = W * (y - G * y)^2, per frame (high-frequency texture)
// where G is a Gaussian blur of detail_sigma pixels and W a Gaussian
// window of window_sigma pixels (both with clamped borders). With
// detail_octaves n > 1 the detail term is the mean over n bands of a
// difference-of-Gaussians pyramid: band k = G_{k-1} * y - G_k * y (G_{-1}
// = identity), G_k of detail_sigma 2^k and its window W_k of window_sigma
// 2^k pixels; the coarser bands hold texture larger than a few pixels (a
// fountain's puffs and gaps), which the finest band does not see. Each
// term is
// the mean over the water pixels of |sqrt(e_rendered + eps) -
// sqrt(e_input + eps)|: the local amplitude of change / texture, rendered
// against input, averaged over the channels (on grey alone, training
// met the motion target with a coloured flicker; on R, G and B, with
// faint tinted streaks: each channel's amplitude matched, their signs
// not). The motion term uses the
// pixels that are water in A or B; the detail term each frame's own;
// without masks, every pixel. With the input's noise known
// (WaterEnergyOptions::input_noise), the render's energies get its
// expected energy added: the render is scored as if it had the input's
// noise, so it is not asked to paint it. Options and terms:
// costs/water_energy_terms.h. The inputs' own energies are kept between
// calls (WaterEnergyOptions::input_cache_bytes).
//
// Evaluates the loss for one pair; reuses its buffers between calls, so
// not thread-safe.
class WaterEnergyLoss {
 public:
  explicit WaterEnergyLoss(const WaterEnergyOptions& options = {});

  const WaterEnergyOptions& options() const { return options_; }

  // rendered_a / rendered_b: H x W x 3 row-major RGB doubles (frames A and
  // B = A's next frame in the video); input_a / input_b: CV_32FC3 or
  // CV_64FC3 RGB in [0, 1] of the same size; mask_a / mask_b: both empty
  // or CV_32FC1 / CV_64FC1 in [0, 1] (> 0.5 = water). Returns
  // motion_weight * motion + detail_weight * detail, times `scale`; if
  // d_a / d_b are not null, `scale` * d loss / d rendered is added to them
  // (+=, H x W x 3). `terms` (nullable) receives the unweighted terms.
  double Evaluate(const double* rendered_a, const double* rendered_b,
                  const cv::Mat& input_a, const cv::Mat& input_b,
                  const cv::Mat& mask_a, const cv::Mat& mask_b, double scale,
                  double* d_a, double* d_b, WaterEnergyTerms* terms = nullptr);

 private:
  // sum_p m_p |sqrt(e_r + floor) - sqrt(e_i + eps)| / sum_p m_p and,
  // into d_energy, its derivative by e_r (times `scale`); floor: the
  // channel's and term's from RenderedEnergyFloors; `term` is scratch.
  double AmplitudeL1(const std::vector<double>& e_rendered,
                     const std::vector<double>& e_input,
                     const std::vector<double>& mask, double floor,
                     double scale, std::vector<double>* term,
                     std::vector<double>* d_energy) const;

  // The inputs' energies: the pair's motion, one frame's detail bands.
  void MotionInputs(const cv::Mat& input_a, const cv::Mat& input_b,
                    internal::InputEnergies* out);
  void DetailInputs(const cv::Mat& input, internal::InputEnergies* out);

  // Opponent channel c's unweighted motion term of the renders' channels
  // ya, yb (divided by the channel count); its gradients by ya and yb,
  // times channel_scale, are added to s->dya and s->dyb.
  double MotionTerm(int c, const std::vector<double>& ya,
                    const std::vector<double>& yb, int w, int h,
                    double channel_scale, const std::vector<double>& e_input,
                    internal::TermScratch* s) const;
  // Half of channel c's unweighted detail term of one frame's render
  // channel y (its share of the two frames' mean, divided by the channel
  // count); its gradient, times channel_scale, is added to *dy.
  double DetailTerm(int c, const std::vector<double>& y, int w, int h,
                    double channel_scale,
                    const std::vector<std::vector<double>>& e_input,
                    const std::vector<double>& water, std::vector<double>* dy,
                    internal::TermScratch* s) const;

  WaterEnergyOptions options_;
  // G_k and W_k of the detail bands.
  WaterEnergyKernels kernels_;
  // The rendered energies' floors per channel: motion, and detail band k.
  std::array<double, 3> motion_floors_;
  std::vector<std::array<double, 3>> band_floors_;
  // The inputs' energies: of the pairs, and of the frames (with a spare
  // for frame B while frame A's may be in the cache's own).
  InputCache<internal::InputEnergies> motion_inputs_, detail_inputs_;
  internal::InputEnergies detail_b_spare_;
  // Per-frame scratch, reused; the channels are evaluated in parallel.
  cv::Mat input_a_, input_b_;  // CV_64FC3, for the inputs' energies
  std::vector<double> mask_, mask_a_, mask_b_;
  std::array<internal::ChannelScratch, 3> channels_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_ENERGY_LOSS_H_
