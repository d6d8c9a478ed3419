#ifndef EULERSPLAT_COSTS_CUDA_WATER_ENERGY_KERNELS_H_
#define EULERSPLAT_COSTS_CUDA_WATER_ENERGY_KERNELS_H_

// The device water energy loss's kernels (water_energy.cu), as
// DeviceWaterEnergyLoss launches them: plain types only, all pointers
// device pointers. A plane is one H x W image of doubles, row-major;
// "planes" are several of them one after another. Images are H x W x 3
// floats, RGB interleaved (DeviceImages::rgb's layout).

namespace es {
namespace cuda {

// kWaterOpponent (costs/water_energy_terms.h), passed by value.
struct OpponentBasis {
  double k[3][3];
};

// Blocks of one plane's per-pixel passes (each writes one partial sum per
// plane).
int WaterEnergyBlocks(long long pixels);

// water = 3 planes: 1 where mask_a, mask_b, and either of them is > 0.5
// (1 everywhere when both masks are null), else 0; partials[q blocks + b]:
// block b's count of plane q.
void WaterPlanes(long long pixels, const float* mask_a, const float* mask_b,
                 double* water, double* partials);
// y = 12 planes: the opponent channels of rendered_a, rendered_b, input_a,
// input_b, three planes each, in that order.
void OpponentPlanes(long long pixels, const OpponentBasis& basis,
                    const float* rendered_a, const float* rendered_b,
                    const float* input_a, const float* input_b, double* y);
// From y: diff = 6 planes, y_b - y_a of the renders (3) then of the
// inputs (3); square = diff^2.
void MotionDifferences(long long pixels, const double* y, double* diff,
                       double* square);
// `planes` planes of width x height, each blurred with the 2 radius + 1
// taps, borders clamped as the CPU's (out[i] = sum_j taps[j]
// in[clamp(i + j - radius)]): along rows into scratch, then down columns
// into out.
void ClampedBlur(int planes, int width, int height, const double* taps,
                 int radius, const double* in, double* scratch, double* out);
// The adjoint of ClampedBlur (columns, then rows), exact at the borders.
void ClampedBlurAdjoint(int planes, int width, int height,
                        const double* taps, int radius, const double* g_out,
                        double* scratch, double* g_in);
// high = fine - coarse and square = high^2 over n values.
void BandAndSquare(long long n, const double* fine, const double* coarse,
                   double* high, double* square);
// The rendered energies' floor per opponent channel
// (RenderedEnergyFloors); plane q is of channel q % 3.
struct ChannelFloors {
  double c[3];
};

// The amplitude L1 of `planes` planes of energies: plane q's water plane
// and count are water[q / planes_per_mask] and counts[q /
// planes_per_mask]; a = sqrt(max(e_r, 0) + floors.c[q % 3]),
// b = sqrt(max(e_i, 0) + eps);
// partials[q blocks + b]: block b's sum of |a - b| over water pixels; with
// d_e set, d_e = scale sign(a - b) / (2 a count) on water, else 0.
void AmplitudeTerms(int planes, int planes_per_mask, long long pixels,
                    const double* e_r, const double* e_i, const double* water,
                    const double* counts, ChannelFloors floors, double eps,
                    double scale, double* d_e, double* partials);
// The motion term's chain rule: t = 2 diff g per render plane c < 3,
// dy[3 + c] += t (frame B), dy[c] -= t (frame A).
void AddMotionGradient(long long pixels, const double* diff, const double* g,
                       double* dy);
// g *= 2 high over n values.
void ScaleByTwice(long long n, const double* high, double* g);
// dy += fine - coarse over n values.
void AddBandGradient(long long n, const double* fine, const double* coarse,
                     double* dy);
// d_a, d_b (nullable) += the basis' transpose of dy's planes (3 for frame
// A, then 3 for B), each sum in double, then added to the float.
void AddRgbGradients(long long pixels, const OpponentBasis& basis,
                     const double* dy, float* d_a, float* d_b);
// sums[s] = the sum of partials[s blocks .. (s + 1) blocks) in block
// order, s < segments.
void SumSegments(int segments, int blocks, const double* partials,
                 double* sums);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_WATER_ENERGY_KERNELS_H_
