#ifndef EULERSPLAT_SOLVERS_TRAIN_STAGE_TRAINER_BASE_H_
#define EULERSPLAT_SOLVERS_TRAIN_STAGE_TRAINER_BASE_H_

// What the Stage-1 and Stage-3 trainers, CPU and device, hold alike: their
// input (frames, training split, options, whether the mask term is on, the
// cameras' extent), the step count, the divergence guard and the blocks it
// bounds, with the accessors of these that their interfaces
// (StaticStageTrainer, JointStageTrainer) declare. Written once, so a
// field the four share is added in one place.

#include <cstdint>
#include <utility>
#include <vector>

#include "core/io/scene.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/splat_training.h"

namespace es {

template <class Interface, class Options>
class StageTrainerBase : public Interface {
 public:
  int64_t iteration() const override { return iteration_; }
  int64_t skipped_steps() const override { return guard_.skipped(); }
  bool last_step_ok() const override { return guard_.in_a_row() == 0; }
  bool uses_masks() const override { return use_masks_; }

 protected:
  // `stage` names the trainer in the guard's messages ("Stage 1
  // training", ...). The mask term is on when mask_weight > 0 and every
  // training frame has a mask.
  StageTrainerBase(const char* stage, const std::vector<Frame>* frames,
                   std::vector<int> train, const Options& options)
      : frames_(frames),
        train_(std::move(train)),
        options_(options),
        use_masks_(options.mask_weight > 0 && AllHaveMasks(*frames, train_)),
        extent_(CameraExtent(*frames, train_)),
        guard_(stage, options.max_nonfinite_steps) {}

  const std::vector<Frame>* frames_;
  std::vector<int> train_;
  Options options_;
  bool use_masks_ = false;
  double extent_ = 1;
  int64_t iteration_ = 0;
  DivergenceGuard guard_;
  std::vector<GuardedBlock> guarded_;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_STAGE_TRAINER_BASE_H_
