#ifndef EULERSPLAT_TESTS_CENTRAL_DIFFERENCES_H_
#define EULERSPLAT_TESTS_CENTRAL_DIFFERENCES_H_

// Finite-difference helpers shared by the field and looping gradient tests
// (double precision, central differences).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
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

// For image losses: the derivative of `loss` with respect to each probed
// entry of `values` (corners, borders, the interior) against `analytic` at
// that entry. Every error must stay below 1e-6 of the largest derivative,
// and the probes must see a gradient.
inline void ExpectProbedGradientNear(const double* analytic, double* values,
                                     std::initializer_list<int> probes,
                                     const std::function<double()>& loss) {
  double max_err = 0, max_grad = 0;
  for (int idx : probes) {
    const double numeric = NumericDerivative(loss, &values[idx]);
    max_err = std::max(max_err, std::abs(numeric - analytic[idx]));
    max_grad = std::max(max_grad, std::abs(numeric));
  }
  EXPECT_GT(max_grad, 1e-5);
  EXPECT_LT(max_err, 1e-6 * max_grad + 1e-10);
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
