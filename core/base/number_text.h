#ifndef EULERSPLAT_CORE_BASE_NUMBER_TEXT_H_
#define EULERSPLAT_CORE_BASE_NUMBER_TEXT_H_

#include <string>

namespace es {

// `v` as printf's "%g" writes it (six significant digits, no trailing
// zeros: 0.5, 1e-05, 2000): numbers in messages, flags and labels.
std::string ShortNumber(double v);

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_NUMBER_TEXT_H_
