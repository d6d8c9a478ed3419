#ifndef EULERSPLAT_APPS_COMMON_SPLAT_RATE_FLAGS_H_
#define EULERSPLAT_APPS_COMMON_SPLAT_RATE_FLAGS_H_

// The splat blocks' learning rates from an app's flags. es_static and
// es_train take all eight but name four of them differently (es_static
// after 3DGS: lr_position, lr_scale, lr_rotation; es_train after the
// blocks: lr_means, lr_log_scales, lr_quats), and those names are
// published, so the app names those four; lr_opacity, lr_sh_dc,
// lr_sh_rest and lr_dynamic are the same in both. The app defines all of
// them (DEFINE_double).

#include <string>

#include "solvers/train/splat_training.h"

namespace es {

struct SplatRateFlagNames {
  std::string means_initial;
  std::string means_final;
  std::string log_scales;
  std::string quats;
};

// The rates the flags hold. Throws InputError naming both flags if the
// final position rate exceeds the initial one.
SplatLearningRateOptions SplatRatesFromFlags(const SplatRateFlagNames& names);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_SPLAT_RATE_FLAGS_H_
