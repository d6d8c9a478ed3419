#ifndef EULERSPLAT_CORE_BASE_INPUT_ERROR_H_
#define EULERSPLAT_CORE_BASE_INPUT_ERROR_H_

#include <stdexcept>
#include <string>

namespace es {

// A problem with user input (a file, a flag): the message names the input and
// says what is wrong. Apps catch it, print it and exit non-zero; programmer
// errors use glog CHECK instead.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message)
      : std::runtime_error(message) {}
};

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_INPUT_ERROR_H_
