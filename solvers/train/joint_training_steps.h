#ifndef EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINING_STEPS_H_
#define EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINING_STEPS_H_

// The host-side pieces of Stage 3 that the CPU trainer (JointTrainer) and
// the device trainer (cuda::DeviceJointTrainer) share, so both take the
// same steps: the loss terms, the schedules, the dynamic set's refresh,
// the water densification's ranking and edit, and the checkpoint's
// packing.

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "costs/joint_objective_options.h"
#include "costs/joint_render_cost.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/joint_stage_trainer.h"

namespace es {

// D's max_cycles for a video of `frames` frames: every cycle number a
// frame can have gets its own encoding.
int CyclesCovering(int frames, int cycle_length);

JointRenderTerms JointLossTerms(const JointTrainerOptions& o, bool use_masks);
RenderOptions JointRenderOptions(const JointTrainerOptions& o);
// The objective both trainers step on: each frame's fit (the mask term on
// with use_masks), the water losses (reading the masks with water_masks).
JointObjectiveOptions JointObjectiveOptionsOf(const JointTrainerOptions& o,
                                              bool use_masks,
                                              bool water_masks);
// Which of its terms are on (JointObjectiveOptions' tests).
bool WaterEnergyOn(const JointTrainerOptions& o);
bool WaterTextureOn(const JointTrainerOptions& o);
// Either loss on frame pairs is on: each step renders a neighbour too.
bool PairLossOn(const JointTrainerOptions& o);
// Any loss on the water's statistics is on (those read the water masks).
bool WaterLossOn(const JointTrainerOptions& o);
// The step at `iteration` (from 0) scores the loop's texture: the term is
// on and the iteration a multiple of loop_texture_interval.
bool LoopTextureDue(const JointTrainerOptions& o, int64_t iteration);
// The factor on the water losses at `iteration` (from 0): rises linearly
// from 0 to 1 over water_loss_warmup of the iterations, 1 after (and
// always 1 without a warm-up).
double WaterLossRamp(const JointTrainerOptions& o, int64_t iteration);
// The same for V's displacement over motion_warmup of the iterations.
double MotionRamp(const JointTrainerOptions& o, int64_t iteration);
// Sets the model's V to move at MotionRamp(o, iteration); both trainers
// call it whenever their iteration changes, so model() always shows the
// motion the next step trains.
void ApplyMotionRamp(const JointTrainerOptions& o, int64_t iteration,
                     LoopModel* model);

// For every training frame (by frame index), the training frame next to
// it in the video: the next one, else the previous one; -1 for none.
std::vector<int> TrainingNeighbours(const std::vector<Frame>& frames,
                                    const std::vector<int>& train);

// The model a trainer starts from: `initial` Gaussians, the dynamic set
// they give, V (the pretrained one with its box, or a new one over the
// dynamic Gaussians' box) and D over the same box, covering `num_frames`
// frames. Start times are drawn from `rng`.
LoopModel InitialLoopModel(const JointTrainerOptions& o, int num_frames,
                           GaussianSet initial,
                           std::optional<MotionField> motion,
                           std::mt19937_64* rng);

// Whether the dynamic set is re-derived before iteration `iteration`.
bool DynamicSetRefreshDue(const JointTrainerOptions& o, int64_t iteration);
// Makes `next` (ascending Gaussian indices) the dynamic set: the
// Gaussians that stay keep their start time, new ones draw theirs from
// `rng` (or 0 without random starts).
void FollowDynamicSet(const JointTrainerOptions& o, std::vector<int> next,
                      std::mt19937_64* rng, LoopModel* model);

// The fields' Adam rates at `iteration` (V's triplane and MLP, then D's;
// the present ones), decaying log-linearly over the run.
std::vector<double> FieldLearningRates(const JointTrainerOptions& o,
                                       int64_t iteration,
                                       const LoopModel& model);
// The fields' parameter arrays in the same order.
std::vector<std::vector<double>*> FieldParamBlocks(LoopModel* model);
// The blocks DivergenceGuard watches: the splat blocks
// (GuardedSplatBlocks), then the fields' in FieldParamBlocks' order, each
// bounded by its values in `model` (the one a trainer starts from).
std::vector<GuardedBlock> GuardedJointBlocks(const JointTrainerOptions& o,
                                             const LoopModel& model,
                                             double extent);

// Water densification after iteration `iteration` (counted from 1):
// whether it is due, and the training frames (indices into `frames`)
// whose gradients rank the water. Stateless (frames and draws follow from
// seed and iteration), so a resumed run densifies as the uninterrupted
// one.
bool WaterDensifyDue(const JointTrainerOptions& o, int64_t iteration,
                     int num_dynamic);
int WaterBudget(const JointTrainerOptions& o, int initial_dynamic);
std::vector<int> WaterDensifyViews(const JointTrainerOptions& o,
                                   const std::vector<int>& train,
                                   int64_t iteration);
// Densifies the top fraction of the water by `mean_grad` (one per dynamic
// Gaussian; non-finite counts as 0) within `budget` dynamic Gaussians.
WaterDensifyResult DensifyRankedWater(const JointTrainerOptions& o,
                                      std::vector<double> mean_grad,
                                      int budget, int64_t iteration,
                                      const std::vector<Frame>& frames,
                                      const std::vector<int>& train,
                                      LoopModel* model, GaussianAdam* adam);

// A checkpoint of `model` (its values current) and the trainer's state.
JointCheckpoint PackJointCheckpoint(
    const LoopModel& model, int64_t iteration, GaussianAdamState adam,
    std::vector<std::vector<double>> field_m,
    std::vector<std::vector<double>> field_v, int64_t field_step,
    FrameSampler::State sampler, const std::mt19937_64& rng);
// Checks that `c` fits `model`'s fields and SH degree (InputError naming
// `source` if not) and puts its Gaussians, dynamic set, field values and
// boxes into `model`; the caller restores its optimizer, sampler and RNG.
void UnpackJointCheckpoint(const JointCheckpoint& c, const std::string& source,
                           LoopModel* model);
// The sampler and start-time RNG of `c` (InputError naming `source`).
void RestoreSamplerAndRng(const JointCheckpoint& c, const std::string& source,
                          FrameSampler* sampler, std::mt19937_64* rng);

// `model` without the Gaussians that no frame of the video shows
// (PruneInvisible over every frame index, registered or not).
LoopModel FinalLoopModel(LoopModel model, const std::vector<Frame>& frames,
                         int* pruned);

// Below one 8-bit level of opacity a splat cannot change a pixel (the
// rasterizer skips alpha < 1/255).
constexpr double kInvisibleOpacity = 1.0 / 255.0;

// Removes the Gaussians whose opacity is below kInvisibleOpacity in every
// frame: static ones by their opacity, dynamic ones by their opacity with
// D's offset at each frame i in [0, max(num_frames, 2 L)) (every training
// frame, and every cycle index at cycle number 0, as the animation plays
// it). Dynamic indices are remapped, start times kept. Returns the count
// removed.
int PruneInvisible(int num_frames, LoopModel* model);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINING_STEPS_H_
