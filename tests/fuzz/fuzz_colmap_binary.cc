// libFuzzer target: COLMAP's binary model; the input is cameras.bin,
// images.bin and points3D.bin separated by "\n@@\n".
#include "core/io/colmap_io.h"
#include "core/base/input_error.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<std::string> parts = es::SplitFuzzInput(data, size, 3);
  const char* kNames[] = {"cameras.bin", "images.bin", "points3D.bin"};
  for (int i = 0; i < 3; ++i)
    es::WriteFuzzFile(kNames[i], parts[i].data(), parts[i].size());
  try {
    es::ReadColmapBinary(es::FuzzDir());
  } catch (const es::InputError&) {
  }
  return 0;
}
