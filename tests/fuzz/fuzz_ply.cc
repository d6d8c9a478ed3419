// libFuzzer target: the PLY reader (ascii and binary little-endian).
#include "core/base/input_error.h"
#include "core/io/ply_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = es::WriteFuzzFile(
      "in.ply", reinterpret_cast<const char*>(data), size);
  try {
    es::ReadPly(path);
  } catch (const es::InputError&) {
  }
  return 0;
}
