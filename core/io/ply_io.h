#ifndef EULERSPLAT_CORE_IO_PLY_IO_H_
#define EULERSPLAT_CORE_IO_PLY_IO_H_

#include <string>

#include "core/model/gaussians.h"

namespace es {

// The standard 3DGS PLY layout: x y z nx ny nz f_dc_0..2 f_rest_* opacity
// scale_0..2 rot_0..3 (float32), f_rest channel-major (all R coefficients,
// then G, then B), opacity as a logit, scale as a log, rotation w x y z.
// The SH degree is inferred from the number of f_rest properties. Unknown
// extra properties are ignored, except our own "dynamic_logit" (0 if absent).
// Reads binary little-endian and ascii; throws InputError naming the file for
// a missing property, a truncated file, or a NaN/Inf value, except opacity
// logits of +/-Inf (opacity 1 or 0, as @playcanvas/splat-transform writes
// them): those are clamped to +/-ln(9999) (opacity 0.9999 / 0.0001, which
// render as 1 and 0 do), with one warning naming the file and the count.
GaussianSet ReadPly(const std::string& path);

// Writes binary little-endian in the standard layout plus "dynamic_logit",
// atomically (core/base/atomic_file.h).
// Values round-trip bit-exactly through float32.
void WritePly(const GaussianSet& gaussians, const std::string& path);
// The bytes WritePly writes.
std::string EncodePly(const GaussianSet& gaussians);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_PLY_IO_H_
