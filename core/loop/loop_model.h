#ifndef EULERSPLAT_CORE_LOOP_LOOP_MODEL_H_
#define EULERSPLAT_CORE_LOOP_LOOP_MODEL_H_

#include <optional>
#include <string>
#include <vector>

#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/model/gaussians.h"

namespace es {

// A trained looping 4D scene: canonical Gaussians, which of them are water
// (dynamic), their loop start times, the velocity field V and the residual
// field D. Static Gaussians are rendered as they are; dynamic Gaussian
// dynamic_index[k] starts its loop at frame start_times[k].
struct LoopModel {
  GaussianSet gaussians;          // canonical, static and dynamic
  std::vector<int> dynamic_index; // ascending indices into gaussians
  std::vector<int> start_times;   // one per dynamic Gaussian, in [0, L)
  int cycle_length = 15;          // L
  std::optional<MotionField> motion;     // absent: --no_motion_field
  std::optional<ResidualField> residual; // absent: --no_residual

  int num_dynamic() const { return static_cast<int>(dynamic_index.size()); }
};

// A looping model's shape without its parameter values: how many splats,
// which are dynamic, when their loops start, and the fields' structure.
// Costs get the values as Ceres parameter blocks and this for the rest; it
// points into a LoopModel (or other storage) that must outlive it. A null
// field pointer: the model has no such field.
struct LoopStructure {
  int count = 0;
  int sh_degree = 0;
  const std::vector<int>* dynamic_index = nullptr;  // ascending
  const std::vector<int>* start_times = nullptr;    // one per dynamic
  int cycle_length = 15;
  const MotionField* motion = nullptr;
  const ResidualField* residual = nullptr;

  int num_dynamic() const {
    return dynamic_index ? static_cast<int>(dynamic_index->size()) : 0;
  }
  static LoopStructure Of(const LoopModel& model);
};

// A model directory holds (each file written atomically):
//   canonical.ply        GaussianSet, standard 3DGS layout + dynamic_logit
//   loop.txt             "cycle_length L", "num_dynamic K", then K lines
//                        "<gaussian index> <start time>"
//   motion_field.bin     core/fields/field_io.h, if the model has V
//   residual_field.bin   core/fields/field_io.h, if the model has D
void SaveLoopModel(const LoopModel& model, const std::string& dir);
// Throws InputError naming the file for anything missing or inconsistent
// (indices out of range or not ascending, start times outside [0, L)).
LoopModel LoadLoopModel(const std::string& dir);

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_MODEL_H_
