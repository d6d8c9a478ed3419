#ifndef EULERSPLAT_SOLVERS_POSES_POSE_ACCURACY_H_
#define EULERSPLAT_SOLVERS_POSES_POSE_ACCURACY_H_

#include "core/io/colmap_io.h"

namespace es {

// How close recovered poses are to known ones, up to the similarity
// (scale, rotation, translation) structure from motion cannot recover.
struct PoseAccuracy {
  int compared = 0;              // frames in both models (by image name)
  double position_rmse = 0;      // camera centres, in the truth's units
  double position_rmse_relative = 0;  // / the true trajectory's extent
  double mean_rotation_error_deg = 0;
  double max_rotation_error_deg = 0;
};

// Aligns `estimate` to `truth` with a similarity: the rotation from the
// cameras' orientations, then scale and translation from their centres
// (least squares); then compares centres and orientations. The extent is
// the largest distance of a true centre from their mean. Throws InputError
// when fewer than 3 frames are shared.
PoseAccuracy ComparePoses(const ColmapModel& estimate,
                          const ColmapModel& truth);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_POSES_POSE_ACCURACY_H_
