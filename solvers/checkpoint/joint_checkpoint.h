#ifndef EULERSPLAT_SOLVERS_CHECKPOINT_JOINT_CHECKPOINT_H_
#define EULERSPLAT_SOLVERS_CHECKPOINT_JOINT_CHECKPOINT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/frame_sampler.h"

namespace es {

// Everything a joint training run needs to continue exactly where it
// stopped. The Stage-1 Checkpoint has no place for the dynamic set, the
// loop start times or the fields, hence this second format.
struct JointCheckpoint {
  int64_t iteration = 0;
  GaussianSet gaussians;
  GaussianAdamState adam;
  std::vector<int> dynamic_index, start_times;
  // The field blocks after the splat blocks, in JointBlockLayout order (V
  // triplane, V MLP, D triplane, D MLP; the present ones), their Adam
  // moments, and the fields' boxes (6 values each, min xyz then max xyz,
  // V first).
  std::vector<std::vector<double>> field_params, field_m, field_v;
  std::vector<double> field_boxes;
  int64_t field_step = 0;
  FrameSampler::State sampler;
  std::string rng;  // the start-time RNG (std::mt19937_64 text form)
  // Frames per iteration (--batch_frames): a resume must draw the same.
  int32_t batch_frames = 1;
};

// Binary, written atomically (core/base/atomic_file.h).
void WriteJointCheckpoint(const JointCheckpoint& checkpoint,
                          const std::string& path);

// Throws InputError naming the file if it is missing, truncated,
// inconsistent or not a joint checkpoint of this version.
JointCheckpoint ReadJointCheckpoint(const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_CHECKPOINT_JOINT_CHECKPOINT_H_
