#ifndef EULERSPLAT_TESTS_EXPECT_ERROR_H_
#define EULERSPLAT_TESTS_EXPECT_ERROR_H_

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace es {

// Runs `run`, which must throw `Error` (InputError, TrainingDiverged...),
// and returns the error's message; fails the test and returns "" where it
// throws nothing.
template <typename Error, typename Run>
std::string ErrorMessage(Run run) {
  try {
    run();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

// Expects `run` to throw `Error` whose message holds every one of `parts`
// (the file, the flag to change, the bad value...).
template <typename Error, typename Run>
void ExpectErrorNaming(Run run, const std::vector<std::string>& parts) {
  const std::string what = ErrorMessage<Error>(run);
  for (const std::string& part : parts)
    EXPECT_NE(what.find(part), std::string::npos) << part << ": " << what;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_EXPECT_ERROR_H_
