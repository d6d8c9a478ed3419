#include "apps/common/parse_color.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "core/base/input_error.h"

namespace es {

Eigen::Vector3d ParseColor(const std::string& text, const std::string& flag) {
  std::stringstream in(text);
  std::string item;
  std::vector<double> values;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' ||
        !std::isfinite(v)) {
      throw InputError("--" + flag + "=" + text + ": '" + item +
                       "' is not a number (expected r,g,b)");
    }
    values.push_back(v);
  }
  if (values.size() != 3 || text.back() == ',') {
    throw InputError("--" + flag + "=" + text +
                     ": expected three comma-separated numbers r,g,b");
  }
  return {values[0], values[1], values[2]};
}

}  // namespace es
