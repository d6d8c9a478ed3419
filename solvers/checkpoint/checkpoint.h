#ifndef EULERSPLAT_SOLVERS_CHECKPOINT_CHECKPOINT_H_
#define EULERSPLAT_SOLVERS_CHECKPOINT_CHECKPOINT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/frame_sampler.h"

namespace es {

// Everything a static training run needs to continue exactly where it
// stopped.
struct Checkpoint {
  int64_t iteration = 0;
  GaussianSet gaussians;
  GaussianAdamState adam;
  FrameSampler::State sampler;
  std::string rng;  // the densification RNG (std::mt19937_64 text form)
  std::vector<double> grad_sum, grad_count, max_radius;  // DensityStats
  // Frames per iteration (--batch_frames): a resume must draw the same.
  int32_t batch_frames = 1;
};

// Writes a binary file atomically (core/base/atomic_file.h), so a run killed
// mid-write leaves the previous checkpoint intact.
void WriteCheckpoint(const Checkpoint& checkpoint, const std::string& path);

// Throws InputError naming the file if it is missing, truncated or not a
// checkpoint of this version.
Checkpoint ReadCheckpoint(const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_CHECKPOINT_CHECKPOINT_H_
