#ifndef EULERSPLAT_SOLVERS_EVAL_MOTION_GT_H_
#define EULERSPLAT_SOLVERS_EVAL_MOTION_GT_H_

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"

namespace es {

// A ground-truth velocity (world units per frame) at a world point.
using VelocityFunction = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

struct MotionGtMetrics {
  int num_points = 0;
  double epe = 0;         // mean |V(x) - v_gt(x)| (world units per frame)
  double mean_speed = 0;  // mean |v_gt(x)|
  double rel_epe = 0;     // epe / mean_speed
  // mean |V(x)| / mean_speed: below 1 the motion is under-estimated.
  double speed_ratio = 0;
};

// One point of the comparison: where it is, the model's velocity there and
// the truth's. Kept per point so that where the error lies can be seen
// (es_eval writes them to motion_gt.csv).
struct MotionGtPoint {
  Eigen::Vector3d x, model, truth;
};

// The field and the truth at each of `points`.
std::vector<MotionGtPoint> MotionGtPoints(
    const MotionField& field, const std::vector<Eigen::Vector3d>& points,
    const VelocityFunction& truth);
MotionGtMetrics SummarizeMotionGt(const std::vector<MotionGtPoint>& points);
// The points as CSV: x, y, z, model_vx.., true_vx.. (one row each).
std::string MotionGtCsv(const std::vector<MotionGtPoint>& points);

// Endpoint error of the field against the true velocity at `points` (the
// dynamic Gaussians' positions): where the model's water actually is.
MotionGtMetrics EvaluateMotionGt(const MotionField& field,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const VelocityFunction& truth);

// The same error for the lifted scene-flow samples themselves (sample v
// against the truth at sample x): what the pretraining is given.
MotionGtMetrics EvaluateSamplesGt(const std::vector<SceneFlowSample>& samples,
                                  const VelocityFunction& truth);

// Diagnosis ("what would a perfect optical flow give?"): each sample's
// velocity becomes the truth at its position, so the samples keep the
// flow's spatial coverage and lose its errors. kFull: all three components,
// seen in every direction (unseen = 0). kSeen: what a perfect 2D flow lifted
// as es_flowinit lifts it would give: the truth less its component along
// the sample's unseen line, which stays free; a sample without that line
// (unseen = 0) gets the whole truth.
enum class TruthPart { kFull, kSeen };
void ReplaceWithTruth(const VelocityFunction& truth, TruthPart part,
                      std::vector<SceneFlowSample>* samples);

// The synthetic scenes' ground truth, DIR/gt/velocity_grid.bin
// (core/io/velocity_grid.h), sampled trilinearly. HasMotionGt says
// whether the scene has it; LoadMotionGt throws InputError naming the file
// when it is missing or malformed.
bool HasMotionGt(const std::string& scene_dir);
VelocityFunction LoadMotionGt(const std::string& scene_dir);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_MOTION_GT_H_
