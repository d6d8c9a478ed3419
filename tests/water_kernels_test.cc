// The water losses' kernels at every SIMD level against the plain
// definitions: the blur gathers its clamped taps, the adjoint scatters
// each output back through them; the energy loss's amplitude terms; the
// texture loss's projections and their adjoint. Bit
// for bit: the kernels promise the same rounding on every set, so a run
// resumed on another CPU goes on alike.

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "costs/water_energy_terms.h"
#include "costs/water_kernels.h"
#include "tests/per_simd_level_test.h"

namespace es {
namespace {

using Image = std::vector<double>;

int Clamp(int v, int hi) { return v < 0 ? 0 : (v > hi ? hi : v); }

// out(x, y) = sum_j k[j] in(clamp(x + j - r), y), or along y.
Image ReferenceBlur(const Image& in, int w, int h, const Image& k,
                    bool along_x) {
  const int r = static_cast<int>(k.size()) / 2;
  Image out(in.size(), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int j = 0; j <= 2 * r; ++j) {
        const int sx = along_x ? Clamp(x + j - r, w - 1) : x;
        const int sy = along_x ? y : Clamp(y + j - r, h - 1);
        out[y * w + x] += k[j] * in[sy * w + sx];
      }
  return out;
}

// The adjoint as a scatter: each output, in order, through its taps in
// order. Along x the scatter goes into a padded row whose ends are folded
// onto the border pixels afterwards, as the losses first defined it.
Image ReferenceAdjoint(const Image& g, int w, int h, const Image& k,
                       bool along_x) {
  const int r = static_cast<int>(k.size()) / 2;
  Image out(g.size(), 0.0);
  if (!along_x) {
    for (int y = 0; y < h; ++y)
      for (int j = 0; j <= 2 * r; ++j)
        for (int x = 0; x < w; ++x)
          out[Clamp(y + j - r, h - 1) * w + x] += k[j] * g[y * w + x];
    return out;
  }
  for (int y = 0; y < h; ++y) {
    Image pad(w + 2 * r, 0.0);
    for (int j = 0; j <= 2 * r; ++j)
      for (int x = 0; x < w; ++x) pad[x + j] += k[j] * g[y * w + x];
    double* row = out.data() + y * w;
    for (int x = 0; x < w; ++x) row[x] = pad[x + r];
    for (int m = 0; m < r; ++m) {
      row[0] += pad[m];
      row[w - 1] += pad[w + r + m];
    }
  }
  return out;
}

class WaterKernelsTest : public PerSimdLevelTest {};

TEST_P(WaterKernelsTest, EveryPassMatchesItsDefinitionBitForBit) {
  const WaterKernelSet& kernels = WaterKernels(GetParam());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  // Widths around the kernels' blocks (up to 64 values) and below a
  // kernel's reach; heights from a single row.
  for (const int w : {1, 2, 5, 13, 64, 70, 131})
    for (const int h : {1, 3, 12})
      for (const double sigma : {0.3, 1.0, 2.0, 4.0}) {
        SCOPED_TRACE(testing::Message() << w << "x" << h << " sigma " << sigma);
        const Image k = WaterEnergyGaussian(sigma);
        const int r = static_cast<int>(k.size()) / 2;
        Image in(static_cast<size_t>(w) * h), out(in.size());
        for (double& v : in) v = value(rng);
        std::vector<const double*> sources(k.size() * k.size());
        Image coefficients(sources.size()), line(w + 2 * r);
        const WaterFilterScratch scratch{sources.data(), coefficients.data(),
                                         line.data()};
        kernels.blur_rows(in.data(), w, h, k.data(), r, scratch, out.data());
        EXPECT_EQ(out, ReferenceBlur(in, w, h, k, true));
        kernels.blur_columns(in.data(), w, h, k.data(), r, scratch,
                             out.data());
        EXPECT_EQ(out, ReferenceBlur(in, w, h, k, false));
        kernels.blur_rows_adjoint(in.data(), w, h, k.data(), r, scratch,
                                  out.data());
        EXPECT_EQ(out, ReferenceAdjoint(in, w, h, k, true));
        kernels.blur_columns_adjoint(in.data(), w, h, k.data(), r, scratch,
                                     out.data());
        EXPECT_EQ(out, ReferenceAdjoint(in, w, h, k, false));
      }
}

TEST_P(WaterKernelsTest, AmplitudeTermsMatchTheirDefinitionBitForBit) {
  const WaterKernelSet& kernels = WaterKernels(GetParam());
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> energy(-1e-6, 1e-2);
  const long n = 203;  // past every set's vectors, with a tail
  Image rendered(n), input(n), water(n), term(n), d(n);
  for (long p = 0; p < n; ++p) {
    rendered[p] = energy(rng);  // some below zero: clamped to 0
    input[p] = p % 7 == 0 ? rendered[p] : energy(rng);  // a == b too
    water[p] = p % 3 == 0 ? 0.0 : 1.0;
  }
  const double floor = 2e-6, eps = 1e-6, scale = 0.7, count = 135;
  kernels.amplitude_terms(rendered.data(), input.data(), water.data(), n,
                          floor, eps, scale, count, term.data(), d.data());
  for (long p = 0; p < n; ++p) {
    double want_term = 0, want_d = 0;
    if (water[p] != 0) {
      const double a = std::sqrt(std::max(rendered[p], 0.0) + floor);
      const double b = std::sqrt(std::max(input[p], 0.0) + eps);
      want_term = std::abs(a - b);
      want_d = scale * (a > b ? 1.0 : (a < b ? -1.0 : 0.0)) / (2 * a * count);
    }
    EXPECT_EQ(term[p], want_term) << p;
    EXPECT_EQ(d[p], want_d) << p;
  }
}

// The texture loss's projections and their adjoint, on 37 water pixels
// (vector blocks and a tail) and 21 directions (a block of 16, of 4, and
// one), against the sums written out in their documented order.
TEST_P(WaterKernelsTest, ProjectionsMatchTheirDefinitionBitForBit) {
  const WaterKernelSet& kernels = WaterKernels(GetParam());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  const int pixels = 23 * 7, count = 6, levels = 2, projections = 21;
  const long n = 37;
  const int dims = 9 * count;
  std::vector<Image> bands(count, Image(pixels));
  for (Image& band : bands)
    for (double& v : band) v = value(rng);
  std::vector<std::vector<int>> taps(levels, std::vector<int>(9 * n));
  std::uniform_int_distribution<int> pixel(0, pixels - 1);
  for (std::vector<int>& level : taps)
    for (int& t : level) t = pixel(rng);
  Image directions(static_cast<size_t>(dims) * projections);
  for (double& v : directions) v = value(rng);
  std::vector<const double*> band_pointers;
  for (const Image& band : bands) band_pointers.push_back(band.data());
  const int* tap_pointers[] = {taps[0].data(), taps[1].data()};
  TextureProjection p;
  p.bands = band_pointers.data();
  p.count = count;
  p.levels = levels;
  p.taps = tap_pointers;
  p.n = n;
  p.directions = directions.data();
  p.projections = projections;
  auto feature = [&](long i, int f) {
    return bands[f / 9][taps[(f / 9) % levels][9 * i + f % 9]];
  };

  Image out(n * projections);
  kernels.project(p, 0, n, out.data());
  for (long i = 0; i < n; ++i)
    for (int j = 0; j < projections; ++j) {
      double want = 0.0;
      for (int f = 0; f < dims; ++f)
        want += feature(i, f) * directions[j * dims + f];
      EXPECT_EQ(out[j * n + i], want) << i << ", " << j;
    }

  Image d_proj(n * projections);
  for (double& v : d_proj) v = value(rng);
  for (int b = 0; b < count; ++b) {
    Image d_band(pixels, 0.0), want(pixels, 0.0);
    kernels.project_adjoint(p, b, d_proj.data(), d_band.data());
    for (const auto& [j0, size] : {std::pair{0, 16}, {16, 4}, {20, 1}})
      for (long i = 0; i < n; ++i)
        for (int o = 0; o < 9; ++o) {
          double v = 0.0;
          for (int j = j0; j < j0 + size; ++j)
            v += d_proj[j * n + i] * directions[j * dims + 9 * b + o];
          want[taps[b % levels][9 * i + o]] += v;
        }
    EXPECT_EQ(d_band, want) << "band " << b;
  }
}

INSTANTIATE_TEST_SUITE_P(Levels, WaterKernelsTest, AllSimdLevels(),
                         SimdLevelTestName);

}  // namespace
}  // namespace es
