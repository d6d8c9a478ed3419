#ifndef EULERSPLAT_CORE_MODEL_GAUSSIANS_H_
#define EULERSPLAT_CORE_MODEL_GAUSSIANS_H_

#include <cmath>
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

// SH degree-0 basis constant: color = kShC0 * f_dc + 0.5.
constexpr double kShC0 = 0.28209479177387814;

inline double Sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }
inline double Logit(double p) { return std::log(p / (1.0 - p)); }

}  // namespace es

#endif  // EULERSPLAT_CORE_MODEL_GAUSSIANS_H_
