// libFuzzer target: the PLY reader (ascii and binary little-endian).
#include "core/io/ply_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = es::WriteFuzzInput("in.ply", data, size);
  es::ReadAllowingRefusal([&] { es::ReadPly(path); });
  return 0;
}
