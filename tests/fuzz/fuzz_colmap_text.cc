// libFuzzer target: COLMAP's text model; the input is cameras.txt,
// images.txt and points3D.txt separated by "\n@@\n".
#include "core/io/colmap_io.h"
#include "core/base/input_error.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<std::string> parts = es::SplitFuzzInput(data, size, 3);
  const char* kNames[] = {"cameras.txt", "images.txt", "points3D.txt"};
  for (int i = 0; i < 3; ++i)
    es::WriteFuzzFile(kNames[i], parts[i].data(), parts[i].size());
  try {
    es::ReadColmapText(es::FuzzDir());
  } catch (const es::InputError&) {
  }
  return 0;
}
