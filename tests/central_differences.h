#ifndef EULERSPLAT_TESTS_CENTRAL_DIFFERENCES_H_
#define EULERSPLAT_TESTS_CENTRAL_DIFFERENCES_H_

// Finite-difference helpers shared by the field and looping gradient tests
// (double precision, central differences).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace es {
namespace central_differences {

constexpr double kStep = 1e-6;
constexpr double kTolerance = 1e-4;  // relative, or absolute below 1

// d f / d *value by central differences; *value is restored.
inline double NumericDerivative(const std::function<double()>& f,
                                double* value) {
  const double saved = *value;
  *value = saved + kStep;
  const double plus = f();
  *value = saved - kStep;
  const double minus = f();
  *value = saved;
  return (plus - minus) / (2 * kStep);
}

inline void ExpectRelativeNear(double analytic, double numeric,
                               const char* what, int index) {
  EXPECT_LE(std::abs(analytic - numeric),
            kTolerance * std::max(1.0, std::abs(numeric)))
      << what << "[" << index << "] analytic " << analytic << " numeric "
      << numeric;
}

// Checks every entry of `analytic` against the derivative of `loss` with
// respect to the matching entry of *values, and that the check saw a
// gradient at all (a zero gradient would pass trivially).
inline void ExpectGradientsNear(const std::vector<double>& analytic,
                                const std::function<double()>& loss,
                                std::vector<double>* values, const char* what) {
  ASSERT_EQ(analytic.size(), values->size());
  double largest = 0.0;
  for (size_t i = 0; i < values->size(); ++i) {
    const double numeric = NumericDerivative(loss, &(*values)[i]);
    largest = std::max(largest, std::abs(numeric));
    ExpectRelativeNear(analytic[i], numeric, what, static_cast<int>(i));
  }
  EXPECT_GT(largest, 1e-3) << what << ": the check must see a gradient";
}

inline std::vector<double> Uniform(int size, double lo, double hi,
                                   uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(lo, hi);
  std::vector<double> v(size);
  for (double& x : v) x = uniform(rng);
  return v;
}

}  // namespace central_differences
}  // namespace es

#endif  // EULERSPLAT_TESTS_CENTRAL_DIFFERENCES_H_
