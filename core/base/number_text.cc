#include "core/base/number_text.h"

#include <cstdio>

namespace es {

std::string ShortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}

}  // namespace es
