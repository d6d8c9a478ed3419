#ifndef EULERSPLAT_SOLVERS_PIPELINE_PIPELINE_OPTIONS_H_
#define EULERSPLAT_SOLVERS_PIPELINE_PIPELINE_OPTIONS_H_

#include <string>

#include "core/io/video_import.h"

namespace es {

// What one run of the whole pipeline is asked for: eulersplat's flags, one
// field each (their help text says more). -1 means "the preset's value".
struct PipelineOptions {
  std::string scene;  // a scene directory, or
  std::string video;  // a video file
  std::string out;    // the run's output folder
  // "" or "auto" (find the water), "none" (all static) or a mask folder.
  std::string masks;
  VideoImportOptions import;       // --video: fps, max_frames, max_width
  int mask_probe_iterations = -1;  // -1: half the preset's Stage 1
  // auto (chosen from the clip and the hardware: preset_choice.h), quick
  // or paper (preset.h)
  std::string preset = "auto";
  int static_iterations = -1;
  int flow_iterations = -1;
  int joint_iterations = -1;
  int cycle_length = 15;  // L, in frames
  double image_scale = -1;
  int animate_frames = -1;  // -1: 4 L
  double dynamic_threshold = 0.2;
  bool white_background = false;
  std::string static_dir;      // "": OUT/static
  std::string train_flags;     // extra es_train flags, space-separated
  bool animate = true;         // the videos and the contact sheet
  std::string device = "cpu";  // passed on as --device (device_stages.h)
  std::string pose_script;     // "": es_poses
  // Ranks of es_static and es_train (mpiexec), and their --batch_frames
  // (-1: one frame per rank).
  int ranks = 1;
  int batch_frames = -1;
  int threads = 1;             // CPU threads the stages use (--threads)
  bool profile = false;        // --profile on es_static and es_train
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_PIPELINE_OPTIONS_H_
