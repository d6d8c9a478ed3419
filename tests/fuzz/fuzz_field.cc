// libFuzzer target: the field files (motion_field.bin, residual_field.bin);
// the magic line at the start decides which reader can accept it, so both
// run on every input.
#include "core/fields/field_io.h"
#include "core/base/input_error.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = es::WriteFuzzFile(
      "field.bin", reinterpret_cast<const char*>(data), size);
  try {
    es::LoadMotionField(path);
  } catch (const es::InputError&) {
  }
  try {
    es::LoadResidualField(path);
  } catch (const es::InputError&) {
  }
  return 0;
}
