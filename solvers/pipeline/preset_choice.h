#ifndef EULERSPLAT_SOLVERS_PIPELINE_PRESET_CHOICE_H_
#define EULERSPLAT_SOLVERS_PIPELINE_PRESET_CHOICE_H_

// --preset auto: the preset that should finish within the run's target
// (the issue's: 10 minutes on two CPU cores, an hour on one GPU), chosen
// from the clip's size and the hardware by a small, explicit time model.

#include <string>

#include "solvers/pipeline/preset.h"

namespace es {

// What the run works on: the clip, and where it runs.
struct ClipSize {
  int frames = 0;
  int width = 0, height = 0;  // the widest camera
};
struct Hardware {
  int threads = 1;   // CPU threads the stages use (--threads, resolved)
  bool gpu = false;  // --device cuda: Stages 1-3 run on the GPU
};

// A run's wall time on an idle machine, predicted as work / speed-up:
//   work = P (k_static Is + k_joint Ij + k_frame (F + 2 A))
// with P the pixels of a training frame (after the preset's max_width),
// Is / Ij the Stage 1 / Stage 3 iterations, F the frames (optical flow,
// evaluation) and A the frames of each of the two animations (4 L); the
// k are single-thread seconds per pixel (docs/BENCHMARKS.md, "The preset
// that fits", has the command that measured them). The speed-up of T CPU
// threads is 1 + kExtraThreadGain (T - 1); on a GPU Stages 1 and 3 run at
// the GPU's measured rates instead.
struct TimeModel {
  double static_seconds;       // k_static, per pixel-iteration, CPU
  double joint_seconds;        // k_joint, per pixel-iteration, CPU
  double frame_seconds;        // k_frame, per pixel-frame, CPU
  double extra_thread_gain;    // speed-up of each thread beyond the first
  double gpu_static_seconds;   // per pixel-iteration, Stage 1 on the GPU
  double gpu_joint_seconds;    // per pixel-iteration, Stage 3 on the GPU
};
// The constants measured on this project's machines.
TimeModel MeasuredTimeModel();

// The predicted wall seconds of `preset` on `clip` (trained at at most
// preset.max_width px wide) with `hardware`.
double PredictSeconds(const TimeModel& model, const Preset& preset,
                      const ClipSize& clip, int cycle_length,
                      const Hardware& hardware);

struct PresetChoice {
  std::string name;           // "quick" or "paper"
  Preset preset;              // with max_width possibly reduced
  double predicted_seconds;   // by the time model
  std::string why;            // one line for the run's log
};

// The target the choice aims at, in seconds: 10 minutes on the CPU, an
// hour with a GPU (issue 45's targets).
double TargetSeconds(const Hardware& hardware);

// The presets with options' iteration overrides, predicted at
// options.cycle_length. With a GPU: paper when it fits the hour, else as
// on the CPU. On the
// CPU: quick at the widest of 320, 288, ..., 160 px whose prediction fits
// the target; quick at 160 px if none does (a slower run, said so).
// Narrower than 160 px the water's texture is lost; a clip at most 160 px
// wide is never scaled, so the README's run is exactly quick on any
// machine.
PresetChoice ChoosePreset(const ClipSize& clip,
                          const PipelineOptions& options,
                          const Hardware& hardware,
                          const TimeModel& model = MeasuredTimeModel());

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_PRESET_CHOICE_H_
