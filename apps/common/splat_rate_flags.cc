#include "apps/common/splat_rate_flags.h"

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <cstdlib>

#include "core/base/input_error.h"

namespace es {
namespace {

// A double flag's value: gflags keeps its text at 17 significant digits,
// which reads back as the very same double.
double DoubleFlag(const std::string& name) {
  const gflags::CommandLineFlagInfo info =
      gflags::GetCommandLineFlagInfoOrDie(name.c_str());
  CHECK_EQ(info.type, "double") << "--" << name;
  return std::strtod(info.current_value.c_str(), nullptr);
}

}  // namespace

SplatLearningRateOptions SplatRatesFromFlags(const SplatRateFlagNames& n) {
  SplatLearningRateOptions lr;
  lr.means_initial = DoubleFlag(n.means_initial);
  lr.means_final = DoubleFlag(n.means_final);
  lr.log_scales = DoubleFlag(n.log_scales);
  lr.quats = DoubleFlag(n.quats);
  lr.opacity = DoubleFlag("lr_opacity");
  lr.sh_dc = DoubleFlag("lr_sh_dc");
  lr.sh_rest = DoubleFlag("lr_sh_rest");
  lr.dynamic = DoubleFlag("lr_dynamic");
  if (lr.means_final > lr.means_initial) {
    throw InputError("--" + n.means_final + " must not exceed --" +
                     n.means_initial);
  }
  return lr;
}

}  // namespace es
