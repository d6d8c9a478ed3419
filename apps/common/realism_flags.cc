#include "apps/common/realism_flags.h"

#include <gflags/gflags.h>

#include "apps/common/flag_checks.h"

DEFINE_int32(realism_patches, es::RealismOptions{}.patch_samples,
             "Random patches per region for the realism distribution "
             "distances (fewer: faster, but the distances of close videos "
             "come out larger).");
DEFINE_double(realism_water_margin, 0.02, "The realism figures' water "
              "region is the water mask dilated by this fraction of the "
              "image diagonal, so that masks of single droplets do not "
              "select where the input has spray (0: the mask itself, the "
              "figures before 2026-12-02).");
DEFINE_uint64(realism_seed, 0, "Seed of the realism patches' positions and "
              "projection directions. Figures compared with one another "
              "should share it; other seeds show the figures' sampling "
              "noise.");

namespace es {

RealismOptions RealismOptionsFromFlags() {
  RequireAtLeast("realism_patches", FLAGS_realism_patches, 16);
  RequireInRange("realism_water_margin", FLAGS_realism_water_margin, 0, 0.5);
  RealismOptions options;
  options.patch_samples = FLAGS_realism_patches;
  options.water_margin = FLAGS_realism_water_margin;
  options.seed = FLAGS_realism_seed;
  return options;
}

}  // namespace es
