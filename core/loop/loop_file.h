#ifndef EULERSPLAT_CORE_LOOP_LOOP_FILE_H_
#define EULERSPLAT_CORE_LOOP_LOOP_FILE_H_

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "core/loop/loop_model.h"

namespace es {

// A looping model packed for playback (es_export --web; the web player
// reads it). The loop repeats every L frames, so it is fully described by
// the splats once plus, for the water (dynamic) splats only, what changes
// in each of the L frames. Little-endian:
//
//   offset  size  field
//   0       8     magic "ESLOOP1\0"
//   8       4     uint32 version (1)
//   12      4     uint32 N, all splats
//   16      4     uint32 W, water splats
//   20      4     uint32 L, frames in the loop
//   24      4     float32 frames per second
//   28      12    float32 background r g b, in [0, 1]
//   40      4     uint32 offset of the PLY (48)
//   44      4     uint32 size of the PLY in bytes
//   48            the splats of loop frame 0 as a standard binary 3DGS PLY
//                 (core/io/ply_io.h), water splats first (rows 0..W-1)
//   T             (T = 48 + PLY size rounded up to 4) float16[L][W][7]:
//                 for frame f, water splat k: position x y z, base color
//                 r g b (0.5 + C0 * SH DC, not clamped), opacity (not a
//                 logit)
//
// Everything the animation changes is in the table except D's offsets to
// the higher SH bands of water splats, which stay as at frame 0 (a viewer
// that applies only the table shows them for every frame). Half floats
// keep ~3 significant digits, as much as splat viewers keep on the GPU.
constexpr char kLoopFileMagic[8] = {'E', 'S', 'L', 'O', 'O', 'P', '1', '\0'};
constexpr int kLoopFileHeaderBytes = 48;
constexpr int kLoopFileValuesPerSplat = 7;

struct LoopFileOptions {
  double fps = 24;
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
};

// Writes the loop file of `model` to `path` (atomically); returns its size
// in bytes.
int64_t WriteLoopFile(const LoopModel& model, const LoopFileOptions& options,
                      const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_FILE_H_
