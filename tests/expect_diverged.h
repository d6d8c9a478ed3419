#ifndef EULERSPLAT_TESTS_EXPECT_DIVERGED_H_
#define EULERSPLAT_TESTS_EXPECT_DIVERGED_H_

#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

#include "solvers/train/divergence_guard.h"

namespace es {

// Runs `run`, which must stop with TrainingDiverged, and returns the
// error's message; fails the test and returns "" where it does not.
template <typename Run>
std::string DivergedMessage(Run run) {
  try {
    run();
  } catch (const TrainingDiverged& e) {
    return e.what();
  }
  ADD_FAILURE() << "no TrainingDiverged";
  return "";
}

// Expects `run` to stop with TrainingDiverged whose message holds every one
// of `parts` (the flag to lower, the iteration, the runaway value...).
template <typename Run>
void ExpectDivergedNaming(Run run, std::initializer_list<std::string> parts) {
  const std::string what = DivergedMessage(run);
  for (const std::string& part : parts)
    EXPECT_NE(what.find(part), std::string::npos) << part << ": " << what;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_EXPECT_DIVERGED_H_
