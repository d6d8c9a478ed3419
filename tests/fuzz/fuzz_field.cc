// libFuzzer target: the field files (motion_field.bin, residual_field.bin);
// the magic line at the start decides which reader can accept it, so both
// run on every input.
#include "core/fields/field_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = es::WriteFuzzInput("field.bin", data, size);
  es::ReadAllowingRefusal([&] { es::LoadMotionField(path); });
  es::ReadAllowingRefusal([&] { es::LoadResidualField(path); });
  return 0;
}
