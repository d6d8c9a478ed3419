#ifndef EULERSPLAT_TESTS_PLANE_COMBINATION_NAME_H_
#define EULERSPLAT_TESTS_PLANE_COMBINATION_NAME_H_

#include <string>

#include <gtest/gtest.h>

#include "core/fields/triplane.h"

namespace es {

// Test name suffix for the tests parameterized by the plane combination.
inline std::string CombinationName(
    const ::testing::TestParamInfo<PlaneCombination>& info) {
  switch (info.param) {
    case PlaneCombination::kSum:
      return "Sum";
    case PlaneCombination::kProduct:
      return "Product";
    case PlaneCombination::kConcat:
      return "Concat";
  }
  return "Unknown";
}

// Every plane combination, as the parameters of such tests.
inline auto AllPlaneCombinations() {
  return ::testing::Values(PlaneCombination::kSum, PlaneCombination::kProduct,
                           PlaneCombination::kConcat);
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_PLANE_COMBINATION_NAME_H_
