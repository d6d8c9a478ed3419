#include "solvers/eval/eval_report.h"

#include <cstdio>

#include "costs/water_input_noise.h"

namespace es {

nlohmann::ordered_json HeldOutJson(const LoopMetrics& m) {
  return {{"frames", m.frames},
          {"psnr", m.psnr},
          {"ssim", m.ssim},
          {"psnr_water", m.psnr_water},
          {"ssim_water", m.ssim_water},
          {"psnr_static", m.psnr_static},
          {"psnr_far_scenery", m.psnr_far_scenery}};
}

void PrintHeldOutRows(const LoopMetrics& m, bool has_masks,
                      double stage1_far_scenery) {
  std::printf("  held-out (%d frames)   PSNR %6.2f dB   SSIM %.4f\n",
              m.frames, m.psnr, m.ssim);
  std::printf("  water region          PSNR %6.2f dB   SSIM %.4f%s\n",
              m.psnr_water, m.ssim_water, has_masks ? "" : "   (no masks)");
  if (!has_masks) return;
  std::printf("  scenery (not water)   PSNR %6.2f dB\n", m.psnr_static);
  std::printf("  scenery far from water PSNR %5.2f dB", m.psnr_far_scenery);
  if (std::isfinite(stage1_far_scenery))
    std::printf("   (Stage 1 %.2f dB)", stage1_far_scenery);
  std::printf("\n");
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

nlohmann::ordered_json EvalJson(const EvalStageOptions& o,
                                const LoopModel& model,
                                const EvalStageResult& e) {
  nlohmann::ordered_json json = {
      {"model", o.model_dir},
      {"scene", o.scene_dir},
      {"device", o.device},
      {"gaussians", model.gaussians.size()},
      {"dynamic_gaussians", model.num_dynamic()},
      {"cycle_length", model.cycle_length},
      {"held_out", HeldOutJson(e.held_out)},
      {"training_water_psnr", TrainingWaterPsnrJson(e.training)},
      {"motion_gt", nullptr},
      {"realism", RealismJson(e.realism)},
      {"realism_input_noise", e.input_noise},
      {"loop_seam",
       {{"anchor_frame", e.anchor_frame},
        {"cycles", o.seam_cycles},
        {"score", e.seam.score},
        {"boundary_change", e.seam.boundary_change},
        {"within_change", e.seam.within_change}}},
      {"render_time_ms",
       {{"frames", e.timing.frames},
        {"alg1_advect", e.timing.alg1_advect_ms},
        {"alg2_advect", e.timing.alg2_advect_ms},
        {"render", e.timing.render_ms},
        {"alg1_frame", e.timing.alg1_frame_ms()},
        {"alg2_frame", e.timing.alg2_frame_ms()},
        {"alg1_alg2_max_position_difference",
         e.timing.max_position_difference}}}};
  if (!e.breakdown.empty()) {
    nlohmann::ordered_json breakdown;
    for (const auto& [name, r] : e.breakdown) {
      breakdown[name] = RealismJson(r);
    }
    json["realism_breakdown"] = breakdown;
  }
  if (e.has_motion_gt) {
    json["motion_gt"] = {{"points", e.motion.num_points},
                         {"epe", e.motion.epe},
                         {"mean_speed", e.motion.mean_speed},
                         {"rel_epe", e.motion.rel_epe},
                         {"speed_ratio", e.motion.speed_ratio}};
    if (e.reference_motion) {
      json["motion_gt"]["reference"] = {
          {"field", o.reference_motion},
          {"epe", e.reference_motion->epe},
          {"rel_epe", e.reference_motion->rel_epe},
          {"speed_ratio", e.reference_motion->speed_ratio}};
    }
  }
  return json;
}

void PrintEvalSummary(const EvalStageOptions& o, const LoopModel& model,
                      const Scene& scene, const EvalStageResult& e) {
  std::printf("%s: %d Gaussians (%d dynamic), L = %d\n",
              o.model_dir.c_str(), model.gaussians.size(),
              model.num_dynamic(), model.cycle_length);
  PrintHeldOutRows(e.held_out, scene.has_masks, e.training.stage1_far_scenery);
  PrintTrainingWaterPsnr(e.training);
  if (e.has_motion_gt) {
    std::printf("  motion vs truth       EPE %.4g (%.1f%% of mean speed "
                "%.4g, speed ratio %.2f) at %d points\n",
                e.motion.epe, 100 * e.motion.rel_epe, e.motion.mean_speed,
                e.motion.speed_ratio, e.motion.num_points);
    if (e.reference_motion) {
      std::printf("  reference V there     EPE %.4g (%.1f%%, speed ratio "
                  "%.2f): %s\n",
                  e.reference_motion->epe,
                  100 * e.reference_motion->rel_epe,
                  e.reference_motion->speed_ratio,
                  o.reference_motion.c_str());
    }
  } else {
    std::printf("  motion vs truth       n/a (%s)\n",
                model.motion ? "no gt/ in the scene" : "model has no V");
  }
  std::printf("  realism vs the input (ratios: 1 = like the input; "
              "distance: 0 = same statistics)\n");
  if (HasInputNoise(e.input_noise)) {
    std::printf("  (the input's noise, std %.4f %.4f %.4f per opponent "
                "channel, drawn onto the renders first)\n",
                e.input_noise[0], e.input_noise[1], e.input_noise[2]);
  }
  PrintRealismRow("  water", e.realism.water);
  PrintRealismRow("  static (control)", e.realism.static_region);
  PrintRealismRow("  whole frame", e.realism.frame);
  for (const auto& [name, r] : e.breakdown) {
    PrintRealismRow(("  water, " + name).c_str(), r.water);
  }
  std::printf("  loop seam             %.3f (boundary %.4g / within %.4g; "
              "~1 = seamless)\n",
              e.seam.score, e.seam.boundary_change, e.seam.within_change);
  std::printf("  ms per frame          Alg. 1 %.2f  Alg. 2 %.2f  (advect "
              "%.3f vs %.3f, render %.2f)\n",
              e.timing.alg1_frame_ms(), e.timing.alg2_frame_ms(),
              e.timing.alg1_advect_ms, e.timing.alg2_advect_ms,
              e.timing.render_ms);
}

}  // namespace es
