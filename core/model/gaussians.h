#ifndef EULERSPLAT_CORE_MODEL_GAUSSIANS_H_
#define EULERSPLAT_CORE_MODEL_GAUSSIANS_H_

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace es {

// Number of SH coefficients per color channel for a degree (0..3).
inline int NumShCoeffs(int degree) { return (degree + 1) * (degree + 1); }
constexpr int kMaxShDegree = 3;

// A set of 3D Gaussian splats. Each attribute is one contiguous double array
// so it can be handed to Ceres as a parameter block as is.
//   means           3N   world position
//   log_scales      3N   log of the per-axis standard deviation
//   quats           4N   rotation, w x y z, not necessarily normalized
//   opacity_logits   N   opacity = sigmoid(logit)
//   sh              3KN  K = NumShCoeffs(sh_degree); layout [n][k][rgb], so
//                        sh[(n*K + k)*3 + c]; k = 0 is the DC term
//   dynamic_logits   N   probability of being water = sigmoid(logit)
struct GaussianSet {
  int sh_degree = 0;
  std::vector<double> means;
  std::vector<double> log_scales;
  std::vector<double> quats;
  std::vector<double> opacity_logits;
  std::vector<double> sh;
  std::vector<double> dynamic_logits;

  int size() const { return static_cast<int>(opacity_logits.size()); }
  int sh_coeffs() const { return NumShCoeffs(sh_degree); }

  // Resizes every array for n Gaussians; new entries are zero, quaternions
  // identity.
  void Resize(int n);
  // Changes the SH degree, keeping the existing lower-order coefficients and
  // zeroing new ones.
  void SetShDegree(int degree);
  // Appends Gaussian `index` of `other` (same SH degree).
  void AppendFrom(const GaussianSet& other, int index);
  // Keeps only the Gaussians whose keep[i] is true, preserving order.
  void Filter(const std::vector<bool>& keep);
  // Checks the array sizes agree with size() and sh_degree (CHECK on failure).
  void CheckConsistent() const;
};

// One per-Gaussian array of GaussianSet, as every loop over the set's
// arrays (resize, append, filter, checkpoints, optimisers, guards, device
// copies) sees it. A new attribute is a member above and a row in
// kGaussianArrays below; those loops then carry it without an edit.
struct GaussianArray {
  std::vector<double> GaussianSet::*values;
  // Values per Gaussian; with per_sh_coeff, per Gaussian and SH coefficient
  // (the SH array: 3 colour channels times sh_coeffs()).
  int width;
  bool per_sh_coeff;
  // The first value of a Gaussian that Resize adds; its other values start
  // at 0 (1 for the quaternion: the identity rotation).
  double first_value;
  const char* name;

  int Width(int sh_coeffs) const {
    return per_sh_coeff ? width * sh_coeffs : width;
  }
};

// Indices into kGaussianArrays, in the order of checkpoints and of the
// splat costs' parameter blocks (costs/splat_render_cost.h).
enum GaussianArrayIndex {
  kMeansArray = 0,
  kLogScalesArray,
  kQuatsArray,
  kOpacityArray,
  kShArray,
  kDynamicArray,
  kNumGaussianArrays
};

inline constexpr std::array<GaussianArray, kNumGaussianArrays>
    kGaussianArrays = {{
        {&GaussianSet::means, 3, false, 0.0, "means"},
        {&GaussianSet::log_scales, 3, false, 0.0, "log_scales"},
        {&GaussianSet::quats, 4, false, 1.0, "quats"},
        {&GaussianSet::opacity_logits, 1, false, 0.0, "opacity_logits"},
        {&GaussianSet::sh, 3, true, 0.0, "sh"},
        {&GaussianSet::dynamic_logits, 1, false, 0.0, "dynamic_logits"},
    }};

// Every array member, from `means` on, has its row: a member added without
// one fails here instead of being dropped by the loops.
static_assert(sizeof(GaussianSet) - offsetof(GaussianSet, means) ==
                  kNumGaussianArrays * sizeof(std::vector<double>),
              "a GaussianSet array without a row in kGaussianArrays");

// SH degree-0 basis constant: color = kShC0 * f_dc + 0.5.
constexpr double kShC0 = 0.28209479177387814;

inline double Sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }
inline double Logit(double p) { return std::log(p / (1.0 - p)); }

}  // namespace es

#endif  // EULERSPLAT_CORE_MODEL_GAUSSIANS_H_
