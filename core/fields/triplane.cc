#include "core/fields/triplane.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <glog/logging.h>
#include <omp.h>

#include "core/fields/gradient_chunks.h"

namespace es {
namespace {

// Axes (column, row) of each plane: xy, xz, yz.
constexpr int kPlaneAxes[3][2] = {{0, 1}, {0, 2}, {1, 2}};

// Below this many points a parallel region costs more than it saves, and on
// a loaded machine far more (threads wait on descheduled peers).
constexpr int kMinParallelPoints = 4096;

// Parameter gradients of one extra OpenMP thread in Backward, kept all zero
// between calls (the reduction clears what it adds), with a flag per plane
// row saying whether the thread wrote to it.
struct PartialGradient {
  std::vector<double> grad;
  std::vector<char> touched_rows;
};

// Per calling thread, so Backward neither allocates nor clears a
// triplane-sized buffer per call (it ran once per Euler step).
std::vector<PartialGradient>& PartialGradients() {
  thread_local std::vector<PartialGradient> pool;
  return pool;
}

}  // namespace

Triplane::Triplane(const TriplaneOptions& options) : options_(options) {
  CHECK_GE(options_.resolution, 2);
  CHECK_GE(options_.channels, 1);
  SetBox(Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0));
}

void Triplane::SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  CHECK((hi.array() > lo.array()).all())
      << "empty triplane box " << lo.transpose() << " .. " << hi.transpose();
  lo_ = lo;
  hi_ = hi;
  texels_per_unit_ = (options_.resolution - 1.0) * (hi - lo).cwiseInverse();
}

int Triplane::output_dim() const {
  return options_.combination == PlaneCombination::kConcat
             ? 3 * options_.channels
             : options_.channels;
}

int Triplane::num_params() const {
  return 3 * options_.resolution * options_.resolution * options_.channels;
}

void Triplane::Initialize(uint32_t seed, double* params) const {
  std::mt19937 rng(seed);
  const double center =
      options_.combination == PlaneCombination::kProduct ? 1.0 : 0.0;
  std::uniform_real_distribution<double> noise(-options_.init_noise,
                                               options_.init_noise);
  for (int i = 0; i < num_params(); ++i) params[i] = center + noise(rng);
}

Triplane::AxisSample Triplane::SampleAxis(double x, int axis) const {
  const int last = options_.resolution - 1;
  const double s = (x - lo_[axis]) * texels_per_unit_[axis];
  // Written so that NaN lands in the first branch.
  if (!(s > 0.0)) return {0, 0.0, 0.0};
  if (s >= last) return {last - 1, 1.0, 0.0};
  const int i0 = std::min(static_cast<int>(s), last - 1);
  return {i0, s - i0, texels_per_unit_[axis]};
}

void Triplane::SamplePoint(const double* params, const double* x,
                           double* out) const {
  const int r = options_.resolution;
  const int c = options_.channels;
  const PlaneCombination mode = options_.combination;
  if (mode == PlaneCombination::kSum) std::fill(out, out + c, 0.0);
  if (mode == PlaneCombination::kProduct) std::fill(out, out + c, 1.0);
  for (int p = 0; p < 3; ++p) {
    const AxisSample a = SampleAxis(x[kPlaneAxes[p][0]], kPlaneAxes[p][0]);
    const AxisSample b = SampleAxis(x[kPlaneAxes[p][1]], kPlaneAxes[p][1]);
    const double* t00 = params + ((p * r + b.i0) * r + a.i0) * c;
    const double* t01 = t00 + c;
    const double* t10 = t00 + r * c;
    const double* t11 = t10 + c;
    const double w00 = (1 - a.frac) * (1 - b.frac), w01 = a.frac * (1 - b.frac);
    const double w10 = (1 - a.frac) * b.frac, w11 = a.frac * b.frac;
    for (int k = 0; k < c; ++k) {
      const double f =
          w00 * t00[k] + w01 * t01[k] + w10 * t10[k] + w11 * t11[k];
      switch (mode) {
        case PlaneCombination::kSum:
          out[k] += f;
          break;
        case PlaneCombination::kProduct:
          out[k] *= f;
          break;
        case PlaneCombination::kConcat:
          out[p * c + k] = f;
          break;
      }
    }
  }
}

void Triplane::Sample(const double* params, int n, const double* x, double* out,
                      int out_stride) const {
  const int d = out_stride > 0 ? out_stride : output_dim();
#pragma omp parallel for schedule(static) if (n >= kMinParallelPoints)
  for (int i = 0; i < n; ++i) SamplePoint(params, x + 3 * i, out + d * i);
}

void Triplane::BackwardPoint(const double* params, const double* x,
                             const double* d_out, double* scratch,
                             double* d_params, double* d_x) const {
  const int r = options_.resolution;
  const int c = options_.channels;
  const PlaneCombination mode = options_.combination;
  AxisSample as[3], bs[3];
  const double* t00s[3];
  for (int p = 0; p < 3; ++p) {
    as[p] = SampleAxis(x[kPlaneAxes[p][0]], kPlaneAxes[p][0]);
    bs[p] = SampleAxis(x[kPlaneAxes[p][1]], kPlaneAxes[p][1]);
    t00s[p] = params + ((p * r + bs[p].i0) * r + as[p].i0) * c;
  }
  // The product needs every plane's feature to form the others' gradients.
  double* f = scratch;
  if (mode == PlaneCombination::kProduct) {
    for (int p = 0; p < 3; ++p) {
      const AxisSample& a = as[p];
      const AxisSample& b = bs[p];
      const double* t00 = t00s[p];
      for (int k = 0; k < c; ++k) {
        f[p * c + k] = (1 - a.frac) * (1 - b.frac) * t00[k] +
                       a.frac * (1 - b.frac) * t00[k + c] +
                       (1 - a.frac) * b.frac * t00[k + r * c] +
                       a.frac * b.frac * t00[k + r * c + c];
      }
    }
  }
  double* g = scratch + 3 * c;  // dL / d(this plane's feature), per channel
  for (int p = 0; p < 3; ++p) {
    const AxisSample& a = as[p];
    const AxisSample& b = bs[p];
    const double* t00 = t00s[p];
    const double* t01 = t00 + c;
    const double* t10 = t00 + r * c;
    const double* t11 = t10 + c;
    const double* gp = g;
    switch (mode) {
      case PlaneCombination::kSum:
        gp = d_out;
        break;
      case PlaneCombination::kProduct: {
        const double* f1 = f + ((p + 1) % 3) * c;
        const double* f2 = f + ((p + 2) % 3) * c;
        for (int k = 0; k < c; ++k) g[k] = d_out[k] * f1[k] * f2[k];
        break;
      }
      case PlaneCombination::kConcat:
        gp = d_out + p * c;
        break;
    }
    double d_a = 0.0, d_b = 0.0;
    for (int k = 0; k < c; ++k) {
      d_a += gp[k] *
             ((1 - b.frac) * (t01[k] - t00[k]) + b.frac * (t11[k] - t10[k]));
      d_b += gp[k] *
             ((1 - a.frac) * (t10[k] - t00[k]) + a.frac * (t11[k] - t01[k]));
    }
    if (d_params != nullptr) {
      // The four texels' channel runs do not overlap each other, nor the
      // features and gradients read here, so the loop vectorizes.
      const double w00 = (1 - a.frac) * (1 - b.frac);
      const double w01 = a.frac * (1 - b.frac);
      const double w10 = (1 - a.frac) * b.frac, w11 = a.frac * b.frac;
      double* __restrict g00 = d_params + (t00 - params);
      double* __restrict g01 = g00 + c;
      double* __restrict g10 = g00 + r * c;
      double* __restrict g11 = g10 + c;
      const double* __restrict gk = gp;
      for (int k = 0; k < c; ++k) {
        g00[k] += w00 * gk[k];
        g01[k] += w01 * gk[k];
        g10[k] += w10 * gk[k];
        g11[k] += w11 * gk[k];
      }
    }
    if (d_x != nullptr) {
      d_x[kPlaneAxes[p][0]] += a.ds_dx * d_a;
      d_x[kPlaneAxes[p][1]] += b.ds_dx * d_b;
    }
  }
}

void Triplane::FlagPoint(const double* x, char* touched_chunks) const {
  const int r = options_.resolution;
  const int c = options_.channels;
  for (int p = 0; p < 3; ++p) {
    const AxisSample a = SampleAxis(x[kPlaneAxes[p][0]], kPlaneAxes[p][0]);
    const AxisSample b = SampleAxis(x[kPlaneAxes[p][1]], kPlaneAxes[p][1]);
    // Texels (i0, j0) and (i0 + 1, j0), then the same one row down.
    const size_t t00 = (static_cast<size_t>(p * r + b.i0) * r + a.i0) * c;
    const size_t t10 = t00 + static_cast<size_t>(r) * c;
    FlagGradientChunks(t00, t00 + 2 * c, touched_chunks);
    FlagGradientChunks(t10, t10 + 2 * c, touched_chunks);
  }
}

void Triplane::Backward(const double* params, int n, const double* x,
                        const double* d_out, double* d_params, double* d_x,
                        int d_out_stride, char* touched_chunks) const {
  const int d = d_out_stride > 0 ? d_out_stride : output_dim();
  if (d_params == nullptr && d_x == nullptr) return;
  if (d_params != nullptr && touched_chunks != nullptr) {
    for (int i = 0; i < n; ++i) FlagPoint(x + 3 * i, touched_chunks);
  }
  // Texels are shared between points: every thread but the first
  // accumulates parameter gradients into its own dense buffer, and the
  // buffers are summed at the end. Inside a parallel region (e.g. one
  // share of FrameComposer's) this runs on the calling thread alone.
  const int threads = n >= kMinParallelPoints && !omp_in_parallel()
                          ? omp_get_max_threads()
                          : 1;
  const int extra = d_params != nullptr ? threads - 1 : 0;
  const int r = options_.resolution;
  const int rows = 3 * r;  // (plane, row) blocks of r * channels params
  const size_t row_size = static_cast<size_t>(r) * options_.channels;
  // Sized here, not by their threads: the team may get fewer threads.
  std::vector<PartialGradient>& partial = PartialGradients();
  if (static_cast<int>(partial.size()) < extra) partial.resize(extra);
  for (int t = 0; t < extra; ++t) {
    PartialGradient& pg = partial[t];
    if (pg.grad.size() < static_cast<size_t>(num_params()))
      pg.grad.resize(num_params(), 0.0);
    if (static_cast<int>(pg.touched_rows.size()) < rows)
      pg.touched_rows.resize(rows, 0);
  }
#pragma omp parallel num_threads(threads)
  {
    const int id = omp_get_thread_num();
    // Per thread and kept, so a call allocates nothing after the first.
    thread_local std::vector<double> scratch;
    if (scratch.size() < 4 * static_cast<size_t>(options_.channels))
      scratch.resize(4 * static_cast<size_t>(options_.channels));
    PartialGradient* mine =
        d_params != nullptr && id > 0 ? &partial[id - 1] : nullptr;
    double* grad = mine != nullptr ? mine->grad.data() : d_params;
#pragma omp for schedule(static)
    for (int i = 0; i < n; ++i) {
      BackwardPoint(params, x + 3 * i, d_out + d * i, scratch.data(), grad,
                    d_x == nullptr ? nullptr : d_x + 3 * i);
      if (mine == nullptr) continue;
      for (int p = 0; p < 3; ++p) {
        const int row = SampleAxis(x[3 * i + kPlaneAxes[p][1]],
                                   kPlaneAxes[p][1]).i0;
        mine->touched_rows[p * r + row] = 1;
        mine->touched_rows[p * r + row + 1] = 1;
      }
    }
    if (extra > 0) {
#pragma omp for schedule(static)
      for (int row = 0; row < rows; ++row) {
        double* dst = d_params + row * row_size;
        for (int t = 0; t < extra; ++t) {
          PartialGradient& pg = partial[t];
          if (!pg.touched_rows[row]) continue;
          pg.touched_rows[row] = 0;
          double* src = pg.grad.data() + row * row_size;
          for (size_t j = 0; j < row_size; ++j) {
            dst[j] += src[j];
            src[j] = 0.0;
          }
        }
      }
    }
  }
}

double Triplane::TotalVariation(const double* params, double weight,
                                double* d_params) const {
  const int r = options_.resolution;
  const int c = options_.channels;
  const double count = 3.0 * c * 2.0 * r * (r - 1);
  const double scale = weight / count;
  double sum = 0.0;
  for (int p = 0; p < 3; ++p) {
    for (int row = 0; row < r; ++row) {
      for (int col = 0; col < r; ++col) {
        const int base = ((p * r + row) * r + col) * c;
        for (int k = 0; k < c; ++k) {
          const int i = base + k;
          // Right neighbour, then the one below.
          for (const int j :
               {col + 1 < r ? i + c : -1, row + 1 < r ? i + r * c : -1}) {
            if (j < 0) continue;
            const double diff = params[j] - params[i];
            sum += diff * diff;
            if (d_params != nullptr) {
              d_params[j] += 2.0 * scale * diff;
              d_params[i] -= 2.0 * scale * diff;
            }
          }
        }
      }
    }
  }
  return scale * sum;
}

}  // namespace es
