#ifndef EULERSPLAT_SOLVERS_EVAL_TRAINING_WATER_PSNR_H_
#define EULERSPLAT_SOLVERS_EVAL_TRAINING_WATER_PSNR_H_

// Held-out water PSNR on the way to a looping model: the static model
// Stage 3 started from (Stage 1), Stage 3 at its first evaluation
// (iteration 0, before any step) and at its last, as es_train recorded
// them in the model directory. es_eval prints them side by side, so a
// drop that Stage 3 starts with or never wins back shows.

#include <cmath>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace es {

struct TrainingWaterPsnr {
  double stage1 = NAN;  // NaN: not recorded (a model from an older es_train)
  double first = NAN;
  int64_t first_iteration = -1;
  double last = NAN;
  int64_t last_iteration = -1;
  // Stage 1's held-out PSNR of the scenery far from the water
  // (LoopMetrics::psnr_far_scenery); NaN: not recorded.
  double stage1_far_scenery = NAN;
};

// Reads MODEL_DIR/metrics.json ("stage1_psnr_test_water",
// "stage1_psnr_test_far_scenery") and
// MODEL_DIR/history.csv (the first and last rows with a
// psnr_test_water); a missing file or key leaves its figures NaN. Throws
// InputError naming the file when one exists but does not parse.
TrainingWaterPsnr ReadTrainingWaterPsnr(const std::string& model_dir);

nlohmann::ordered_json TrainingWaterPsnrJson(const TrainingWaterPsnr& p);

// "  water PSNR, training    Stage 1 ... -> Stage 3 ... (iteration 0) ->
// ... dB (iteration N)", or nothing when none was recorded.
void PrintTrainingWaterPsnr(const TrainingWaterPsnr& p);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_TRAINING_WATER_PSNR_H_
