#ifndef EULERSPLAT_SOLVERS_TRAIN_STATIC_STAGE_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_STATIC_STAGE_TRAINER_H_

#include "core/model/gaussians.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/train/stage_trainer_base.h"

namespace es {

struct IterationStats {
  int frame = -1;
  double loss = 0;  // weighted total
  double photometric = 0;
  double mask = 0;
  bool skipped = false;  // non-finite loss or gradient: no update
};

// What RunStaticStage (static_stage.h) drives: a Stage 1 trainer on the
// CPU (StaticTrainer) or on a CUDA device (cuda::DeviceStaticTrainer),
// which take the same steps and exchange the same checkpoints.
class StaticStageTrainer : public StageTrainer {
 public:
  // One iteration. A non-finite loss or gradient skips the update (counted
  // in skipped_steps()); throws TrainingDiverged after too many in a row or
  // if the parameters become non-finite.
  virtual IterationStats Step() = 0;

  // The current model (on a device trainer a download when it changed).
  virtual const GaussianSet& gaussians() const = 0;
  virtual double scene_extent() const = 0;

  virtual Checkpoint Save() const = 0;
  // Continues from a checkpoint of a run with the same frames and options.
  virtual void Restore(const Checkpoint& checkpoint) = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_STATIC_STAGE_TRAINER_H_
