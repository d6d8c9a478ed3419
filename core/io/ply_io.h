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
// a missing property, a truncated file, or a NaN/Inf value.
GaussianSet ReadPly(const std::string& path);

// Writes binary little-endian in the standard layout plus "dynamic_logit",
// atomically (core/io/atomic_file.h).
// Values round-trip bit-exactly through float32.
void WritePly(const GaussianSet& gaussians, const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_PLY_IO_H_
