#ifndef EULERSPLAT_CORE_BASE_PARSE_CHOICE_H_
#define EULERSPLAT_CORE_BASE_PARSE_CHOICE_H_

#include <cstddef>
#include <string>
#include <utility>

#include "core/base/input_error.h"

namespace es {

// A value's spelling, e.g. a flag's: {"plane", SecondEnd::kFacingPlane}.
template <typename T>
using Choice = std::pair<const char*, T>;

// The value named `name` among `choices`; otherwise throws InputError
// "unknown <what> '<name>'; available: <the names, in order>".
template <typename T, size_t N>
T ParseChoice(const std::string& what, const std::string& name,
              const Choice<T> (&choices)[N]) {
  std::string names;
  for (const auto& [choice, value] : choices) {
    if (name == choice) return value;
    names += (names.empty() ? "" : ", ") + std::string(choice);
  }
  throw InputError("unknown " + what + " '" + name + "'; available: " + names);
}

// The name of `value` among `choices` ("" where it has none).
template <typename T, size_t N>
const char* ChoiceName(T value, const Choice<T> (&choices)[N]) {
  for (const auto& [choice, v] : choices) {
    if (v == value) return choice;
  }
  return "";
}

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_PARSE_CHOICE_H_
