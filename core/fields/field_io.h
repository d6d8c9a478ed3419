#ifndef EULERSPLAT_CORE_FIELDS_FIELD_IO_H_
#define EULERSPLAT_CORE_FIELDS_FIELD_IO_H_

#include <string>

#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"

namespace es {

// Binary files of a trained field: a magic line ("eulersplat motion field
// v1\n" or "eulersplat residual field v1\n"), then little-endian records:
// the options (ints as int32, reals as float64, the plane combination as
// int32), the box (6 float64: min xyz, max xyz), then the triplane and MLP
// parameter counts (int64) each followed by that many float64.
// Writes go to a temporary file renamed into place, so a crash never leaves
// a half-written field. Reads throw InputError naming the file for a wrong
// magic, a truncated file, counts that disagree with the options, or a
// non-finite parameter.
void SaveMotionField(const MotionField& field, const std::string& path);
MotionField LoadMotionField(const std::string& path);

void SaveResidualField(const ResidualField& field, const std::string& path);
ResidualField LoadResidualField(const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_FIELD_IO_H_
