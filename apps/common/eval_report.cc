#include "apps/common/eval_report.h"

#include <cstdio>

namespace es {

nlohmann::ordered_json HeldOutJson(const LoopMetrics& m) {
  return {{"frames", m.frames},
          {"psnr", m.psnr},
          {"ssim", m.ssim},
          {"psnr_water", m.psnr_water},
          {"ssim_water", m.ssim_water}};
}

void PrintHeldOutRows(const LoopMetrics& m, bool has_masks) {
  std::printf("  held-out (%d frames)   PSNR %6.2f dB   SSIM %.4f\n",
              m.frames, m.psnr, m.ssim);
  std::printf("  water region          PSNR %6.2f dB   SSIM %.4f%s\n",
              m.psnr_water, m.ssim_water, has_masks ? "" : "   (no masks)");
}

nlohmann::ordered_json RealismRegionJson(const RealismRegion& r) {
  return {{"pixels", r.pixels},
          {"detail_ratio", r.detail_ratio},
          {"band_ratio", r.band_ratio},
          {"motion_ratio", r.motion_ratio},
          {"real_detail", r.real_detail},
          {"real_motion", r.real_motion},
          {"patches", r.patches},
          {"distance_2d", r.distance_2d},
          {"distance_3d", r.distance_3d}};
}

nlohmann::ordered_json RealismJson(const RealismMetrics& metrics) {
  return {{"water", RealismRegionJson(metrics.water)},
          {"static", RealismRegionJson(metrics.static_region)},
          {"frame", RealismRegionJson(metrics.frame)}};
}

void PrintRealismRow(const char* name, const RealismRegion& r) {
  if (r.pixels == 0) {
    std::printf("  %-21s n/a (no masks)\n", name);
    return;
  }
  std::printf("  %-21s detail %.2f  motion %.2f  distance 2D %.4f  "
              "3D %.4f\n",
              name, r.detail_ratio, r.motion_ratio, r.distance_2d,
              r.distance_3d);
}

}  // namespace es
