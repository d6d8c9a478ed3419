#ifndef EULERSPLAT_SYNTH_SPARSE_H_
#define EULERSPLAT_SYNTH_SPARSE_H_

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/io/colmap_io.h"
#include "core/model/camera.h"
#include "core/model/gaussians.h"

namespace es {

struct SynthSparseOptions {
  int num_points = 4000;
  double point_noise = 0.01;  // world units, std
  double pixel_noise = 0.3;   // pixels, std
  uint64_t seed = 1;
};

// The COLMAP model structure from motion would give for a synthetic scene:
// one PINHOLE camera, the exact poses, and points sampled on the scenery
// with small noise, each tracked in every frame where it is visible (it
// projects inside the image and the rendered depth there, `depths` as in
// SynthScene, agrees with its own: neither water nor rock hides it).
ColmapModel MakeSynthSparse(const std::vector<Camera>& cameras,
                            const GaussianSet& scenery,
                            const std::vector<cv::Mat>& depths,
                            const SynthSparseOptions& options);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_SPARSE_H_
