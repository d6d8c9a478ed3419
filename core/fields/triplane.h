#ifndef EULERSPLAT_CORE_FIELDS_TRIPLANE_H_
#define EULERSPLAT_CORE_FIELDS_TRIPLANE_H_

#include <cstdint>

#include <Eigen/Core>

namespace es {

// How the three plane features of a point become one feature vector.
enum class PlaneCombination {
  kSum,      // f_xy + f_xz + f_yz         (C outputs)
  kProduct,  // f_xy * f_xz * f_yz, per channel (C outputs, K-Planes style)
  kConcat,   // [f_xy, f_xz, f_yz]         (3C outputs)
};

struct TriplaneOptions {
  int resolution = 128;  // R: each plane is R x R texels
  int channels = 12;     // C: features per texel
  PlaneCombination combination = PlaneCombination::kProduct;
  // Initial features are uniform in [center - init_noise, center + init_noise]
  // with center 1 for kProduct (so the product starts near 1 and every plane
  // gets a gradient) and 0 otherwise.
  double init_noise = 0.1;
};

// Three axis-aligned feature planes (xy, xz, yz) over a bounding box.
//
// Parameters are ONE contiguous double array (a Ceres parameter block) of
// num_params() = 3 R R C values, channels innermost:
//   params[((plane * R + row) * R + col) * C + c]
// plane 0 = xy (col from x, row from y), 1 = xz (col x, row z),
// 2 = yz (col y, row z).
//
// Sampling: a coordinate is normalized by the box to u in [-1, 1] and mapped
// align-corners style to texel space s = (u + 1) / 2 * (R - 1): -1 is the
// center of texel 0, +1 the center of texel R - 1. Outside the box the
// coordinate is clamped to the border, so along a clamped axis the gradient
// with respect to position is zero. A non-finite coordinate samples texel 0
// with zero position gradient (never undefined behaviour).
//
// All gradient outputs are accumulated (+=), so callers zero them first.
class Triplane {
 public:
  explicit Triplane(const TriplaneOptions& options);

  // Sets the box mapped to [-1, 1]^3; hi must exceed lo on every axis.
  void SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  const Eigen::Vector3d& box_min() const { return lo_; }
  const Eigen::Vector3d& box_max() const { return hi_; }

  const TriplaneOptions& options() const { return options_; }
  int output_dim() const;
  int num_params() const;

  // Fills params (num_params()) as documented in TriplaneOptions::init_noise.
  void Initialize(uint32_t seed, double* params) const;

  // Samples n points: x is n x 3, out is n x output_dim(), row-major, with
  // rows out_stride apart (0 means output_dim(); larger lets the features
  // fill the leading columns of a wider matrix).
  void Sample(const double* params, int n, const double* x, double* out,
              int out_stride = 0) const;

  // Given d_out = dL/dout (n x output_dim()), accumulates dL/dparams into the
  // dense array d_params (num_params(); only 4 texels per plane per point are
  // touched) and dL/dx into d_x (n x 3). Either may be nullptr. d_out rows
  // are d_out_stride apart, as in Sample. touched_chunks (nullable, one flag
  // per kGradientChunk values of d_params, core/fields/gradient_chunks.h)
  // gets the chunks written to d_params set; the others are left alone.
  void Backward(const double* params, int n, const double* x,
                const double* d_out, double* d_params, double* d_x,
                int d_out_stride = 0, char* touched_chunks = nullptr) const;

  // Total variation: weight * mean over planes, channels and horizontal and
  // vertical neighbour pairs of the squared difference. Accumulates its
  // gradient into d_params when not nullptr.
  double TotalVariation(const double* params, double weight,
                        double* d_params) const;

 private:
  // Texel-space position of coordinate x along an axis.
  struct AxisSample {
    int i0;        // lower texel
    double frac;   // weight of texel i0 + 1
    double ds_dx;  // d frac / d x; 0 where clamped
  };
  AxisSample SampleAxis(double x, int axis) const;
  // One point of Sample / Backward; scratch holds 4 C doubles.
  void SamplePoint(const double* params, const double* x, double* out) const;
  void BackwardPoint(const double* params, const double* x, const double* d_out,
                     double* scratch, double* d_params, double* d_x) const;
  // Flags the chunks of d_params that BackwardPoint at x writes.
  void FlagPoint(const double* x, char* touched_chunks) const;

  TriplaneOptions options_;
  Eigen::Vector3d lo_, hi_;
  Eigen::Vector3d texels_per_unit_;  // (R - 1) / (hi - lo)
};

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_TRIPLANE_H_
