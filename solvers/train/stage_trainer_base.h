#ifndef EULERSPLAT_SOLVERS_TRAIN_STAGE_TRAINER_BASE_H_
#define EULERSPLAT_SOLVERS_TRAIN_STAGE_TRAINER_BASE_H_

// What the Stage-1 and Stage-3 trainers, CPU and device, share: the
// questions their interfaces answer alike (StageTrainer), and what they
// hold alike (StageTrainerBase): their input (frames, training split,
// options, whether the mask term is on, the cameras' extent), the step
// count, the divergence guard and the blocks it bounds, with the accessors
// of these. Written once, so a field the four share is added in one place.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/io/scene.h"
#include "core/render/rasterizer.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/splat_training.h"

namespace es {

// The part of the stage interfaces (StaticStageTrainer, JointStageTrainer)
// that does not depend on the stage: the drivers' progress, checkpoint and
// evaluation questions.
class StageTrainer {
 public:
  virtual ~StageTrainer() = default;

  virtual int64_t iteration() const = 0;
  virtual int64_t skipped_steps() const = 0;
  // False right after a skipped step: the state is not one to checkpoint.
  virtual bool last_step_ok() const = 0;
  virtual bool uses_masks() const = 0;
  // How the model is rendered for evaluation.
  virtual RenderOptions render_options() const = 0;

  // Bytes one step sends to sum over the ranks, on average (data-parallel
  // batches: the gradients' non-zero chunks; in one process all it would
  // sum), 0 for a one-frame step.
  virtual size_t allreduce_bytes() const { return 0; }
};

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
