#include "solvers/pipeline/preset_choice.h"

#include <algorithm>
#include <cstdio>
#include <iterator>

namespace es {
namespace {

// The widths quick may train at, widest first; below 160 px the water's
// texture is lost (the README's scene, 160 px, is the narrowest the
// realism figures were measured at).
constexpr int kQuickWidths[] = {320, 288, 256, 224, 208, 192, 176, 160};

// Pixels of a training frame of `clip` scaled to at most `max_width`.
double TrainingPixels(const ClipSize& clip, int max_width) {
  if (max_width <= 0 || clip.width <= max_width)
    return static_cast<double>(clip.width) * clip.height;
  const double scale = static_cast<double>(max_width) / clip.width;
  return scale * clip.width * scale * clip.height;
}

std::string Minutes(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f min", seconds / 60);
  return text;
}

}  // namespace

TimeModel MeasuredTimeModel() {
  TimeModel m;
  // CPU, single-thread seconds per pixel (docs/BENCHMARKS.md, "The preset
  // that fits", has the commands). Stage 3: the README's run on an idle
  // 2-core machine, 174 s for 4000 iterations of 160x120 with 2 threads
  // (x 1.5, the 2-thread speed-up): 3.4e-6. The other stages, per
  // pixel-iteration or pixel-frame: from the CPU seconds of
  // benchmarks/profile_driver.sh on a 320x240, 120-frame clip relative to
  // Stage 3's when it cost 4.6e-6 (Stage 1 0.243 of it, its evaluations
  // included; the flow init, videos, export and evaluation 0.427 per
  // frame), measured under load, where only ratios of CPU seconds carry
  // over.
  m.joint_seconds = 3.4e-6;
  m.static_seconds = 0.243 * 4.6e-6;
  m.frame_seconds = 0.427 * 4.6e-6;
  // One thread to two: es_static 1.67x, es_train 1.41x (docs/BENCHMARKS.md,
  // "thread scaling").
  m.extra_thread_gain = 0.5;
  // One H200: Stage 1 at 243.6 it/s and Stage 3 at 25 it/s (the slow end
  // of 25-29) on 1168x880 frames (docs/BENCHMARKS.md, "GPU").
  m.gpu_static_seconds = 1.0 / (243.6 * 1168 * 880);
  m.gpu_joint_seconds = 1.0 / (25.0 * 1168 * 880);
  return m;
}

double PredictSeconds(const TimeModel& model, const Preset& preset,
                      const ClipSize& clip, int cycle_length,
                      const Hardware& hardware) {
  const double pixels = TrainingPixels(clip, preset.max_width);
  const double speedup =
      1.0 + model.extra_thread_gain * (std::max(hardware.threads, 1) - 1);
  const double frames = clip.frames + 2.0 * 4 * cycle_length;
  const double per_frame = pixels * model.frame_seconds * frames / speedup;
  if (hardware.gpu) {
    return per_frame +
           pixels * (model.gpu_static_seconds * preset.static_iterations +
                     model.gpu_joint_seconds * preset.joint_iterations);
  }
  return per_frame +
         pixels *
             (model.static_seconds * preset.static_iterations +
              model.joint_seconds * preset.joint_iterations) /
             speedup;
}

double TargetSeconds(const Hardware& hardware) {
  return hardware.gpu ? 3600 : 600;
}

PresetChoice ChoosePreset(const ClipSize& clip,
                          const PipelineOptions& options,
                          const Hardware& hardware, const TimeModel& model) {
  const int cycle_length = options.cycle_length;
  const double target = TargetSeconds(hardware);
  const std::string size = std::to_string(clip.frames) + " frames of " +
                           std::to_string(clip.width) + "x" +
                           std::to_string(clip.height);
  const std::string where =
      hardware.gpu ? "a GPU" : std::to_string(hardware.threads) + " thread(s)";
  if (hardware.gpu) {
    const Preset paper = WithOverrides(MakePreset("paper"), options);
    const double seconds =
        PredictSeconds(model, paper, clip, cycle_length, hardware);
    if (seconds <= target) {
      return {"paper", paper, seconds,
              "paper: " + size + " on " + where + " should take about " +
                  Minutes(seconds) + " (target " + Minutes(target) + ")"};
    }
  }
  const Preset full_quick = WithOverrides(MakePreset("quick"), options);
  Preset quick = full_quick;
  constexpr int kNarrowest = kQuickWidths[std::size(kQuickWidths) - 1];
  for (int width : kQuickWidths) {
    quick.max_width = width;
    const double seconds =
        PredictSeconds(model, quick, clip, cycle_length, hardware);
    // A clip no wider than the narrowest width always trains at full
    // size, with the preset exactly as it is.
    const bool last = width == kNarrowest || clip.width <= kNarrowest;
    if (seconds > target && !last) continue;
    std::string why = "quick";
    if (clip.width > width && width < kQuickWidths[0])
      why += " at " + std::to_string(width) + " px wide";
    why += ": " + size + " on " + where + " should take about " +
           Minutes(seconds) + " (target " + Minutes(target) + ")";
    if (seconds > target) why += "; no quick run is predicted to fit";
    if (clip.width <= kNarrowest) quick = full_quick;
    return {"quick", quick, seconds, why};
  }
  return {};  // not reached: the narrowest width returns
}

}  // namespace es
