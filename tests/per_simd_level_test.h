#ifndef EULERSPLAT_TESTS_PER_SIMD_LEVEL_TEST_H_
#define EULERSPLAT_TESTS_PER_SIMD_LEVEL_TEST_H_

#include <string>

#include <gtest/gtest.h>

#include "core/base/simd_level.h"

namespace es {

// Base of the suites that run once per SIMD level of the kernels; a level
// this CPU lacks is skipped. Instantiate with
//   INSTANTIATE_TEST_SUITE_P(Levels, Suite, AllSimdLevels(),
//                            SimdLevelTestName);
class PerSimdLevelTest : public ::testing::TestWithParam<SimdLevel> {
 protected:
  void SetUp() override {
    if (!SimdLevelSupported(GetParam()))
      GTEST_SKIP() << "CPU lacks " << SimdLevelName(GetParam());
  }
};

inline auto AllSimdLevels() {
  return ::testing::Values(SimdLevel::kSse2, SimdLevel::kAvx2,
                           SimdLevel::kAvx512);
}

inline std::string SimdLevelTestName(
    const ::testing::TestParamInfo<SimdLevel>& info) {
  return SimdLevelName(info.param);
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_PER_SIMD_LEVEL_TEST_H_
